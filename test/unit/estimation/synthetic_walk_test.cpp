// The estimator on a synthetic 10 s walk (synthetic_walk.hpp) with the sensors' noise and biases:
// it must converge and stay within the issue's bounds — horizontal drift ≤ 2 % of the distance
// walked, velocity RMS error ≤ 0.05 m/s, height error ≤ 1 cm, roll/pitch error ≤ 1° — and find
// the gyro bias. The contact decision is the schedule alone here (no torques are synthesised;
// the force check is tested in contact_force_observer_test and in the Simbody integration test).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "test/unit/estimation/synthetic_walk.hpp"
#include "test/unit/settings_support.hpp"

namespace ballast::test {
namespace {

using namespace estimation;
using Eigen::Vector3d;

struct WalkFigures {
  double distance = 0, drift = 0, driftMax = 0, velocityRms = 0, heightMax = 0, tiltMax = 0;
  double tiltMaxAfter1s = 0;  // once the attitude filter has settled
  double yawDrift = 0, gyroBiasError = 0, velocityWithin3Sigma = 0;
};

WalkFigures walk(const SensorNoise& noise, const EstimatorSettings& settings, double seconds,
                 unsigned seed) {
  const model::Model& m = humanoid();
  SyntheticWalk motion(m);
  SyntheticSensors sensors(motion, noise, seed);
  StateEstimator est(m, settings);
  EstimatorInput in = est.makeInput();
  EstimatorOutput out;
  Eigen::VectorXd q, v;
  WalkFigures fig;
  double sumV2 = 0;
  int n = 0, within = 0;
  Vector3d start = Vector3d::Zero();
  const int ticks = static_cast<int>(std::lround(seconds / motion.period));
  for (int k = 0; k <= ticks; ++k) {
    const double t = k * motion.period;
    sensors.sample(t, in, q, v);
    const EstimatorStatus status = est.update(in, out);
    EXPECT_EQ(status, EstimatorStatus::kOk) << "t = " << t;
    const Eigen::Matrix3d R = model::quaternionToRotation<double>(q.segment<4>(3));
    const Vector3d velocity = R * v.head<3>();
    if (k == 0) start = q.head<3>();
    const Vector3d e = out.basePosition - q.head<3>();
    const Vector3d ev = out.baseLinearVelocity - velocity;
    // Roll and pitch of the error rotation, and its yaw.
    const Vector3d tilt = model::rpyFromRotation(R.transpose() * out.baseRotation);
    fig.driftMax = std::max(fig.driftMax, e.head<2>().norm());
    fig.heightMax = std::max(fig.heightMax, std::abs(e.z()));
    fig.tiltMax = std::max({fig.tiltMax, std::abs(tilt.x()), std::abs(tilt.y())});
    if (t >= 1.0) fig.tiltMaxAfter1s = std::max({fig.tiltMaxAfter1s, std::abs(tilt.x()), std::abs(tilt.y())});
    fig.yawDrift = std::abs(tilt.z());
    sumV2 += ev.squaredNorm();
    ++n;
    const Eigen::Vector3d sigma = out.covarianceDiagonal.segment<3>(3).cwiseSqrt();
    within += (ev.array().abs() <= 3.0 * sigma.array()).all();
    fig.drift = e.head<2>().norm();
    fig.distance = (q.head<2>() - start.head<2>()).norm();
  }
  fig.velocityRms = std::sqrt(sumV2 / n);
  fig.velocityWithin3Sigma = static_cast<double>(within) / n;
  fig.gyroBiasError = (out.gyroBias - sensors.gyroBias()).norm();
  std::printf("synthetic walk %.1f s, %.2f m: drift %.1f mm (max %.1f mm), velocity RMS %.1f mm/s "
              "(%.0f %% of samples within 3σ), height max %.2f mm, roll/pitch max %.3f deg (%.3f deg "
              "after 1 s), yaw %.3f deg, gyro bias error %.1e rad/s\n",
              seconds, fig.distance, 1e3 * fig.drift, 1e3 * fig.driftMax, 1e3 * fig.velocityRms,
              100 * fig.velocityWithin3Sigma, 1e3 * fig.heightMax, fig.tiltMax * 180 / M_PI, fig.tiltMaxAfter1s * 180 / M_PI,
              fig.yawDrift * 180 / M_PI, fig.gyroBiasError);
  return fig;
}

TEST(EstimatorSyntheticWalk, ConvergesAndStaysWithinTheIssueBounds) {
  EstimatorSettings settings = estimatorSettings();
  settings.contactForceCheck = false;
  const WalkFigures fig = walk(SensorNoise{}, settings, 10.0, 1);
  EXPECT_GT(fig.distance, 3.0);
  EXPECT_LE(fig.drift, 0.02 * fig.distance);
  EXPECT_LE(fig.velocityRms, 0.05);
  EXPECT_LE(fig.heightMax, 0.01);
  EXPECT_LE(fig.tiltMax, 1.0 * M_PI / 180);
  EXPECT_LE(fig.gyroBiasError, 1e-3);
  // The filter's velocity uncertainty is honest: most errors within 3σ.
  EXPECT_GE(fig.velocityWithin3Sigma, 0.9);
}

TEST(EstimatorSyntheticWalk, LegKinematicsAreWhatHoldsThePosition) {
  // The same walk with the legs' measurements made worthless (huge noise): position and
  // velocity then drift on the IMU alone, far outside the bounds. Shows that the bounds above
  // are met by the fusion, not by an easy trajectory.
  EstimatorSettings settings = estimatorSettings();
  settings.contactForceCheck = false;
  settings.kinematicsPositionNoise = 1.0;
  settings.kinematicsVelocityNoise = 10.0;
  settings.footHeightNoise = 1.0;
  const WalkFigures fig = walk(SensorNoise{}, settings, 10.0, 1);
  EXPECT_GT(fig.velocityRms, 0.05);
}

}  // namespace
}  // namespace ballast::test
