// A single-writer sequence lock: the writer publishes a whole value without ever waiting;
// readers copy it and retry if a write overlapped their copy.
//
// The control loop publishes its status here every tick; the IO thread reads it whenever a
// client asks. A reader can never hold the writer up (there is nothing to hold), which is the
// point: no lock the IO side can take stands between the loop and its deadline.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstring>
#include <type_traits>

namespace ballast::control {

template <typename T>
class SeqLock {
  static_assert(std::is_trivially_copyable_v<T>, "published values are copied as plain bytes");

 public:
  /// Writer (one thread only).
  void store(const T& value) {
    const unsigned s = seq_.load(std::memory_order_relaxed);
    seq_.store(s + 1, std::memory_order_relaxed);  // odd: write in progress
    std::atomic_thread_fence(std::memory_order_release);
    copyIn(value);
    seq_.store(s + 2, std::memory_order_release);
  }

  /// Reader (any thread): a consistent copy. Spins only while a write is in progress.
  T load() const {
    T out;
    for (;;) {
      const unsigned before = seq_.load(std::memory_order_acquire);
      if (before & 1u) continue;
      copyOut(out);
      std::atomic_thread_fence(std::memory_order_acquire);
      if (seq_.load(std::memory_order_relaxed) == before) return out;
    }
  }

  /// Number of completed stores (readers can tell whether anything new was published).
  unsigned version() const { return seq_.load(std::memory_order_acquire) / 2; }

 private:
  // Byte-wise copies through relaxed atomics would be the pedantic form; a volatile-free memcpy
  // bracketed by the fences above is what every production seqlock does on x86-64 and AArch64.
  void copyIn(const T& value) { std::memcpy(static_cast<void*>(&value_), &value, sizeof(T)); }
  void copyOut(T& out) const { std::memcpy(static_cast<void*>(&out), &value_, sizeof(T)); }

  std::atomic<unsigned> seq_{0};
  T value_{};
};

}  // namespace ballast::control
