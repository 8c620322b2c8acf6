// Delays of the control host, injected into a simulated backend's ticks to test the daemon's
// deadline policy in real time: one stall at a given simulated time, and jitter (a delay on a
// random fraction of the ticks from a given time on). The delay happens inside advance(),
// before the pacing, as a slow tick's work would. Its random draws have their own generator, so
// turning it on changes no other noise of the simulation. A delay says how long it was asked to
// sleep and how long it took, so that the host keeping the thread asleep longer (a late wake-up)
// is told apart from the delay the test asked for.
#pragma once

#include <time.h>

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <random>

#include "tick_pacer.hpp"

namespace ballast::plugin {

/// The delays of one tick: the sleep asked for (s), the wall time it took (s), and the thread's
/// voluntary context switches in it (the sleep's own; they do not mean the tick's work blocked).
struct InjectedDelay {
  double requested = 0.0;
  double wall = 0.0;
  long voluntary_switches = 0;
};

class HostDelays {
 public:
  /// stall_at < 0: no stall; jitter_fraction 0: no jitter. Times are simulated, delays wall.
  void configure(double stall_at, double stall, double jitter_from, double jitter_fraction,
                 double jitter, std::uint64_t seed) {
    stall_at_ = stall_at;
    stall_ = stall;
    jitter_from_ = jitter_from;
    jitter_fraction_ = jitter_fraction;
    jitter_ = jitter;
    random_.seed(seed ^ 0x486f737444656c61ull);  // "HostDela"
    stalled_ = false;
  }
  /// Called once per tick at simulated time t; sleeps if a delay is due.
  InjectedDelay delay(double t) {
    InjectedDelay d;
    if (stall_at_ >= 0.0 && !stalled_ && t >= stall_at_) {
      stalled_ = true;
      d.requested += stall_;
    }
    if (jitter_fraction_ > 0.0 && t >= jitter_from_ && uniform_(random_) < jitter_fraction_)
      d.requested += jitter_;
    if (d.requested <= 0.0) return d;
    const timespec began = monotonicNow();
    const ThreadRun before = threadRun();
    sleep(d.requested);
    d.voluntary_switches = threadRun().voluntary_switches - before.voluntary_switches;
    d.wall = secondsBetween(began, monotonicNow());
    return d;
  }

 private:
  static void sleep(double seconds) {
    timespec ts{static_cast<time_t>(seconds),
                static_cast<long>((seconds - std::floor(seconds)) * 1e9)};
    while (clock_nanosleep(CLOCK_MONOTONIC, 0, &ts, &ts) == EINTR) {
    }
  }

  double stall_at_ = -1.0, stall_ = 0.0, jitter_from_ = 0.0, jitter_fraction_ = 0.0, jitter_ = 0.0;
  bool stalled_ = false;
  std::mt19937_64 random_;
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
};

}  // namespace ballast::plugin
