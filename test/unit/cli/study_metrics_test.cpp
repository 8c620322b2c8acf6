// ballast-study's metrics (cli/study_metrics.hpp) on made-up recordings whose RMS values are known
// in closed form: sinusoids of known amplitude over whole periods, a fall that cuts the window,
// truth preferred over the estimate, and a .blog written and read back.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "blog/blog.hpp"
#include "cli/study_metrics.hpp"

namespace ballast::cli {
namespace {

const std::vector<std::string> kColumns = {
    "t",        "mode",      "v_fwd",  "true_v_fwd", "z",        "true_z",   "roll",  "true_roll",
    "pitch",    "true_pitch", "yaw",   "true_yaw",   "cmd_vx",   "cmd_roll", "cmd_pitch",
    "limb_err", "mpc_ms",    "wbc_ms"};

/// 10 s at 1 kHz, walking (mode 3) at a commanded 1 m/s: the true velocity 1 + 0.2 sin(2π t),
/// height 0.8 + 0.01 sin, roll 0.05 sin, pitch 0.02 + 0.03 cos (its command 0.02), yaw 0.1 +
/// 0.04 sin (heading 0.1 at t = 0), limb error 0.1 constant; the estimate is off by 1 everywhere
/// (truth must win). fallAt >= 0: damped (mode 4) from then on.
Recording walking(double fallAt = -1.0) {
  Recording r;
  r.columns = kColumns;
  for (int i = 0; i < 10000; ++i) {
    const double t = i * 1e-3, s = std::sin(2 * M_PI * t), c = std::cos(2 * M_PI * t);
    const double mode = fallAt >= 0.0 && t >= fallAt ? 4 : 3;
    const double truth[] = {1.0 + 0.2 * s, 0.8 + 0.01 * s, 0.05 * s, 0.02 + 0.03 * c, 0.1 + 0.04 * s};
    r.values.insert(r.values.end(), {t, mode, truth[0] + 1, truth[0], truth[1] + 1, truth[1],
                                     truth[2] + 1, truth[2], truth[3] + 1, truth[3], truth[4] + 1,
                                     truth[4], 1.0, 0.0, 0.02, 0.1, 2.0 + (i % 2), 0.1});
  }
  return r;
}

TEST(StudyMetrics, RmsOverWholePeriodsIsTheAmplitudeOverRootTwo) {
  const Recording r = walking();
  RunMetrics m;
  std::string error;
  MetricsWindow w;
  w.begin = 2.0;
  w.end = 8.0;
  w.headingTime = 0.0;
  ASSERT_TRUE(computeMetrics(r, w, m, error)) << error;
  EXPECT_FALSE(m.fell);
  EXPECT_EQ(m.samples, 6000u);
  const double k = 1.0 / std::sqrt(2.0);
  EXPECT_NEAR(m.velocity, 0.2 * k, 1e-6);
  EXPECT_NEAR(m.height, 0.01 * k, 1e-8);
  EXPECT_NEAR(m.roll, 0.05 * k, 1e-7);
  EXPECT_NEAR(m.pitch, 0.03 * k, 1e-7);
  EXPECT_NEAR(m.yaw, 0.04 * k, 1e-7);
  EXPECT_NEAR(m.limb, 0.1, 1e-12);
  EXPECT_NEAR(m.mpcMs, 2.5, 1e-9);
  EXPECT_NEAR(m.wbcMs, 0.1, 1e-12);
}

TEST(StudyMetrics, AFallIsTheFirstDampedFrameAndEndsTheWindow) {
  const Recording r = walking(5.25);
  RunMetrics m;
  std::string error;
  MetricsWindow w{2.0, 8.0, 0.0};
  ASSERT_TRUE(computeMetrics(r, w, m, error)) << error;
  EXPECT_TRUE(m.fell);
  EXPECT_NEAR(m.fallTime, 5.25, 1e-12);
  EXPECT_EQ(m.samples, 3250u);  // 2.0 .. 5.249
  // A window that starts after the fall has no figures (NaN, not zeros)...
  ASSERT_TRUE(computeMetrics(r, MetricsWindow{6.0, 8.0, 0.0}, m, error)) << error;
  EXPECT_EQ(m.samples, 0u);
  EXPECT_TRUE(std::isnan(m.velocity) && std::isnan(m.yaw));
  EXPECT_NEAR(m.mpcMs, 2.5, 1e-9);  // solve times from the heading time to the fall
  // ... and one past the end of a recording without a fall is an error.
  EXPECT_FALSE(computeMetrics(walking(), MetricsWindow{12.0, 14.0, 0.0}, m, error));
  EXPECT_NE(error.find("no frame"), std::string::npos);
}

TEST(StudyMetrics, TheEstimateServesWithoutTruthAndMissingColumnsAreNamed) {
  Recording r = walking();
  for (std::size_t f = 0; f < r.frames(); ++f) r.values[f * r.columns.size() + r.column("true_v_fwd")] = NAN;
  RunMetrics m;
  std::string error;
  ASSERT_TRUE(computeMetrics(r, MetricsWindow{2.0, 8.0, 0.0}, m, error));
  EXPECT_NEAR(m.velocity, std::sqrt(1.0 + 0.02), 1e-6);  // the estimate: off by 1 m/s
  Recording bare;
  bare.columns = {"t", "mode"};
  bare.values = {0.0, 3.0};
  EXPECT_FALSE(computeMetrics(bare, MetricsWindow{}, m, error));
  EXPECT_NE(error.find("v_fwd"), std::string::npos);
}

TEST(StudyMetrics, ReadsABinaryRecording) {
  const Recording r = walking(7.0);
  blog::Header h;
  for (const std::string& c : r.columns)
    h.columns.push_back({c, "-", c == "t" ? blog::Type::kF64 : c == "mode" ? blog::Type::kU8 : blog::Type::kF32});
  const std::string path = ::testing::TempDir() + "study_metrics_test.blog";
  blog::Writer w;
  std::string error;
  ASSERT_TRUE(w.open(path, h, error)) << error;
  for (std::size_t f = 0; f < r.frames(); ++f) w.append(&r.values[f * r.columns.size()]);
  w.close();
  Recording back;
  ASSERT_TRUE(loadRecording(path, back, error)) << error;
  EXPECT_EQ(back.columns, r.columns);
  ASSERT_EQ(back.frames(), r.frames());
  RunMetrics a, b;
  ASSERT_TRUE(computeMetrics(r, MetricsWindow{2.0, 9.0, 0.0}, a, error));
  ASSERT_TRUE(computeMetrics(back, MetricsWindow{2.0, 9.0, 0.0}, b, error));
  EXPECT_EQ(b.fell, a.fell);
  EXPECT_DOUBLE_EQ(b.fallTime, a.fallTime);
  EXPECT_NEAR(b.velocity, a.velocity, 1e-6);  // f32 columns
  EXPECT_NEAR(b.height, a.height, 1e-6);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace ballast::cli
