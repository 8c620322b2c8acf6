// What the robot's sensors report, from the world's true values: joint encoders (quantised,
// velocity noise), motor torques (noise), IMU (white noise + a per-axis bias drawn at start, a
// small random rotation on the orientation), ground truth flagged as such, and, when
// position_fix.rate > 0, a localisation source: the true base position with white noise, at
// that rate (what lidar scans matched against the map give a real robot).
//
// All randomness comes from one generator seeded with Config::seed and re-seeded by start(), so
// a lockstep run repeats bit for bit; a sample is drawn once per tick (reading twice does not
// draw twice). Noise σ per sample = density / √period (white noise sampled at the tick rate).
#pragma once

#include <cstdint>
#include <random>

#include "backend_abi.hpp"
#include "sim_settings.hpp"
#include "simbody_world.hpp"

namespace ballast::simbody {

class SensorModel {
 public:
  void configure(const SimSettings& settings, double period, std::uint64_t seed);
  /// Re-seeds the generator and draws the biases.
  void start();
  /// Fills every field of `out` but time and sequence from the world's current state.
  void sample(const SimbodyWorld& world, backend::Sensors& out);

 private:
  double gaussian(double sigma) { return sigma > 0.0 ? sigma * normal_(rng_) : 0.0; }

  std::uint64_t seed_ = 0;
  double encoderResolution_ = 0, velocityNoise_ = 0, torqueNoise_ = 0;
  double gyroSigma_ = 0, accelSigma_ = 0, gyroBiasSigma_ = 0, accelBiasSigma_ = 0;
  double orientationSigma_ = 0;
  SimTK::Vec3 gyroBias_{0}, accelBias_{0};
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  // Position fixes draw from their own generator: turning them on changes no other reading.
  double fixPeriod_ = 0.0, fixSigma_ = 0.0, nextFix_ = 0.0;
  std::mt19937_64 fixRng_;
  std::normal_distribution<double> fixNormal_{0.0, 1.0};
};

}  // namespace ballast::simbody
