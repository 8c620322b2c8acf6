// A bounded single-producer/single-consumer ring of trivially copyable values, lock-free.
//
// One thread pushes, one thread pops; neither ever blocks or allocates after construction
// (the storage is sized once). This is how data crosses between a 1 kHz thread and the threads
// around it that do IO (in ballastd: operator commands in, replies, events and telemetry frames
// out; in a backend plugin: frames to a log writer): a full ring makes tryPush() return false,
// which the producer counts, so the real-time side never waits on IO. Shared by the daemon and
// the plugins, it depends on nothing but the standard library.
#pragma once

#include <atomic>
#include <cstddef>
#include <memory>
#include <type_traits>

namespace ballast {

template <typename T>
class SpscRing {
  static_assert(std::is_trivially_copyable_v<T>, "ring slots are copied as plain bytes");

 public:
  /// capacity is rounded up to a power of two.
  explicit SpscRing(std::size_t capacity) {
    std::size_t n = 2;
    while (n < capacity) n *= 2;
    mask_ = n - 1;
    slots_ = std::make_unique<T[]>(n);
  }

  std::size_t capacity() const { return mask_ + 1; }

  /// Producer: copies value in; false if the ring is full.
  bool tryPush(const T& value) {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_.load(std::memory_order_acquire) > mask_) return false;
    slots_[head & mask_] = value;
    head_.store(head + 1, std::memory_order_release);
    return true;
  }

  /// Consumer: copies the oldest value out; false if the ring is empty.
  bool tryPop(T& value) {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (tail == head_.load(std::memory_order_acquire)) return false;
    value = slots_[tail & mask_];
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }

  /// Either side: number of values waiting (a snapshot).
  std::size_t size() const {
    return head_.load(std::memory_order_acquire) - tail_.load(std::memory_order_acquire);
  }

 private:
  std::unique_ptr<T[]> slots_;
  std::size_t mask_ = 0;
  alignas(64) std::atomic<std::size_t> head_{0};  // written by the producer only
  alignas(64) std::atomic<std::size_t> tail_{0};  // written by the consumer only
};

}  // namespace ballast
