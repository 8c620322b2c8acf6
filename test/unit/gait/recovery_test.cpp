// Standing recovery steps (issue 13): when a standing robot steps, with which foot, when it stops
// (gait/recovery.hpp), the right-first schedule a recovery to the right uses, and the footholds
// of a recovery step (step adjustment at zero velocity), against cases computed by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "gait/contact_schedule.hpp"
#include "gait/recovery.hpp"
#include "gait/step_adjustment.hpp"

namespace ballast::gait {
namespace {

constexpr double kRecoveryTol = 1e-9;

/// Feet 0.2 m apart, toes 0.1 m ahead of the ankles and heels 0.1 m behind: the support polygon
/// is the square [-0.1, 0.1]².
std::array<Eigen::Vector3d, kNumContacts> squareStance(double yaw = 0.0) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  std::array<Eigen::Vector3d, kNumContacts> p;
  const double local[kNumContacts][2] = {{0.1, 0.1}, {-0.1, 0.1}, {0.1, -0.1}, {-0.1, -0.1}};
  for (int i = 0; i < kNumContacts; ++i)
    p[i] = Eigen::Vector3d(c * local[i][0] - s * local[i][1], s * local[i][0] + c * local[i][1], 0.0);
  return p;
}

TEST(StandingRecovery, ThePointIsTheCapturePointPlusThePushsOffset) {
  // ω = 3.4, m = 50 kg: ċ = 0.34 m/s puts ξ 0.1 ahead of c, on the front edge; 20 N adds
  // 20 / (50 · 11.56) = 0.0346 m.
  const SupportCheck still = supportCheck(squareStance(), {0.0, 0.0}, {0.34, 0.0}, {0.0, 0.0}, 50.0, 3.4);
  EXPECT_NEAR(still.point.x(), 0.1, kRecoveryTol);
  EXPECT_NEAR(still.outside, 0.0, kRecoveryTol);
  const SupportCheck pushed =
      supportCheck(squareStance(), {0.0, 0.0}, {0.34, 0.0}, {20.0, 0.0}, 50.0, 3.4);
  EXPECT_NEAR(pushed.point.x(), 0.1 + 20.0 / (50.0 * 3.4 * 3.4), kRecoveryTol);
  EXPECT_NEAR(pushed.outside, 20.0 / (50.0 * 3.4 * 3.4), kRecoveryTol);
}

TEST(StandingRecovery, StepsOnlyBeyondTheMargin) {
  RecoveryParameters p;
  p.margin = 0.02;
  const auto stance = squareStance();
  // Outside by 0.0346: a step.
  EXPECT_TRUE(needsStep(supportCheck(stance, {0.0, 0.0}, {0.34, 0.0}, {20.0, 0.0}, 50.0, 3.4), p));
  // Outside by 0.01 (ξ at 0.11): no step yet.
  EXPECT_FALSE(needsStep(supportCheck(stance, {0.0, 0.0}, {0.374, 0.0}, {0.0, 0.0}, 50.0, 3.4), p));
  // A robot at rest leaning 0.03 m into a steady 20 N push: the point 0.0046 ahead of the middle.
  const SupportCheck leaning = supportCheck(stance, {-0.03, 0.0}, {0.0, 0.0}, {20.0, 0.0}, 50.0, 3.4);
  EXPECT_NEAR(leaning.outside, -(0.1 - (-0.03 + 20.0 / (50.0 * 3.4 * 3.4))), kRecoveryTol);
  EXPECT_FALSE(needsStep(leaning, p));
  // Sideways, off a corner: distance to the corner (0.1, 0.1) from (0.13, 0.14) is 0.05.
  EXPECT_TRUE(needsStep(supportCheck(stance, {0.13, 0.14}, {0.0, 0.0}, {0.0, 0.0}, 50.0, 3.4), p));
  EXPECT_NEAR(supportCheck(stance, {0.13, 0.14}, {0.0, 0.0}, {0.0, 0.0}, 50.0, 3.4).outside, 0.05,
              kRecoveryTol);
  p.enabled = false;
  EXPECT_FALSE(needsStep(supportCheck(stance, {0.13, 0.14}, {0.0, 0.0}, {0.0, 0.0}, 50.0, 3.4), p));
}

TEST(StandingRecovery, EndsInsideTheMarginAndSlow) {
  RecoveryParameters p;
  p.margin = 0.02;
  p.settleSpeed = 0.1;
  SupportCheck s;
  s.outside = -0.05;
  EXPECT_TRUE(recovered(s, 0.05, p));
  EXPECT_FALSE(recovered(s, 0.2, p));  // still moving
  s.outside = -0.01;
  EXPECT_FALSE(recovered(s, 0.05, p));  // too near the edge
}

TEST(StandingRecovery, TheFootOnTheSideThePointLeftToStepsFirst) {
  EXPECT_TRUE(leftFootFirst({0.0, 0.15}, squareStance(), 0.0));
  EXPECT_FALSE(leftFootFirst({0.0, -0.15}, squareStance(), 0.0));
  // Facing +y (yaw π/2), +x in the world is the robot's right.
  EXPECT_FALSE(leftFootFirst({0.15, 0.0}, squareStance(M_PI / 2), M_PI / 2));
  EXPECT_TRUE(leftFootFirst({-0.15, 0.0}, squareStance(M_PI / 2), M_PI / 2));
}

TEST(StandingRecovery, RightFirstSwingsTheRightFootFirst) {
  // Period 0.8, double support 0.2: each cycle begins with 0.08 s of double support, then the
  // first foot swings 0.32 s; right first, the right foot swings [1.08, 1.40], the left
  // [1.48, 1.80].
  Gait g{true, 0.8, 0.2, 0.0};
  g.rightFirst = true;
  ContactSchedule s(Gait{}, 0.0);
  EXPECT_DOUBLE_EQ(s.setGait(g, 1.0), 1.0);
  SwingInterval right, left;
  ASSERT_TRUE(s.swingAround(kRightToe, 1.0, 3.0, right));
  ASSERT_TRUE(s.swingAround(kLeftToe, 1.0, 3.0, left));
  EXPECT_NEAR(right.liftOff, 1.08, kRecoveryTol);
  EXPECT_NEAR(right.touchDown, 1.40, kRecoveryTol);
  EXPECT_NEAR(left.liftOff, 1.48, kRecoveryTol);
  EXPECT_NEAR(left.touchDown, 1.80, kRecoveryTol);
  EXPECT_FALSE(g == Gait({true, 0.8, 0.2, 0.0}));  // a different gait: the schedule tells them apart
}

/// A recovery step: zero commanded velocity, no double support, e^{ωT} = 2, feet 0.2 apart at
/// x = 0, the left foot lifting now and landing after T.
CaptureStepInput standingStep(const Eigen::Vector2d& capturePoint) {
  CaptureStepInput in;
  in.stepTime = 0.4;
  in.omega = std::log(2.0) / in.stepTime;
  in.doubleSupportTime = 0.0;
  in.width = 0.2;
  in.leftFoot = {0.0, 0.1};
  in.rightFoot = {0.0, -0.1};
  in.capturePoint = capturePoint;
  return in;
}

TEST(StandingRecovery, TheStepLandsWhereTheCapturePointWillBeLessTheStandingOffset) {
  // Stepping in place, b_L = (0, −W/(e+1)) = (0, −0.2/3). ξ = (0.1, 0) pushed forward:
  // ξ_td = 2 ξ − p_R = (0.2, 0.1); foothold ξ_td − b_L = (0.2, 0.1667).
  const CaptureStepInput in = standingStep({0.1, 0.0});
  Step step;
  step.left = true;
  step.touchDown = 0.4;
  captureFootholds(in, &step, 1);
  EXPECT_NEAR(step.capturePoint.x(), 0.2, 1e-6);
  EXPECT_NEAR(step.capturePoint.y(), 0.1, 1e-6);
  EXPECT_NEAR(step.foothold.x(), 0.2, 1e-6);
  EXPECT_NEAR(step.foothold.y(), 0.1 + 0.2 / 3.0, 1e-6);
  EXPECT_FALSE(step.limited);
}

TEST(StandingRecovery, ASidewaysStepIsHeldToTheWidestStep) {
  // ξ = (0, 0.3) pushed left: ξ_td = 2 ξ − p_R = (0, 0.7), the target 0.8667 left of the right
  // foot; the widest step (0.45) puts the foot at (0, 0.35).
  const CaptureStepInput in = standingStep({0.0, 0.3});
  Step step;
  step.left = true;
  step.touchDown = 0.4;
  captureFootholds(in, &step, 1);
  EXPECT_NEAR(step.foothold.x(), 0.0, 1e-6);
  EXPECT_NEAR(step.foothold.y(), -0.1 + 0.45, 1e-6);
  EXPECT_TRUE(step.limited);
}

// Step timing (recoveryPeriod): ω = 3, the walking period 0.8 s, the shortest 0.4 s, the default
// reach (0.5 ahead, 0.35 behind, 0.45 wide). The stance foot's toe at x 0.1, heel at -0.1.
constexpr double kOmega = 3.0, kWalk = 0.8, kShortest = 0.4;

TEST(StandingRecovery, ASidewaysStepIsQuickerTheFartherThePointIsOut) {
  // The right foot stands (toe (0.1, -0.1), heel (-0.1, -0.1)), the left steps. ξ + d = (0, 0.1):
  // p = (0, -0.1), ξ + d runs away along +y from 0.2 to the widest step 0.45 in e^{ωt} = 2.25:
  // the step lands at t = ln 2.25 / 3 = 0.27031 s, half the period: 0.54062 s.
  const Eigen::Vector2d toe(0.1, -0.1), heel(-0.1, -0.1);
  const double expected = 2.0 * std::log(2.25) / kOmega;
  EXPECT_NEAR(expected, 0.54062, 1e-5);
  EXPECT_NEAR(
      recoveryPeriod({0.0, 0.1}, toe, heel, 0.0, true, StepLimits{}, kOmega, kWalk, kShortest),
      expected, kRecoveryTol);
  // Heading along +y (the same feet and point turned by 90 degrees): the same period.
  EXPECT_NEAR(recoveryPeriod({-0.1, 0.0}, {0.1, 0.1}, {0.1, -0.1}, M_PI / 2, true, StepLimits{},
                             kOmega, kWalk, kShortest),
              expected, kRecoveryTol);
  // Already beyond the widest step at 0.6 from p (reach 0.45/0.6 < 1): the shortest.
  EXPECT_NEAR(
      recoveryPeriod({0.0, 0.5}, toe, heel, 0.0, true, StepLimits{}, kOmega, kWalk, kShortest),
      kShortest, kRecoveryTol);
  // 0.05 out: e^{ωt} = 9, 2 ln 9 / 3 = 1.46 s, longer than walking: the walking period.
  EXPECT_NEAR(
      recoveryPeriod({0.0, -0.05}, toe, heel, 0.0, true, StepLimits{}, kOmega, kWalk, kShortest),
      kWalk, kRecoveryTol);
  // On the toe-heel line nothing runs away: the walking period. A shortest period above it: that.
  EXPECT_NEAR(
      recoveryPeriod({0.05, -0.1}, toe, heel, 0.0, true, StepLimits{}, kOmega, kWalk, kShortest),
      kWalk, kRecoveryTol);
  EXPECT_NEAR(recoveryPeriod({0.0, 0.5}, toe, heel, 0.0, true, StepLimits{}, kOmega, kWalk, 1.0),
              kWalk, kRecoveryTol);
}

TEST(StandingRecovery, AStepBackTakesItsTimeFromTheHeel) {
  // The left foot stands (toe (0.1, 0.1), heel (-0.1, 0.1)), the right steps. ξ + d = (-0.2, 0):
  // p = the heel, 0.1 behind the foot's middle; ξ + d runs away along (-0.1, -0.1): behind, from
  // -0.1 to -0.35 in e^{ωt} = 2.5; sideways (the right foot's side) 0.45 / 0.1 = 4.5, later.
  // Period 2 ln 2.5 / 3 = 0.61086 s.
  const double expected = 2.0 * std::log(2.5) / kOmega;
  EXPECT_NEAR(expected, 0.61086, 1e-5);
  EXPECT_NEAR(recoveryPeriod({-0.2, 0.0}, {0.1, 0.1}, {-0.1, 0.1}, 0.0, false, StepLimits{}, kOmega,
                             kWalk, kShortest),
              expected, kRecoveryTol);
}

TEST(WalkingPush, ThePapersFootholdsKeepTheSideOfAPushAlongTheWalk) {
  const Eigen::Vector2d walking(0.0, 1.0);  // walking along +y (world) at 1 m/s
  const auto pushAxis = [&](const Eigen::Vector2d& push) { return walkingPushAxis(push, walking); };
  // Along the walk: the push's axis, and across it the paper's footholds.
  EXPECT_LT((pushAxis({0.0, 60.0}).axis - Eigen::Vector2d(0.0, 1.0)).norm(), 1e-12);
  EXPECT_NEAR(pushAxis({0.0, 60.0}).paperAcross, 1.0, 1e-12);
  // 30° off it: cos 60° = 0.5, whatever the push's size; the axis is the push's.
  const Eigen::Vector2d off30(std::sin(M_PI / 6.0), std::cos(M_PI / 6.0));
  EXPECT_NEAR(pushAxis(40.0 * off30).paperAcross, 0.5, 1e-12);
  EXPECT_NEAR(pushAxis(Eigen::Vector2d(-off30.x(), off30.y())).paperAcross, 0.5,
              1e-12);  // other side
  EXPECT_LT((pushAxis(40.0 * off30).axis - off30).norm(), 1e-12);
  // 45° or more off it, across it, against it, standing, no push: the capture point's both ways.
  EXPECT_NEAR(pushAxis({40.0, 40.0}).paperAcross, 0.0, 1e-12);
  EXPECT_EQ(pushAxis({60.0, 10.0}).paperAcross, 0.0);
  EXPECT_EQ(pushAxis({0.0, -60.0}).paperAcross, 0.0);
  EXPECT_EQ(walkingPushAxis({0.0, 60.0}, Eigen::Vector2d::Zero()).paperAcross, 0.0);
  EXPECT_EQ(pushAxis(Eigen::Vector2d::Zero()).paperAcross, 0.0);
}

}  // namespace
}  // namespace ballast::gait
