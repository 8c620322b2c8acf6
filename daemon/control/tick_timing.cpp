#include "control/tick_timing.hpp"

#include <algorithm>
#include <cmath>

namespace ballast::control {

namespace {
constexpr double kGrowth = 1.05;
const double kLogGrowth = std::log(kGrowth);
}  // namespace

TickTimingStats::TickTimingStats(double rate)
    : ticks_per_bucket_(static_cast<std::uint32_t>(std::max(1.0, std::round(rate)))),
      period_(1.0 / rate),
      late_ring_(ticks_per_bucket_, 0) {}

int TickTimingStats::bin(double lateness) {
  const double us = lateness * 1e6;
  if (!(us >= 1.0)) return 0;  // also NaN and negative: the fastest bin
  const int i = 1 + static_cast<int>(std::log(us) / kLogGrowth);
  return std::min(i, kBins - 1);
}

double TickTimingStats::binValue(int bin) {
  if (bin <= 0) return 0.5e-6;
  return std::pow(kGrowth, bin - 0.5) * 1e-6;
}

void TickTimingStats::rollBucket() {
  current_ = (current_ + 1) % kBuckets;
  Bucket& b = buckets_[current_];
  for (int i = 0; i < kBins; ++i) total_[i] -= b.counts[i];
  b.counts.fill(0);
  b.ticks = 0;
  b.max = b.work_max = 0.0;
}

void TickTimingStats::record(const backend::TickTiming& timing, double work) {
  if (buckets_[current_].ticks >= ticks_per_bucket_) rollBucket();
  Bucket& b = buckets_[current_];
  const int i = bin(timing.lateness);
  ++b.counts[i];
  ++total_[i];
  ++b.ticks;
  b.max = std::max(b.max, timing.lateness);
  b.work_max = std::max(b.work_max, work);
  last_ = timing.lateness;
  work_last_ = work;
  skipped_ += timing.skipped;
  if (timing.host_stall > 0.0) {
    ++host_stalls_;
    host_stall_max_ = std::max(host_stall_max_, timing.host_stall);
  }

  std::uint8_t& slot = late_ring_[ring_next_];
  if (window_filled_ == late_ring_.size()) late_in_window_ -= slot;
  else ++window_filled_;
  slot = timing.late ? 1 : 0;
  late_in_window_ += slot;
  ring_next_ = (ring_next_ + 1) % static_cast<std::uint32_t>(late_ring_.size());
  if (timing.late) ++late_;
}

TimingSummary TickTimingStats::summary() const {
  TimingSummary s;
  s.lateness_last = last_;
  s.work_last = work_last_;
  s.late_ticks = late_;
  s.skipped_periods = skipped_;
  s.host_stalls = host_stalls_;
  s.host_stall_max = host_stall_max_;
  s.late_in_last_second = late_in_window_;
  std::uint64_t n = 0;
  for (const Bucket& b : buckets_) {
    n += b.ticks;
    s.lateness_max = std::max(s.lateness_max, b.max);
    s.work_max = std::max(s.work_max, b.work_max);
  }
  s.window = static_cast<double>(n) * period_;
  if (n == 0) return s;
  // The smallest bin whose cumulative count reaches the quantile's rank.
  const double ranks[2] = {0.5 * static_cast<double>(n), 0.99 * static_cast<double>(n)};
  double* out[2] = {&s.lateness_p50, &s.lateness_p99};
  std::uint64_t cumulative = 0;
  int q = 0;
  for (int i = 0; i < kBins && q < 2; ++i) {
    cumulative += total_[i];
    while (q < 2 && static_cast<double>(cumulative) >= ranks[q]) *out[q++] = binValue(i);
  }
  // A bin's centre can lie past the largest sample in it.
  s.lateness_p50 = std::min(s.lateness_p50, s.lateness_max);
  s.lateness_p99 = std::min(s.lateness_p99, s.lateness_max);
  return s;
}

}  // namespace ballast::control
