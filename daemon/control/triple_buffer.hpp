// A single-writer/single-reader triple buffer: the writer fills a back slot and publishes it
// with one atomic exchange; the reader takes the newest published slot with another. Neither
// waits for the other and nothing is copied twice, which suits large values (a planner's
// trajectory) that a seqlock would copy on every read.
#pragma once

#include <atomic>
#include <cstdint>

namespace ballast::control {

template <typename T>
class TripleBuffer {
 public:
  /// Writer: the slot to fill, then publish().
  T& back() { return slots_[back_]; }
  void publish() {
    const std::uint32_t old = shared_.exchange(back_ | kFresh, std::memory_order_acq_rel);
    back_ = old & kIndex;
  }

  /// Reader: true if something newer than the last take() was published; front() is it.
  bool take() {
    if (!(shared_.load(std::memory_order_acquire) & kFresh)) return false;
    const std::uint32_t old = shared_.exchange(front_, std::memory_order_acq_rel);
    front_ = old & kIndex;
    return true;
  }
  const T& front() const { return slots_[front_]; }

 private:
  static constexpr std::uint32_t kIndex = 3, kFresh = 4;
  T slots_[3]{};
  std::uint32_t back_ = 0;                // writer's
  std::uint32_t front_ = 1;               // reader's
  std::atomic<std::uint32_t> shared_{2};  // the one in between, with the fresh bit
};

}  // namespace ballast::control
