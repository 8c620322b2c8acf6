// TickTimingStats against exact statistics of the same samples: quantiles from a sorted copy,
// the late count of a sliding second, the ten-second window.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "control/tick_timing.hpp"

namespace ballast::control {
namespace {

backend::TickTiming sample(double lateness, bool late = false) {
  backend::TickTiming t;
  t.lateness = lateness;
  t.late = late;
  return t;
}

TEST(TickTimingStats, BinsAreFivePercentWideAndCoverMicrosecondsToMinutes) {
  for (double x : {1.2e-6, 3e-5, 1e-3, 0.05, 2.0, 60.0}) {
    const double v = TickTimingStats::binValue(TickTimingStats::bin(x));
    EXPECT_NEAR(v, x, 0.026 * x) << x;
  }
  EXPECT_EQ(TickTimingStats::bin(0.0), 0);
  EXPECT_EQ(TickTimingStats::bin(-1.0), 0);
  EXPECT_EQ(TickTimingStats::bin(1e9), TickTimingStats::kBins - 1);
}

TEST(TickTimingStats, QuantilesMatchTheSortedSamplesWithinTheBinWidth) {
  TickTimingStats stats(1000.0);
  std::mt19937 random(3);
  std::lognormal_distribution<double> latency(std::log(50e-6), 0.6);
  std::vector<double> all;
  for (int k = 0; k < 5000; ++k) {
    const double x = latency(random);
    all.push_back(x);
    stats.record(sample(x), 0.0004);
  }
  std::sort(all.begin(), all.end());
  const TimingSummary s = stats.summary();
  const double p50 = all[all.size() / 2], p99 = all[static_cast<std::size_t>(0.99 * all.size())];
  EXPECT_NEAR(s.lateness_p50, p50, 0.05 * p50);
  EXPECT_NEAR(s.lateness_p99, p99, 0.05 * p99);
  EXPECT_DOUBLE_EQ(s.lateness_max, all.back());
  EXPECT_DOUBLE_EQ(s.lateness_last, stats.summary().lateness_last);
  EXPECT_NEAR(s.window, 5.0, 1e-9);
  EXPECT_DOUBLE_EQ(s.work_max, 0.0004);
}

TEST(TickTimingStats, LateTicksAreCountedOverTheLastSecondAndInTotal) {
  TickTimingStats stats(100.0);  // a second is 100 ticks
  for (int k = 0; k < 100; ++k) stats.record(sample(1e-5, k < 30), 0.0);
  EXPECT_EQ(stats.lateInLastSecond(), 30u);
  EXPECT_EQ(stats.windowTicks(), 100u);
  for (int k = 0; k < 20; ++k) stats.record(sample(1e-5), 0.0);  // the first 20 late ones leave
  EXPECT_EQ(stats.lateInLastSecond(), 10u);
  EXPECT_EQ(stats.summary().late_ticks, 30u);
}

TEST(TickTimingStats, TheWindowForgetsAfterTenSeconds) {
  TickTimingStats stats(100.0);
  stats.record(sample(0.5, true), 0.0);  // a stall
  for (int k = 0; k < 500; ++k) stats.record(sample(1e-5), 0.0);
  EXPECT_DOUBLE_EQ(stats.summary().lateness_max, 0.5);
  for (int k = 0; k < 600; ++k) stats.record(sample(1e-5), 0.0);
  const TimingSummary s = stats.summary();
  EXPECT_LT(s.lateness_max, 1e-4);  // the stall's bucket has retired
  EXPECT_LE(s.window, 10.0 + 1e-9);
  EXPECT_EQ(s.late_ticks, 1u);  // the total remembers
}

}  // namespace
}  // namespace ballast::control
