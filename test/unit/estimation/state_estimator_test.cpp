// The estimator's behaviour at its edges: start-up, bad input, the contact decision, flight,
// and the external position correction.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "estimation/state_estimator.hpp"
#include "test/unit/settings_support.hpp"
#include "test/unit/test_support.hpp"

namespace ballast::test {
namespace {

using namespace estimation;
using Eigen::Matrix3d;
using Eigen::Vector3d;
using Eigen::VectorXd;

/// The humanoid standing at rest, base yawed and slightly tilted, feet flat on z = 0.
struct Standing {
  const model::Model& m = humanoid();
  VectorXd q;
  Matrix3d Rwb;
  Standing() {
    q = standingConfiguration(m);
    q.segment<4>(3) = model::quaternionXyzwFromZyx(Vector3d(0.7, 0.0, 0.0));  // yaw only: feet stay flat
    Rwb = model::quaternionToRotation<double>(q.segment<4>(3));
  }
  /// Sensor input at rest; the torques put force[c] (world) on contact point c.
  void fill(EstimatorInput& in, double t, const std::array<Vector3d, kContactPoints>& force) const {
    in.time = t;
    in.q = q.tail(m.nj());
    in.dq.setZero();
    model::Data<double> d(m);
    VectorXd tau = model::nonLinearEffects(m, d, q, VectorXd::Zero(m.nv));
    Eigen::Matrix<double, 3, Eigen::Dynamic> J(3, m.nv);
    const char* names[] = {"left_toe", "left_heel", "right_toe", "right_heel"};
    for (int c = 0; c < kContactPoints; ++c) {
      model::frameJacobian(m, d, m.frameId(names[c]), J);
      tau -= J.transpose() * force[c];
    }
    in.tau = tau.tail(m.nj());
    const model::Frame& imu = m.frames[m.frameId("imu")];
    const Matrix3d Rwi = Rwb * imu.placement.R;
    in.imu.orientation = Eigen::Quaterniond(Rwi);
    in.imu.angularVelocity.setZero();
    in.imu.linearAcceleration = Rwi.transpose() * -m.gravity;
    in.imu.valid = true;
  }
  std::array<Vector3d, kContactPoints> weightOnAll() const {
    const Vector3d f(0, 0, m.totalMass() * 9.81 / 4);
    return {f, f, f, f};
  }
};

TEST(StateEstimator, WaitsForTheImu) {
  Standing s;
  StateEstimator est(s.m, estimatorSettings());
  EstimatorInput in = est.makeInput();
  s.fill(in, 0.0, s.weightOnAll());
  in.imu.valid = false;
  EstimatorOutput out;
  EXPECT_EQ(est.update(in, out), EstimatorStatus::kWaitingForImu);
  EXPECT_FALSE(out.valid);
  in.imu.valid = true;
  EXPECT_EQ(est.update(in, out), EstimatorStatus::kOk);
  EXPECT_TRUE(out.valid);
}

TEST(StateEstimator, StartsWithTheFeetOnTheTerrainAtTheGivenPlace) {
  Standing s;
  StateEstimator est(s.m, estimatorSettings());
  est.reset(1.5, -2.0);
  EstimatorInput in = est.makeInput();
  s.fill(in, 0.0, s.weightOnAll());
  for (double& h : in.terrainHeight) h = 0.25;  // standing on a stage
  EstimatorOutput out;
  ASSERT_EQ(est.update(in, out), EstimatorStatus::kOk);
  EXPECT_NEAR(out.basePosition.x(), 1.5, 1e-12);
  EXPECT_NEAR(out.basePosition.y(), -2.0, 1e-12);
  EXPECT_NEAR(out.basePosition.z(), s.q[2] + 0.25, 1e-9);
  EXPECT_NEAR(out.rpy.z(), 0.7, 1e-9);
  for (int c = 0; c < kContactPoints; ++c) {
    EXPECT_TRUE(out.stance[c]);
    EXPECT_NEAR(out.contactPosition[c].z(), 0.25, 1e-9);
  }
}

TEST(StateEstimator, RefusesBadInputAndKeepsItsState) {
  Standing s;
  StateEstimator est(s.m, estimatorSettings());
  EstimatorInput in = est.makeInput();
  EstimatorOutput out;
  for (int k = 0; k < 10; ++k) {
    s.fill(in, 0.001 * k, s.weightOnAll());
    est.update(in, out);
  }
  const EstimatorOutput before = out;
  const BaseKalmanFilter::Vector x = est.kalmanFilter().state();
  EstimatorInput bad = in;
  bad.time = 0.010;
  bad.q[3] = std::nan("");
  EXPECT_EQ(est.update(bad, out), EstimatorStatus::kInvalidInput);
  bad = in;
  bad.imu.linearAcceleration.x() = INFINITY;
  EXPECT_EQ(est.update(bad, out), EstimatorStatus::kInvalidInput);
  bad = in;
  bad.tau.resize(3);
  EXPECT_EQ(est.update(bad, out), EstimatorStatus::kInvalidInput);
  bad = in;
  bad.imu.orientation.coeffs().setZero();
  EXPECT_EQ(est.update(bad, out), EstimatorStatus::kInvalidInput);
  EXPECT_EQ(est.kalmanFilter().state(), x);
  EXPECT_EQ(out.basePosition, before.basePosition);
  EXPECT_EQ(out.time, before.time);
}

TEST(StateEstimator, ScheduledContactNeedsTheForce) {
  // The planner schedules all four points, but the left foot carries nothing: it stays swing.
  Standing s;
  StateEstimator est(s.m, estimatorSettings());
  EstimatorInput in = est.makeInput();
  std::array<Vector3d, kContactPoints> force = s.weightOnAll();
  force[0] = force[1] = Vector3d::Zero();
  force[2] *= 2;
  force[3] *= 2;
  EstimatorOutput out;
  for (int k = 0; k < 50; ++k) {
    s.fill(in, 0.001 * k, force);
    est.update(in, out);
  }
  EXPECT_FALSE(out.stance[0]);
  EXPECT_FALSE(out.stance[1]);
  EXPECT_TRUE(out.stance[2]);
  EXPECT_TRUE(out.stance[3]);
  // Within what λ leaves out of a bent leg's load (estimator.contact_force_regularization, 1 %
  // along the leg at this knee: contact_force_observer.hpp).
  EXPECT_NEAR(out.contactForce[2].z(), force[2].z(), 0.02 * force[2].z());  // 1.2 % here
  EXPECT_NEAR(out.contactForce[0].z(), 0.0, 1.0);
  // Not scheduled: not stance, whatever the force.
  in.scheduledStance = {true, true, false, true};
  est.update(in, out);
  EXPECT_FALSE(out.stance[2]);
  EXPECT_TRUE(out.stance[3]);
  // With the check off, the schedule alone decides.
  EstimatorSettings scheduleOnly = estimatorSettings();
  scheduleOnly.contactForceCheck = false;
  ASSERT_TRUE(est.setSettings(scheduleOnly));
  in.scheduledStance = {true, true, true, true};
  est.update(in, out);
  EXPECT_TRUE(out.stance[0]);
}

TEST(StateEstimator, AFootOnItsHeelKeepsItsToeInStance) {
  // Weight on the heels (centre of pressure behind the ankles): the toes carry nothing, the
  // feet are down all the same.
  Standing s;
  StateEstimator est(s.m, estimatorSettings());
  EstimatorInput in = est.makeInput();
  std::array<Vector3d, kContactPoints> force = s.weightOnAll();
  force[1] += force[0];
  force[3] += force[2];
  force[0] = force[2] = Vector3d::Zero();
  EstimatorOutput out;
  for (int k = 0; k < 50; ++k) {
    s.fill(in, 0.001 * k, force);
    est.update(in, out);
  }
  for (int c = 0; c < kContactPoints; ++c) EXPECT_TRUE(out.stance[c]) << c;
  EXPECT_NEAR(out.contactForce[0].z(), 0.0, 1.0);
}

TEST(StateEstimator, ALandedFootInPlannedStanceOutlastsAShortDropInItsForce) {
  // A landing bounces and a stretched leg hides its load: the right foot's estimated force
  // falls to nothing for 20 ms while the plan keeps it in stance. It stays in stance; held
  // low past estimator.contact_force_release_time it is released; with the plan's swing, at
  // once.
  Standing s;
  EstimatorSettings settings = estimatorSettings();
  ASSERT_GT(settings.contactForceReleaseTime, 0.03);
  // The force estimate follows the torques within a tick: what is tested is the decision, not
  // the observer's lag.
  settings.contactForceBandwidth = 1000.0;
  StateEstimator est(s.m, settings);
  EstimatorInput in = est.makeInput();
  std::array<Vector3d, kContactPoints> unloadedRight = s.weightOnAll();
  unloadedRight[0] *= 2;
  unloadedRight[1] *= 2;
  unloadedRight[2] = unloadedRight[3] = Vector3d::Zero();
  EstimatorOutput out;
  int k = 0;
  auto run = [&](int ticks, const std::array<Vector3d, kContactPoints>& force) {
    bool always = true;
    for (int i = 0; i < ticks; ++i, ++k) {
      s.fill(in, 0.001 * k, force);
      est.update(in, out);
      always = always && out.stance[2] && out.stance[3];
    }
    return always;
  };
  EXPECT_TRUE(run(200, s.weightOnAll()));
  EXPECT_TRUE(run(20, unloadedRight)) << "a 20 ms drop released the foot";
  EXPECT_TRUE(run(100, s.weightOnAll()));
  // Low for longer than the release time: a lift-off the plan did not have.
  run(static_cast<int>(settings.contactForceReleaseTime / 0.001) + 40, unloadedRight);
  EXPECT_FALSE(out.stance[2] || out.stance[3]);
  EXPECT_TRUE(out.stance[0] && out.stance[1]);
  // Loaded again, confirmed again; then the plan's swing with the force gone: released at once,
  // and scheduled again while still unloaded, not in stance.
  run(100, s.weightOnAll());
  EXPECT_TRUE(out.stance[2] && out.stance[3]);
  in.scheduledStance = {true, true, false, false};
  run(2, unloadedRight);
  in.scheduledStance = {true, true, true, true};
  run(1, unloadedRight);
  EXPECT_FALSE(out.stance[2] || out.stance[3]);
}

/// Max |base velocity| while the left leg's encoders report a 0.5 rad/s hip swing for 20 ticks,
/// its foot still loaded (a slipping foot, as the legs see it).
double velocityDuringLeftFootSlip(double gate) {
  Standing s;
  EstimatorSettings settings = estimatorSettings();
  settings.kinematicsVelocityGate = gate;
  // The gate counts in σ of the leg velocity: at 0.05 m/s, 5σ puts it at 0.25 m/s, below the
  // ~0.4 m/s this hip swing gives the foot (the default σ, 0.2, lets slower creep through).
  settings.kinematicsVelocityNoise = 0.05;
  StateEstimator est(s.m, settings);
  EstimatorInput in = est.makeInput();
  EstimatorOutput out;
  double worst = 0;
  for (int k = 0; k < 220; ++k) {
    s.fill(in, 0.001 * k, s.weightOnAll());
    if (k >= 200) in.dq[s.m.jointId("left_hip_pitch")] = 0.5;
    est.update(in, out);
    if (k >= 200) {
      worst = std::max(worst, out.baseLinearVelocity.norm());
      if (gate > 0) {
        EXPECT_FALSE(out.stance[0] || out.stance[1]) << "tick " << k;
        EXPECT_TRUE(out.slipping[0] && out.slipping[1]) << "tick " << k;
      }
      EXPECT_TRUE(out.stance[2] && out.stance[3]);
    }
  }
  return worst;
}

TEST(StateEstimator, VelocityGateRejectsASlippingFoot) {
  EXPECT_LT(velocityDuringLeftFootSlip(5.0), 0.01);
  EXPECT_GT(velocityDuringLeftFootSlip(0.0), 0.05);  // without the gate the slip pulls the base
}

TEST(StateEstimator, WithoutStanceItIntegratesTheImu) {
  // Free fall for 0.2 s: the accelerometer reads 0, no point is scheduled.
  Standing s;
  StateEstimator est(s.m, estimatorSettings());
  EstimatorInput in = est.makeInput();
  EstimatorOutput out;
  s.fill(in, 0.0, s.weightOnAll());
  est.update(in, out);
  const double z0 = out.basePosition.z();
  in.scheduledStance = {false, false, false, false};
  in.imu.linearAcceleration.setZero();
  EstimatorStatus status = EstimatorStatus::kOk;
  for (int k = 1; k <= 200; ++k) {
    in.time = 0.001 * k;
    status = est.update(in, out);
  }
  EXPECT_EQ(status, EstimatorStatus::kNoStance);
  EXPECT_NEAR(out.baseLinearVelocity.z(), -9.81 * 0.2, 1e-9);
  EXPECT_NEAR(out.basePosition.z(), z0 - 0.5 * 9.81 * 0.2 * 0.2, 1e-9);
  // Swing points follow the legs.
  for (int c = 0; c < kContactPoints; ++c) EXPECT_NEAR(out.contactPosition[c].z(), out.basePosition.z() - z0, 1e-9);
}

TEST(StateEstimator, ExternalPositionCorrection) {
  Standing s;
  StateEstimator est(s.m, estimatorSettings());
  EstimatorInput in = est.makeInput();
  EstimatorOutput out;
  Vector3d p;
  EXPECT_FALSE(est.correctPosition(Vector3d::Zero(), Matrix3d::Identity()));  // no estimate yet
  for (int k = 0; k < 500; ++k) {
    s.fill(in, 0.001 * k, s.weightOnAll());
    est.update(in, out);
  }
  p = out.basePosition;
  const Vector3d c0 = out.contactPosition[0];
  // A lidar fix 5 cm ahead, far more certain than the estimate: the base and the stance points
  // it is tied to move together.
  ASSERT_TRUE(est.correctPosition(p + Vector3d(0.05, 0, 0), 1e-8 * Matrix3d::Identity()));
  s.fill(in, 0.5, s.weightOnAll());
  est.update(in, out);
  EXPECT_NEAR(out.basePosition.x(), p.x() + 0.05, 1e-3);
  EXPECT_NEAR(out.contactPosition[0].x(), c0.x() + 0.05, 2e-3);
  EXPECT_NEAR(out.basePosition.z(), p.z(), 1e-3);
  Matrix3d asymmetric = Matrix3d::Identity();
  asymmetric(0, 1) = 0.5;
  EXPECT_FALSE(est.correctPosition(p, asymmetric));
  EXPECT_FALSE(est.correctPosition(Vector3d(std::nan(""), 0, 0), Matrix3d::Identity()));
  EXPECT_FALSE(est.correctPosition(p, -Matrix3d::Identity()));
}

}  // namespace
}  // namespace ballast::test
