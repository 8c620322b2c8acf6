// gaitAtSpeed and fitSwing (gait/cadence.hpp) against hand-computed cases.
#include <gtest/gtest.h>

#include "gait/cadence.hpp"

namespace ballast::gait {
namespace {

Gait walking(double period, double doubleSupport) {
  Gait g;
  g.walking = true;
  g.period = period;
  g.doubleSupport = doubleSupport;
  g.toeOffLead = 0.0;
  return g;
}

// The mean speed of a swing foot: a stride v·T in ½(1 − ds)·T.
double swingSpeed(const Gait& g, double v) { return v * g.period / g.swingDuration(); }

TEST(Cadence, SlowWalkingKeepsTheProfilesGait) {
  // 1.2 m/s with T 0.8, ds 0.2: steps of 0.48 m, swing at 3.0 m/s; both within the limits.
  const Gait g = gaitAtSpeed(walking(0.8, 0.2), 1.2, 0.5, 3.3);
  EXPECT_EQ(g, walking(0.8, 0.2));
  EXPECT_EQ(gaitAtSpeed(walking(0.8, 0.2), 0.0, 0.5, 3.3), walking(0.8, 0.2));
  EXPECT_EQ(gaitAtSpeed(Gait{}, 1.5, 0.5, 3.3), Gait{});  // standing stays standing
}

TEST(Cadence, FasterWalkingShortensTheCycleToKeepTheStepsWithinReach) {
  // 1.5 m/s: T 0.8 would take steps of 0.6 m; 2·0.5/1.5 = 0.667 s takes them of 0.5 m. The
  // swing speed, 2·1.5/(1 − ds), needs no shorter double support under a 10 m/s limit.
  const Gait g = gaitAtSpeed(walking(0.8, 0.2), 1.5, 0.5, 10.0);
  EXPECT_NEAR(g.period, 2.0 * 0.5 / 1.5, 1e-12);
  EXPECT_NEAR(0.5 * 1.5 * g.period, 0.5, 1e-12);
  EXPECT_EQ(g.doubleSupport, 0.2);
}

TEST(Cadence, FasterWalkingShortensTheDoubleSupportToKeepTheSwingWithinItsSpeed) {
  // 1.5 m/s with ds 0.2: the swing foot at 2·1.5/0.8 = 3.75 m/s; at 3.3 m/s the double support
  // is 1 − 3/3.3 = 0.0909.
  const Gait g = gaitAtSpeed(walking(0.8, 0.2), 1.5, 0.0, 3.3);
  EXPECT_EQ(g.period, 0.8);  // no step limit
  EXPECT_NEAR(g.doubleSupport, 1.0 - 3.0 / 3.3, 1e-12);
  EXPECT_NEAR(swingSpeed(g, 1.5), 3.3, 1e-12);
  // Faster than the swing can go even with no double support: none, not a negative one.
  EXPECT_EQ(gaitAtSpeed(walking(0.8, 0.2), 2.0, 0.0, 3.3).doubleSupport, 0.0);
}

TEST(Cadence, BothLimitsTogether) {
  const Gait g = gaitAtSpeed(walking(0.8, 0.2), 1.5, 0.5, 3.3);
  EXPECT_NEAR(g.period, 0.6667, 1e-4);
  EXPECT_NEAR(g.doubleSupport, 0.0909, 1e-4);
  EXPECT_LE(swingSpeed(g, 1.5), 3.3 + 1e-12);
  EXPECT_LE(0.5 * 1.5 * g.period, 0.5 + 1e-12);
}

TEST(Cadence, ASwingIsFittedWithinItsSpeedByTheDoubleSupport) {
  // A 0.8 m swing in a 0.6 s cycle at 3.1 m/s takes 0.8/3.1 = 0.2581 s of the 0.3 s step: the
  // double support is 1 − 2·0.8/(0.6·3.1) = 0.13978 of the cycle.
  Gait g = walking(0.6, 0.2);
  EXPECT_TRUE(fitSwing(g, 0.8, 3.1));
  EXPECT_NEAR(g.doubleSupport, 1.0 - 1.6 / 1.86, 1e-12);
  EXPECT_NEAR(0.8 / g.swingDuration(), 3.1, 1e-12);
  EXPECT_EQ(g.period, 0.6);
  // A short swing keeps the gait's own double support; no limit keeps it whatever the swing.
  g = walking(0.6, 0.2);
  EXPECT_TRUE(fitSwing(g, 0.5, 3.1));  // 1 − 1/1.86 = 0.462 > 0.2
  EXPECT_EQ(g, walking(0.6, 0.2));
  EXPECT_TRUE(fitSwing(g, 5.0, 0.0));
  EXPECT_EQ(g, walking(0.6, 0.2));
  // 1.0 m in that cycle needs 0.323 s of swing, more than the 0.3 s step: none, and false.
  g = walking(0.6, 0.2);
  EXPECT_FALSE(fitSwing(g, 1.0, 3.1));
  EXPECT_EQ(g.doubleSupport, 0.0);
  // The walking gait's own case: gaitAtSpeed fits the stride v·T (1.5 m/s, T 0.8: 1.2 m).
  g = walking(0.8, 0.2);
  EXPECT_TRUE(fitSwing(g, 1.5 * 0.8, 3.3));
  EXPECT_NEAR(g.doubleSupport, gaitAtSpeed(walking(0.8, 0.2), 1.5, 0.0, 3.3).doubleSupport, 1e-12);
}

}  // namespace
}  // namespace ballast::gait
