#include "sensor_model.hpp"

#include <cmath>

namespace ballast::simbody {

void SensorModel::configure(const SimSettings& s, double period, std::uint64_t seed) {
  seed_ = seed;
  encoderResolution_ = s.encoder_resolution;
  velocityNoise_ = s.joint_velocity_noise;
  torqueNoise_ = s.torque_noise;
  gyroSigma_ = s.imu_gyro_noise_density / std::sqrt(period);
  accelSigma_ = s.imu_accel_noise_density / std::sqrt(period);
  gyroBiasSigma_ = s.imu_gyro_bias;
  accelBiasSigma_ = s.imu_accel_bias;
  orientationSigma_ = s.imu_orientation_noise;
  fixPeriod_ = s.position_fix_rate > 0.0 ? 1.0 / s.position_fix_rate : 0.0;
  fixSigma_ = s.position_fix_noise;
  start();
}

void SensorModel::start() {
  rng_.seed(seed_);
  normal_.reset();
  for (int i = 0; i < 3; ++i) gyroBias_[i] = gaussian(gyroBiasSigma_);
  for (int i = 0; i < 3; ++i) accelBias_[i] = gaussian(accelBiasSigma_);
  fixRng_.seed(seed_ ^ 0x9e3779b97f4a7c15ULL);
  fixNormal_.reset();
  nextFix_ = 0.0;
}

void SensorModel::sample(const SimbodyWorld& world, backend::Sensors& out) {
  const int n = world.numJoints();
  out.num_joints = n;
  world.jointState(out.q, out.dq);
  world.motorTorques(out.tau);
  for (int j = 0; j < n; ++j) {
    if (encoderResolution_ > 0.0)
      out.q[j] = encoderResolution_ * std::round(out.q[j] / encoderResolution_);
    out.dq[j] += gaussian(velocityNoise_);
    out.tau[j] += gaussian(torqueNoise_);
  }

  const ImuTruth imu = world.imu();
  SimTK::Rotation R = imu.R_GI;
  if (orientationSigma_ > 0.0) {
    const SimTK::Vec3 v(gaussian(orientationSigma_), gaussian(orientationSigma_),
                        gaussian(orientationSigma_));
    const double angle = v.norm();
    if (angle > 0.0) R = R * SimTK::Rotation(angle, SimTK::UnitVec3(v / angle));
  }
  const SimTK::Quaternion quat = R.convertRotationToQuaternion();
  for (int i = 0; i < 3; ++i) {
    out.imu.orientation[i] = quat[i + 1];
    out.imu.angular_velocity[i] = imu.angularVelocity[i] + gyroBias_[i] + gaussian(gyroSigma_);
    out.imu.linear_acceleration[i] = imu.specificForce[i] + accelBias_[i] + gaussian(accelSigma_);
  }
  out.imu.orientation[3] = quat[0];
  out.imu_valid = true;

  out.has_truth = true;
  world.truth(out.truth);

  backend::PositionFix& fix = out.position_fix;
  fix.fresh = false;
  // A fix per fixPeriod_ of simulated time (the tolerance absorbs the sum of tick periods).
  if (fixPeriod_ > 0.0 && world.time() + 1e-9 >= nextFix_) {
    fix.fresh = true;
    fix.time = world.time();
    for (int i = 0; i < 3; ++i) {
      fix.position[i] = out.truth.base_position[i] + fixSigma_ * fixNormal_(fixRng_);
      fix.stddev[i] = fixSigma_;
    }
    nextFix_ += fixPeriod_;
  }
}

}  // namespace ballast::simbody
