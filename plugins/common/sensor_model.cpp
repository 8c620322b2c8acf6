#include "sensor_model.hpp"

#include <cmath>

namespace ballast::plugin {

void SensorModel::configure(const SensorNoise& s, double period, std::uint64_t seed) {
  seed_ = seed;
  encoderResolution_ = s.encoder_resolution;
  velocityNoise_ = s.joint_velocity_noise;
  torqueNoise_ = s.torque_noise;
  gyroSigma_ = s.gyro_noise_density / std::sqrt(period);
  accelSigma_ = s.accel_noise_density / std::sqrt(period);
  gyroBiasSigma_ = s.gyro_bias;
  accelBiasSigma_ = s.accel_bias;
  orientationSigma_ = s.orientation_noise;
  fixPeriod_ = s.position_fix_rate > 0.0 ? 1.0 / s.position_fix_rate : 0.0;
  fixSigma_ = s.position_fix_noise;
  start();
}

void SensorModel::start() {
  rng_.seed(seed_);
  normal_.reset();
  for (double& b : gyroBias_) b = gaussian(gyroBiasSigma_);
  for (double& b : accelBias_) b = gaussian(accelBiasSigma_);
  fixRng_.seed(seed_ ^ 0x9e3779b97f4a7c15ULL);
  fixNormal_.reset();
  nextFix_ = 0.0;
}

void SensorModel::sample(const ImuTruth& imu, double time, backend::Sensors& out) {
  for (int j = 0; j < out.num_joints; ++j) {
    if (encoderResolution_ > 0.0)
      out.q[j] = encoderResolution_ * std::round(out.q[j] / encoderResolution_);
    out.dq[j] += gaussian(velocityNoise_);
    out.tau[j] += gaussian(torqueNoise_);
  }

  // Orientation: the true one turned by a small random rotation about an IMU-frame axis,
  // q = q_true ⊗ q_noise; reported with w >= 0.
  double q[4] = {imu.orientation[0], imu.orientation[1], imu.orientation[2], imu.orientation[3]};
  if (orientationSigma_ > 0.0) {
    const double v[3] = {gaussian(orientationSigma_), gaussian(orientationSigma_),
                         gaussian(orientationSigma_)};
    const double angle = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (angle > 0.0) {
      const double s = std::sin(angle / 2) / angle, c = std::cos(angle / 2);
      const double n[4] = {s * v[0], s * v[1], s * v[2], c};  // (x, y, z, w)
      const double a[4] = {q[0], q[1], q[2], q[3]};
      q[3] = a[3] * n[3] - a[0] * n[0] - a[1] * n[1] - a[2] * n[2];
      q[0] = a[3] * n[0] + a[0] * n[3] + a[1] * n[2] - a[2] * n[1];
      q[1] = a[3] * n[1] - a[0] * n[2] + a[1] * n[3] + a[2] * n[0];
      q[2] = a[3] * n[2] + a[0] * n[1] - a[1] * n[0] + a[2] * n[3];
    }
  }
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  const double sign = q[3] < 0.0 ? -1.0 : 1.0;
  for (int i = 0; i < 4; ++i) out.imu.orientation[i] = sign * q[i] / norm;
  for (int i = 0; i < 3; ++i) {
    out.imu.angular_velocity[i] = imu.angular_velocity[i] + gyroBias_[i] + gaussian(gyroSigma_);
    out.imu.linear_acceleration[i] = imu.specific_force[i] + accelBias_[i] + gaussian(accelSigma_);
  }
  out.imu_valid = true;

  backend::PositionFix& fix = out.position_fix;
  fix.fresh = false;
  // A fix per fixPeriod_ of simulated time (the tolerance absorbs the sum of tick periods).
  if (fixPeriod_ > 0.0 && time + 1e-9 >= nextFix_) {
    fix.fresh = true;
    fix.time = time;
    for (int i = 0; i < 3; ++i) {
      fix.position[i] = out.truth.base_position[i] + fixSigma_ * fixNormal_(fixRng_);
      fix.stddev[i] = fixSigma_;
    }
    nextFix_ += fixPeriod_;
  }
}

}  // namespace ballast::plugin
