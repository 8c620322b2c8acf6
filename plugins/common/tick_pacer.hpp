// Real-time pacing of a backend's ticks on CLOCK_MONOTONIC: advance() sleeps until the next
// deadline, one control period after the last; a tick that ends after its deadline is an
// overrun (reported, counted), and the schedule restarts from then instead of trying to catch
// up with a burst of short ticks.
#pragma once

#include <time.h>

#include <cerrno>
#include <cmath>
#include <cstdint>

namespace ballast::plugin {

inline timespec monotonicNow() {
  timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t;
}

/// b − a, s.
inline double secondsBetween(const timespec& a, const timespec& b) {
  return static_cast<double>(b.tv_sec - a.tv_sec) + 1e-9 * static_cast<double>(b.tv_nsec - a.tv_nsec);
}

inline void addSeconds(timespec& t, double seconds) {
  const long long ns = static_cast<long long>(t.tv_nsec) + std::llround(seconds * 1e9);
  t.tv_sec += static_cast<time_t>(ns / 1000000000LL);
  t.tv_nsec = static_cast<long>(ns % 1000000000LL);
}

class TickPacer {
 public:
  /// The schedule starts now: the first deadline is one period away.
  void start(double period) {
    period_ = period;
    deadline_ = monotonicNow();
  }
  /// Sleeps until the next deadline. False if the tick already ended after it; `late` says by
  /// how much (s).
  bool wait(double& late) {
    addSeconds(deadline_, period_);
    const timespec now = monotonicNow();
    late = secondsBetween(deadline_, now);
    if (late > 0.0) {
      ++overruns_;
      deadline_ = now;
      return false;
    }
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &deadline_, nullptr) == EINTR) {
    }
    return true;
  }
  std::uint64_t overruns() const { return overruns_; }

 private:
  double period_ = 0.001;
  timespec deadline_{};
  std::uint64_t overruns_ = 0;
};

}  // namespace ballast::plugin
