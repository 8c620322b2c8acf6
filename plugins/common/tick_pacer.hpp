// Real-time pacing of a backend's ticks on CLOCK_MONOTONIC, on absolute deadlines: tick k is
// due at start + k·period, whatever happened to the ticks before it (no drift). wait() sleeps to
// the next deadline; a tick whose work ran past it begins at once and is late; after a stall of
// more than a period the schedule skips the periods already gone (the next tick is the one due
// now), so a stall is never followed by a burst of short catch-up ticks.
//
// A simulation in real time pauses the schedule for its own computing beyond a share of the
// period (pause()): a simulator that is momentarily slow falls behind the wall clock, as
// real-time simulators do, instead of making the controller look late.
//
// The first kSettlingTicks after start() set the schedule (cold caches, page faults, the first
// plan): a late one moves the schedule to now instead of counting, as a drive's start-up does.
#pragma once

#include <sys/resource.h>
#include <time.h>

#include <cerrno>
#include <cmath>
#include <cstdint>

#include "backend_abi.hpp"

namespace ballast::plugin {

inline timespec monotonicNow() {
  timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t;
}

/// What the calling thread has had of the CPU: its CPU time (s) and how often it gave the CPU up
/// by blocking (sleeping, waiting on a lock or IO). Wall time beyond the CPU time in a span
/// without such a switch is time the host kept the thread from running (preempted, or its
/// virtual CPU not scheduled).
struct ThreadRun {
  double cpu = 0.0;
  long voluntary_switches = 0;
};

inline ThreadRun threadRun() {
  ThreadRun r;
  timespec t;
  if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t) == 0)
    r.cpu = static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
  rusage usage;
  if (getrusage(RUSAGE_THREAD, &usage) == 0) r.voluntary_switches = usage.ru_nvcsw;
  return r;
}

/// b − a, s.
inline double secondsBetween(const timespec& a, const timespec& b) {
  return static_cast<double>(b.tv_sec - a.tv_sec) + 1e-9 * static_cast<double>(b.tv_nsec - a.tv_nsec);
}

inline void addSeconds(timespec& t, double seconds) {
  const long long ns = static_cast<long long>(t.tv_nsec) + std::llround(seconds * 1e9);
  t.tv_sec += static_cast<time_t>(ns / 1000000000LL);
  t.tv_nsec = static_cast<long>(ns % 1000000000LL);
  if (t.tv_nsec < 0) {
    t.tv_nsec += 1000000000L;
    --t.tv_sec;
  }
}

class TickPacer {
 public:
  static constexpr std::uint64_t kSettlingTicks = 10;

  /// The schedule starts now: the first deadline is one period away.
  void start(double period) {
    period_ = period;
    start_ = monotonicNow();
    ticks_ = 0;
    late_ = skipped_ = 0;
  }
  /// Sleeps until the next deadline (unless it has passed) and says how the tick went.
  backend::TickTiming wait() {
    backend::TickTiming timing;
    ++ticks_;
    timespec deadline = deadlineOf(ticks_);
    timespec now = monotonicNow();
    const double behind = secondsBetween(deadline, now);
    if (behind > 0.0) {
      if (ticks_ <= kSettlingTicks) {  // still setting the schedule: it starts again from now
        start_ = now;
        addSeconds(start_, -period_ * static_cast<double>(ticks_));
        return timing;
      }
      timing.late = true;
      timing.lateness = behind;
      ++late_;
      const auto skip = static_cast<std::uint64_t>(std::floor(behind / period_));
      timing.skipped = static_cast<std::uint32_t>(skip);
      skipped_ += skip;
      ticks_ += skip;
      return timing;
    }
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &deadline, nullptr) == EINTR) {
    }
    now = monotonicNow();
    timing.lateness = secondsBetween(deadline, now);  // the wake-up latency
    return timing;
  }
  /// Moves every deadline from now on later by `seconds`: time that is not the tick's, such as
  /// a simulator's own computing beyond its share of the period (its world waits meanwhile).
  void pause(double seconds) {
    if (seconds > 0.0) addSeconds(start_, seconds);
  }
  /// Ticks that could not sleep since start(), and periods skipped.
  std::uint64_t lateTicks() const { return late_; }
  std::uint64_t skippedPeriods() const { return skipped_; }

 private:
  timespec deadlineOf(std::uint64_t k) const {
    timespec d = start_;
    addSeconds(d, period_ * static_cast<double>(k));
    return d;
  }

  double period_ = 0.001;
  timespec start_{};
  std::uint64_t ticks_ = 0;  // deadlines handed out (including skipped ones)
  std::uint64_t late_ = 0, skipped_ = 0;
};

}  // namespace ballast::plugin
