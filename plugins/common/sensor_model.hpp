// What a simulated robot's sensors report, from the simulation's true values: joint encoders
// (quantised, velocity noise), motor torques (noise), IMU (white noise + a per-axis bias drawn at
// start, a small random rotation on the orientation) and, when position_fix_rate > 0, a
// localisation source: the true base position with white noise, at that rate (what lidar scans
// matched against the map give a real robot). Shared by the simulation backends (simbody,
// mujoco), so a profile's noise means the same on either.
//
// All randomness comes from one generator seeded with Config::seed and re-seeded by start(), so
// a lockstep run repeats bit for bit; a sample is drawn once per tick (reading twice does not
// draw twice). Noise σ per sample = density / √period (white noise sampled at the tick rate).
// Position fixes draw from their own generator: turning them on changes no other reading.
// Nothing allocates.
#pragma once

#include <cstdint>
#include <random>

#include "backend_abi.hpp"

namespace ballast::plugin {

/// The noise of every sensor (a backend's profile keys of the same names).
struct SensorNoise {
  double encoder_resolution = 0.0;    ///< rad; 0: exact
  double joint_velocity_noise = 0.0;  ///< σ, rad/s
  double torque_noise = 0.0;          ///< σ, N·m
  double gyro_noise_density = 0.0;    ///< rad/s/√Hz
  double gyro_bias = 0.0;             ///< σ of the per-axis bias, rad/s
  double accel_noise_density = 0.0;   ///< m/s²/√Hz
  double accel_bias = 0.0;            ///< σ of the per-axis bias, m/s²
  double orientation_noise = 0.0;     ///< σ (rad) of a random small rotation of the orientation
  double position_fix_rate = 0.0;     ///< Hz; 0: no fixes
  double position_fix_noise = 0.01;   ///< σ per axis, m
};

/// SensorNoise from a simulation plugin's settings, whose keys (and fields) have these names.
template <typename Settings>
SensorNoise sensorNoise(const Settings& s) {
  SensorNoise n;
  n.encoder_resolution = s.encoder_resolution;
  n.joint_velocity_noise = s.joint_velocity_noise;
  n.torque_noise = s.torque_noise;
  n.gyro_noise_density = s.imu_gyro_noise_density;
  n.gyro_bias = s.imu_gyro_bias;
  n.accel_noise_density = s.imu_accel_noise_density;
  n.accel_bias = s.imu_accel_bias;
  n.orientation_noise = s.imu_orientation_noise;
  n.position_fix_rate = s.position_fix_rate;
  n.position_fix_noise = s.position_fix_noise;
  return n;
}

/// The IMU's true values.
struct ImuTruth {
  double orientation[4] = {0, 0, 0, 1};  ///< world <- IMU, (x, y, z, w)
  double angular_velocity[3] = {};       ///< IMU frame, rad/s
  double specific_force[3] = {};         ///< IMU frame, m/s²
};

class SensorModel {
 public:
  void configure(const SensorNoise& noise, double period, std::uint64_t seed);
  /// Re-seeds the generators and draws the biases.
  void start();
  /// Turns a true sample into a measured one. On entry out.num_joints, out.q, out.dq, out.tau
  /// hold the true joint values and out.truth the true base (fixes are drawn around it); the
  /// joint values get their noise in place, out.imu and out.position_fix are filled from `imu`
  /// and the truth at simulated time `time`. out.time and out.sequence are the caller's.
  void sample(const ImuTruth& imu, double time, backend::Sensors& out);

 private:
  double gaussian(double sigma) { return sigma > 0.0 ? sigma * normal_(rng_) : 0.0; }

  std::uint64_t seed_ = 0;
  double encoderResolution_ = 0, velocityNoise_ = 0, torqueNoise_ = 0;
  double gyroSigma_ = 0, accelSigma_ = 0, gyroBiasSigma_ = 0, accelBiasSigma_ = 0;
  double orientationSigma_ = 0;
  double gyroBias_[3] = {}, accelBias_[3] = {};
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  double fixPeriod_ = 0.0, fixSigma_ = 0.0, nextFix_ = 0.0;
  std::mt19937_64 fixRng_;
  std::normal_distribution<double> fixNormal_{0.0, 1.0};
};

}  // namespace ballast::plugin
