// How the control loop keeps its real-time schedule: per tick the lateness the backend reports
// (backend::TickTiming: how long after its deadline the tick began), whether it was late (its
// predecessor ran past the deadline), the periods skipped after a stall, and how long the tick's
// own work took. Kept as:
//   - totals since start (late ticks, skipped periods);
//   - the late ticks among the last `window_ticks` (one second at the control rate): the
//     deadline policy's late fraction;
//   - a histogram of lateness over the last ten such windows, for p50/p99/max in `status`:
//     log-spaced bins 5 % wide from 1 µs to 100 s, in ten one-second buckets that retire in turn.
// Sized at construction; record() and summary() allocate nothing (the 1 kHz path).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "backend_abi.hpp"

namespace ballast::control {

/// What status reports under `timing` (seconds; see TickTimingStats).
struct TimingSummary {
  double lateness_last = 0.0;   ///< of the tick that began last
  double lateness_p50 = 0.0;    ///< over the window (±2.5 %: the histogram's resolution)
  double lateness_p99 = 0.0;
  double lateness_max = 0.0;    ///< exact
  double window = 0.0;          ///< s of ticks the figures cover (up to 10 s)
  double work_last = 0.0;       ///< the last tick's work: the loop's and the backend's before it slept
  double work_max = 0.0;        ///< the longest over the window
  std::uint64_t late_ticks = 0;       ///< since start
  std::uint64_t skipped_periods = 0;  ///< since start
  /// Ticks since start in which a simulation's world waited for its host, which did not run the
  /// control thread although it was ready (TickTiming::host_stall), and the longest wait (s).
  std::uint64_t host_stalls = 0;
  double host_stall_max = 0.0;
  std::uint32_t late_in_last_second = 0;
};

class TickTimingStats {
 public:
  static constexpr int kBuckets = 10;

  /// rate: control rate (Hz): one bucket holds a second of ticks.
  explicit TickTimingStats(double rate);

  /// One tick: the timing its advance() reported and how long its work took (s).
  void record(const backend::TickTiming& timing, double work);
  /// Late ticks among the last second's (fewer while the first second fills).
  std::uint32_t lateInLastSecond() const { return late_in_window_; }
  /// Ticks the late window holds (a second's worth once full).
  std::uint32_t windowTicks() const { return window_filled_; }
  TimingSummary summary() const;

  /// The histogram bin of a lateness (s) and a representative value of a bin (its geometric
  /// centre), exposed for tests.
  static int bin(double lateness);
  static double binValue(int bin);
  static constexpr int kBins = 520;  // 1.05^518 µs ≈ 100 s

 private:
  struct Bucket {
    std::array<std::uint32_t, kBins> counts{};
    std::uint32_t ticks = 0;
    double max = 0.0, work_max = 0.0;
  };
  void rollBucket();

  std::uint32_t ticks_per_bucket_;
  double period_;
  std::array<Bucket, kBuckets> buckets_;
  std::array<std::uint32_t, kBins> total_{};  // the sum of the buckets
  int current_ = 0;
  std::vector<std::uint8_t> late_ring_;  // the last second's ticks: 1 = late
  std::uint32_t ring_next_ = 0, window_filled_ = 0, late_in_window_ = 0;
  double last_ = 0.0, work_last_ = 0.0;
  std::uint64_t late_ = 0, skipped_ = 0, host_stalls_ = 0;
  double host_stall_max_ = 0.0;
};

}  // namespace ballast::control
