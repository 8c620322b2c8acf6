// Settings of the state estimator (state_estimator.hpp): which model frames it reads, the noise
// model of its two filters, and how it decides that a contact point is in stance. Filled by the
// profile module from the profile's `estimator` section; validateSettings() is the one place
// that checks them, against the bounds of estimatorNumberKeys() (each number key declared once,
// with its profile key, bounds, unit and meaning; the defaults are the initialisers below).
//
// Units: SI. A noise "density" is the standard deviation of a white noise times √s (per-sample
// σ = density / √period); a "noise" without "density" is a per-sample standard deviation.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "model/contact_points.hpp"
#include "model/model.hpp"

namespace ballast::estimation {

/// The contact points the filter state has 3 coordinates of.
inline constexpr int kContactPoints = model::kNumContacts;

struct EstimatorSettings {
  // The robot (names as in the URDF).
  std::string imuFrame = "imu";  ///< must be rigidly attached to the floating base
  std::array<std::string, kContactPoints> contactFrames{"left_toe", "left_heel", "right_toe",
                                                        "right_heel"};
  /// Control period, s: the time step when two samples' time stamps do not give a usable one.
  double period = 0.001;

  // Attitude filter (orientation and gyro bias, attitude_filter.hpp).
  double gyroNoiseDensity = 2.4e-4;     ///< rad/s/√Hz
  double gyroBiasRandomWalk = 1e-5;     ///< rad/s/√s: how fast the gyro bias may wander
  double gyroBiasInitial = 0.01;        ///< rad/s, σ of the bias before any measurement
  double orientationNoise = 0.005;      ///< rad, σ of the IMU's orientation output per sample

  // Position/velocity filter (base_kalman_filter.hpp).
  /// m/s²/√Hz. The accelerometer's white noise plus what the filter does not model (the
  /// accelerometer bias, vibration, time-stamp jitter): larger than a datasheet's density. The
  /// accelerometer bias is no filter state: the stance legs' velocity pulls the estimate back
  /// within tens of ms, so a bias b shifts the velocity by only b·(that time), ~1 mm/s for 0.03 m/s².
  double accelerometerNoiseDensity = 0.02;
  double kinematicsPositionNoise = 0.003;  ///< m, σ of a contact point's position from the joints
  /// m/s, σ of a contact point's velocity from the joints. Not the encoders' noise alone: a
  /// stance foot rolls and creeps under load, most when a push loads it sideways. At 0.05 the
  /// filter followed that creep and its velocity error during a 40 N push rose from 4 to
  /// 23 mm/s RMS (162 mm/s peak) and the walk sometimes fell where on ground truth it never
  /// did; at 0.2 the IMU carries the velocity over it (6 mm/s RMS, 19 mm/s peak).
  double kinematicsVelocityNoise = 0.2;
  /// A stance point whose leg velocity is more than this many standard deviations from the
  /// filter's prediction is slipping or lifting off: it counts as swing for that tick (unless
  /// all stance points disagree). 0: off.
  double kinematicsVelocityGate = 5.0;
  double footHeightNoise = 0.005;          ///< m, σ of a stance point's height above the terrain
  double contactDriftNoise = 0.002;        ///< m/√s, how fast a stance contact point may slip
  /// Variance multiplier for contact points in swing (de-weighting): a swing point is not
  /// measured; it is re-placed on the leg every tick with σ² = kinematicsPositionNoise²·scale
  /// and random-walks with contactDriftNoise²·scale, so nothing it did in swing pulls the base.
  double swingNoiseScale = 1e4;
  double initialPositionNoise = 0.01;  ///< m, σ of the base position at start
  double initialVelocityNoise = 0.1;   ///< m/s, σ of the base velocity at start

  // Contact (contact_force_observer.hpp): stance = scheduled and, if contactForceCheck,
  // confirmed by the estimated normal force on the contact point's foot (toe and heel together).
  bool contactForceCheck = true;
  double contactForceThreshold = 30.0;  ///< N: foot normal force that confirms a scheduled contact
  /// Fraction of the threshold below which a confirmed contact is released (hysteresis).
  double contactForceRelease = 0.5;
  double contactForceBandwidth = 50.0;  ///< 1/s, the momentum observer's gain (time constant 1/K)
};

/// A number of EstimatorSettings as the profile names it, with its bounds (inclusive).
struct EstimatorNumberKey {
  const char* key;  ///< profile key under `estimator.`, e.g. "gyro_noise_density"
  double EstimatorSettings::*field;
  double min, max;
  const char* unit;
  const char* doc;
};

/// Every number key, in documentation order (period is the loop's, `control.rate`, not listed).
const std::vector<EstimatorNumberKey>& estimatorNumberKeys();

/// "" if the settings fit the model, otherwise one message naming the field (the profile key,
/// e.g. "estimator.gyro_noise_density") and what is wrong.
std::string validateSettings(const EstimatorSettings& settings, const model::Model& model);

}  // namespace ballast::estimation
