// The estimator in the loop (issue 7): the humanoid balances in the Simbody backend under the
// whole-body controller running on the ESTIMATE (base from the estimator, joints from the
// quantised encoders), with realistic sensor noise and biases (kRealisticSensors), while both
// arms swing ±60° at 1 Hz out of phase (as test/integration/wbc/balance_test.cpp) and the base is
// pushed forward (40 N), sideways (35 N) and backward (40 N), 0.3 s each. The estimate is scored
// against the simulator's ground truth over the 10 s (after a 0.1 s start, EstimationScore) to
// the issue's bars: velocity error RMS ≤ 0.05 m/s, height error ≤ 1 cm, roll/pitch error ≤ 1°;
// and, the robot standing, horizontal drift ≤ 1 cm. The pushes make the feet rock and pivot
// (the summary prints how far the contact points moved while touching the ground: leg odometry
// cannot see that, and it is most of the drift). The contact decision (all four points
// scheduled, confirmed by the estimated force) must agree with the simulator's contacts 98 % of
// the time: a foot rattling at 100 Hz after a push is what it misses.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "test/integration/estimation/estimation_loop.hpp"

namespace ballast::test {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

/// Arm swing references: shoulder pitch ±60° at 1 Hz, out of phase, amplitude ramped in over
/// the first second (C² quintic), the other arm joints held where they started.
void armSwing(const model::Model& m, double t, wbc::WbcReference& ref) {
  const double amplitude = 60.0 * kDeg, omega = 2.0 * kPi;
  const double tau = std::min(t, 1.0);
  const double e = tau * tau * tau * (10.0 - 15.0 * tau + 6.0 * tau * tau);
  const double de = t < 1.0 ? 30.0 * tau * tau * (1.0 - tau) * (1.0 - tau) : 0.0;
  const double dde = t < 1.0 ? 60.0 * tau * (1.0 - tau) * (1.0 - 2.0 * tau) : 0.0;
  const double sn = std::sin(omega * t), cs = std::cos(omega * t);
  for (auto [name, sign] : {std::pair{"left_shoulder_pitch", 1.0}, std::pair{"right_shoulder_pitch", -1.0}}) {
    const int j = m.jointId(name);
    ref.jointPosition[j] = sign * amplitude * e * sn;
    ref.jointVelocity[j] = sign * amplitude * (de * sn + e * omega * cs);
    ref.jointAcceleration[j] =
        sign * amplitude * (dde * sn + 2.0 * de * omega * cs - e * omega * omega * sn);
  }
}

struct BalanceRun {
  EstimationScore score;
  bool fell = false;
  double fallTime = -1;
  int failedTicks = 0;
};

BalanceRun balanceWithPushes(bool controlOnTruth, double seconds) {
  EstimationLoop::Options options;
  options.controlOnTruth = controlOnTruth;
  EstimationLoop loop(options);
  const model::Model& m = loop.model();
  BalanceRun run;
  if (!loop.sense()) return run;
  // Hold the pose the robot starts in, in the estimator's world; weight shared by the four points.
  wbc::WbcReference& ref = loop.reference;
  ref.basePosition = loop.estimate().basePosition;
  ref.baseOrientation = loop.estimate().baseOrientation;
  ref.jointPosition = loop.input().q;
  for (int c = 0; c < 4; ++c) ref.contactForce[3 * c + 2] = m.totalMass() * 9.81 / 4;
  const double startHeight = loop.sensors().truth.base_position[2];
  struct Push {
    double t, fx, fy, duration;
  };
  const Push pushes[] = {{3.0, 40, 0, 0.3}, {5.5, 0, 35, 0.3}, {8.0, -40, 0, 0.3}};
  const int ticks = static_cast<int>(std::lround(seconds / 0.001));
  for (int tick = 0; tick < ticks; ++tick) {
    const double t = loop.sensors().time;
    for (const Push& p : pushes)
      if (std::abs(t - p.t) < 0.0005) loop.push(p.fx, p.fy, p.duration);
    armSwing(m, t, ref);
    if (!loop.act() || !loop.sense()) break;
    if (loop.fallen(startHeight)) {
      run.fell = true;
      run.fallTime = loop.sensors().time;
      break;
    }
  }
  run.score = loop.score;
  run.failedTicks = loop.failedTicks;
  return run;
}

void expectIssueBars(const BalanceRun& run) {
  EXPECT_FALSE(run.fell) << "fell at t = " << run.fallTime << " s";
  EXPECT_EQ(run.failedTicks, 0);
  const EstimationScore& s = run.score;
  EXPECT_GT(s.samples, 9800);
  EXPECT_LE(s.velocityRms, 0.05);
  EXPECT_LE(s.heightMax, 0.01);
  EXPECT_LE(s.tiltMax, 1.0 * kDeg);
  EXPECT_LE(s.driftMax, 0.01);
  EXPECT_GE(s.contactAgreement, 0.98);
}

TEST(EstimatorInTheLoop, BalancingOnTheEstimateWhileArmsSwingAndPushes) {
  const BalanceRun run = balanceWithPushes(false, 10.0);
  std::printf("%s\n", run.score.summary("WBC on the estimate").c_str());
  RecordProperty("summary", run.score.summary("WBC on the estimate"));
  expectIssueBars(run);
  // The pushes really moved the robot (the velocities scored are not just noise around zero).
  EXPECT_GT(run.score.distance, 0.02);
}

TEST(EstimatorInTheLoop, SameRunWithTheControllerOnGroundTruth) {
  // The estimator watches, the controller runs on the simulator's truth: the estimator's own
  // error without the loop feeding it back.
  const BalanceRun run = balanceWithPushes(true, 10.0);
  std::printf("%s\n", run.score.summary("WBC on ground truth, estimator watching").c_str());
  RecordProperty("summary", run.score.summary("WBC on truth"));
  expectIssueBars(run);
}

}  // namespace
}  // namespace ballast::test
