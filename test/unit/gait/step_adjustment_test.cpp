// Step adjustment (issue 13): the capture point's arithmetic (gait/capture_point.hpp) and the
// footholds chosen from it (gait/step_adjustment.hpp) against cases computed by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "gait/capture_point.hpp"
#include "gait/step_adjustment.hpp"

namespace ballast::gait {
namespace {

constexpr double kTol = 1e-9;

void expectNear(const Eigen::Vector2d& a, double x, double y, double tol = 1e-6) {
  EXPECT_NEAR(a.x(), x, tol);
  EXPECT_NEAR(a.y(), y, tol);
}

TEST(CapturePoint, IsTheComPlusItsVelocityOverOmega) {
  // ξ = c + ċ/ω: (0.1, 0) + (0.35, −0.7)/3.5.
  expectNear(capturePoint({0.1, 0.0}, {0.35, -0.7}, 3.5), 0.2, -0.2, kTol);
  EXPECT_NEAR(pendulumFrequency(0.981, 9.81), std::sqrt(10.0), kTol);
}

TEST(CapturePoint, ForceOffsetIsForceOverMassOmegaSquared) {
  // 60 N on 60 kg with ω² = 12.25: 1/12.25 m.
  expectNear(forceOffset({60.0, -30.0}, 60.0, 3.5), 1.0 / 12.25, -0.5 / 12.25, kTol);
}

TEST(CapturePoint, DivergesFromAHeldCentreOfPressure) {
  // ω Δt = 1: ξ − p grows by e; with d = 0.05 it grows about p − d.
  expectNear(predictCapturePoint({0.1, 0.0}, {0.0, 0.0}, 2.0, 0.5), 0.1 * std::exp(1.0), 0.0);
  expectNear(predictCapturePoint({0.1, 0.0}, {0.0, 0.0}, 2.0, 0.5, {0.05, 0.0}),
             -0.05 + 0.15 * std::exp(1.0), 0.0);
  // ξ at p − d stays (the robot leaning into the push).
  expectNear(predictCapturePoint({-0.05, 0.2}, {0.0, 0.2}, 3.0, 0.7, {0.05, 0.0}), -0.05, 0.2);
}

TEST(CapturePoint, RampWeightIsTheIntegralOfTheLinearTransfer) {
  // ω = 1, ramp = dt = 1: α = ∫₀¹ e^{1−s}(1 − s) ds = ∫₀¹ u e^u du = 1.
  EXPECT_NEAR(rampWeight(1.0, 1.0, 1.0), 1.0, 1e-12);
  EXPECT_NEAR(rampWeight(3.0, 0.0, 0.4), 0.0, 1e-12);
  // A ramp over the whole interval from p_a to p_b: the same as a numerical integral of
  // ξ̇ = ω (ξ − p(t)).
  const double w = 3.3, T = 0.4, Tr = 0.1;
  Eigen::Vector2d xi(0.3, 0.1), pa(0.0, 0.1), pb(0.2, -0.1);
  Eigen::Vector2d x = xi;
  const int n = 400000;
  for (int k = 0; k < n; ++k) {
    const double t = (k + 0.5) * T / n;
    const Eigen::Vector2d p = t < Tr ? Eigen::Vector2d(pa + (pb - pa) * (t / Tr)) : pb;
    x += T / n * w * (x - p);
  }
  const Eigen::Vector2d predicted = predictCapturePoint(xi, pa, pb, w, Tr, T);
  EXPECT_NEAR(predicted.x(), x.x(), 1e-5);
  EXPECT_NEAR(predicted.y(), x.y(), 1e-5);
}

TEST(CapturePoint, PeriodicOffsetsOfForwardWalking) {
  // e^{ωT} = 2, no double support, steps (L, ±W) = (0.2, ±0.2): b = (L/(e−1), ∓W/(e+1)).
  const double T = 0.4, w = std::log(2.0) / T;
  const PeriodicOffsets b = periodicOffsets({0.2, 0.2}, {0.2, -0.2}, w, T);
  expectNear(b.left, 0.2, -0.2 / 3.0);
  expectNear(b.right, 0.2, 0.2 / 3.0);
}

TEST(CapturePoint, SignedDistanceToTheSupportPolygon) {
  Eigen::Matrix<double, 2, 4> square;
  square << 1, 0, 1, 0,  // deliberately not in hull order
      1, 0, 0, 1;
  EXPECT_NEAR(signedDistanceToHull<4>(square, {0.5, 0.25}), -0.25, kTol);
  EXPECT_NEAR(signedDistanceToHull<4>(square, {2.0, 0.5}), 1.0, kTol);
  EXPECT_NEAR(signedDistanceToHull<4>(square, {2.0, 2.0}), std::sqrt(2.0), kTol);
}

TEST(StepLimits, ClampForwardBackwardAndWidthInTheHeadingFrame) {
  const StepLimits limits;  // 0.5 ahead, 0.35 behind, 0.12 to 0.45 sideways
  expectNear(limitStep({0.8, 0.05}, {0.0, 0.0}, 0.0, true, limits), 0.5, 0.12, kTol);
  expectNear(limitStep({-0.5, -0.6}, {0.0, 0.0}, 0.0, false, limits), -0.35, -0.45, kTol);
  // A left foot may not cross to the right of the stance foot.
  expectNear(limitStep({0.1, -0.3}, {0.0, 0.0}, 0.0, true, limits), 0.1, 0.12, kTol);
  // Heading 90°: forward is +y, left is −x. 0.8 forward and 0.05 left: (−0.12, 0.5).
  expectNear(limitStep({1.0 - 0.05, 2.0 + 0.8}, {1.0, 2.0}, M_PI / 2, true, limits), 1.0 - 0.12,
             2.5, kTol);
  // Within reach: unchanged.
  expectNear(limitStep({0.2, 0.3}, {0.0, 0.1}, 0.0, true, limits), 0.2, 0.3, kTol);
}

/// The right foot has just landed at (0, −0.1), the left at (−0.2, 0.1) lifts now and lands in
/// 0.4 s; e^{ωT} = 2, no double support, 0.5 m/s: on the periodic orbit ξ = p_R + b_R.
CaptureStepInput onTheOrbit() {
  CaptureStepInput in;
  in.stepTime = 0.4;
  in.doubleSupportTime = 0.0;
  in.omega = std::log(2.0) / in.stepTime;
  in.velocity = {0.5, 0.0};
  in.width = 0.2;
  in.leftFoot = {-0.2, 0.1};
  in.rightFoot = {0.0, -0.1};
  in.capturePoint = Eigen::Vector2d(0.0, -0.1) + Eigen::Vector2d(0.2, 0.2 / 3.0);
  return in;
}

TEST(StepAdjustment, OnTheOrbitTheFootholdsAreThePeriodicGaits) {
  const CaptureStepInput in = onTheOrbit();
  Step steps[2];
  steps[0].left = true;
  steps[0].liftOff = 0.0;
  steps[0].touchDown = 0.4;
  steps[1].left = false;
  steps[1].liftOff = 0.4;
  steps[1].touchDown = 0.8;
  captureFootholds(in, steps, 2);
  // ξ_td = p_R + 2 (ξ − p_R) = (0.4, 0.0333); foothold = ξ_td − b_L = (0.2, 0.1).
  expectNear(steps[0].capturePoint, 0.4, 0.1 / 3.0);
  expectNear(steps[0].foothold, 0.2, 0.1);
  EXPECT_FALSE(steps[0].limited);
  // And the right foot 0.4 ahead of where it was.
  expectNear(steps[1].foothold, 0.4, -0.1);
}

TEST(StepAdjustment, APushMovesTheFootholdWhereItCarriesThePointNotByItsOffsetOn) {
  // d = (0.05, 0): ξ_td = p − d + (ξ + d − p)·2 = (0.45, 0.0333); foothold ξ_td − b_L,
  // not ξ_td + d − b_L (0.3: where the centre of pressure holds ξ still if the push outlasts
  // the step; header comment).
  CaptureStepInput in = onTheOrbit();
  in.forceOffset = {0.05, 0.0};
  Step step;
  step.left = true;
  step.liftOff = 0.0;
  step.touchDown = 0.4;
  captureFootholds(in, &step, 1);
  expectNear(step.capturePoint, 0.45, 0.1 / 3.0);
  expectNear(step.foothold, 0.25, 0.1);
  // A capture point 0.4 m further ahead: the step is held to 0.5 m ahead of the stance foot.
  in.forceOffset.setZero();
  in.capturePoint.x() += 0.4;  // ξ_td 0.8 further ahead, foothold (1.0, 0.1)
  captureFootholds(in, &step, 1);
  expectNear(step.foothold, 0.5, 0.1);
  EXPECT_TRUE(step.limited);
}

TEST(StepAdjustment, AStepLandsWhereTheNextOneCanReachItsCapturePoint) {
  // Steps at most 0.18 m apart sideways. The capture point 0.03 m to the right of the orbit:
  // the left step's own target is (0.2, 0.1 − 2·0.03) = (0.2, 0.04), within reach; from there
  // the right step's would be (0.4, −0.16), 0.2 m out, held to −0.14. The next step's
  // ξ_td − p_stance changes by −(e − α) = −2 per metre the stance foot moves, so the left foot
  // lands 0.02/2 = 0.01 m further right and the right step reaches its target, (0.4, −0.15).
  CaptureStepInput in = onTheOrbit();
  in.limits.maxWidth = 0.18;
  in.capturePoint.y() -= 0.03;
  Step steps[2];
  steps[0].left = true;
  steps[0].touchDown = 0.4;
  steps[1].left = false;
  steps[1].liftOff = 0.4;
  steps[1].touchDown = 0.8;
  captureFootholds(in, steps, 2);
  expectNear(steps[0].foothold, 0.2, 0.03);
  EXPECT_FALSE(steps[0].limited);
  expectNear(steps[1].foothold, 0.4, -0.15);
  EXPECT_FALSE(steps[1].limited);
  // 0.05 m to the right: the left step's target (0.2, 0.0) is held to 0.12 from the right foot,
  // (0.2, 0.02), and it cannot move further right for the next one, which is held in turn.
  in.capturePoint.y() -= 0.02;
  captureFootholds(in, steps, 2);
  expectNear(steps[0].foothold, 0.2, 0.02);
  EXPECT_TRUE(steps[0].limited);
  expectNear(steps[1].foothold, 0.4, 0.02 - 0.18);
  EXPECT_TRUE(steps[1].limited);
  // With a double support before the next lift-off (0.05 s: α ≠ 0), the right step's target,
  // 0.188 m out from (0.2, 0.04), is brought exactly onto its limit by the left foot's move.
  in.capturePoint.y() += 0.02;
  steps[0] = Step{};
  steps[0].left = true;
  steps[0].touchDown = 0.4;
  steps[1].liftOff = 0.45;
  captureFootholds(in, steps, 2);
  EXPECT_LT(steps[0].foothold.y(), 0.04 - 1e-3);
  EXPECT_FALSE(steps[1].limited);
  EXPECT_NEAR(steps[0].foothold.y() - steps[1].foothold.y(), 0.18, 1e-9);
}

TEST(StepAdjustment, AFixedStepKeepsItsFootholdAndTheNextStepsFromIt) {
  CaptureStepInput in = onTheOrbit();
  Step steps[2];
  steps[0].left = true;
  steps[0].touchDown = 0.4;
  steps[0].fixed = true;
  steps[0].foothold = {0.2, 0.1};
  steps[1].left = false;
  steps[1].liftOff = 0.4;
  steps[1].touchDown = 0.8;
  captureFootholds(in, steps, 2);
  expectNear(steps[0].foothold, 0.2, 0.1);
  expectNear(steps[1].foothold, 0.4, -0.1);
}

}  // namespace
}  // namespace ballast::gait
