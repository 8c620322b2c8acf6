// Settings of the state estimator (state_estimator.hpp): which model frames it reads, the noise
// model of its two filters, and how it decides that a contact point is in stance. Filled by the
// profile schema (daemon/profile/schema.cpp: every key's bounds and default); validateSettings()
// checks what the filters need of them (finite, positive where they divide) and the frames
// against the model.
//
// Units: SI. A noise "density" is the standard deviation of a white noise times √s (per-sample
// σ = density / √period); a "noise" without "density" is a per-sample standard deviation.
#pragma once

#include <array>
#include <string>

#include "model/contact_points.hpp"
#include "model/model.hpp"
#include "model/settings_problem.hpp"

namespace ballast::estimation {

/// The contact points the filter state has 3 coordinates of.
inline constexpr int kContactPoints = model::kNumContacts;

struct EstimatorSettings {
  // The robot (names as in the URDF).
  std::string imuFrame;  ///< must be rigidly attached to the floating base
  std::array<std::string, kContactPoints> contactFrames;
  /// Control period, s: the time step when two samples' time stamps do not give a usable one.
  double period;

  // Attitude filter (orientation and gyro bias, attitude_filter.hpp).
  double gyroNoiseDensity;     ///< rad/s/√Hz
  double gyroBiasRandomWalk;   ///< rad/s/√s: how fast the gyro bias may wander
  double gyroBiasInitial;      ///< rad/s, σ of the bias before any measurement
  double orientationNoise;     ///< rad, σ of the IMU's orientation output per sample

  // Position/velocity filter (base_kalman_filter.hpp).
  /// m/s²/√Hz. The accelerometer's white noise plus what the filter does not model (the
  /// accelerometer bias, vibration, time-stamp jitter): larger than a datasheet's density. The
  /// accelerometer bias is no filter state: the stance legs' velocity pulls the estimate back
  /// within tens of ms, so a bias b shifts the velocity by only b·(that time), ~1 mm/s for 0.03 m/s².
  double accelerometerNoiseDensity;
  double kinematicsPositionNoise;  ///< m, σ of a contact point's position from the joints
  /// m/s, σ of a contact point's velocity from the joints. Not the encoders' noise alone: a
  /// stance foot rolls and creeps under load, most when a push loads it sideways (the default's
  /// reasons are beside its key in the schema).
  double kinematicsVelocityNoise;
  /// A stance point whose leg velocity is more than this many standard deviations from the
  /// filter's prediction is slipping or lifting off: it counts as swing for that tick (unless
  /// all stance points disagree). 0: off.
  double kinematicsVelocityGate;
  double footHeightNoise;          ///< m, σ of a stance point's height above the terrain
  double contactDriftNoise;        ///< m/√s, how fast a stance contact point may slip
  /// Variance multiplier for contact points in swing (de-weighting): a swing point is not
  /// measured; it is re-placed on the leg every tick with σ² = kinematicsPositionNoise²·scale
  /// and random-walks with contactDriftNoise²·scale, so nothing it did in swing pulls the base.
  double swingNoiseScale;
  double initialPositionNoise;  ///< m, σ of the base position at start
  double initialVelocityNoise;  ///< m/s, σ of the base velocity at start

  // Contact (contact_force_observer.hpp): stance = scheduled and, if contactForceCheck,
  // confirmed by the estimated normal force on the contact point's foot (toe and heel together).
  bool contactForceCheck;
  double contactForceThreshold;  ///< N: foot normal force that confirms a scheduled contact
  /// Fraction of the threshold below which a confirmed contact is released (hysteresis).
  double contactForceRelease;
  /// s: while the plan has a confirmed point in stance, its force must stay under the release
  /// level this long before the point is released (a landing's bounce, a stretched leg whose
  /// load the joints barely see, is not a lift-off). A point the plan has in swing is released
  /// at once. 0: released at the first tick under the release level.
  double contactForceReleaseTime;
  double contactForceBandwidth;  ///< 1/s, the momentum observer's gain (time constant 1/K)
  /// m², λ of each foot's least squares of the contact forces (contact_force_observer.hpp).
  double contactForceRegularization;
  /// External force (external_force_observer.hpp, same kind of observer): horizontal forces
  /// under this times the robot's mass read as none (model errors, which scale with the
  /// robot), larger ones are reported less that.
  double externalForceDeadbandPerKg;  ///< N/kg
  double externalForceBandwidth;  ///< 1/s, its observer's gain (time constant 1/K)
};

/// No problem if the settings fit the model and the filters; otherwise the field at fault and
/// what is wrong.
model::SettingsProblem validateSettings(const EstimatorSettings& settings, const model::Model& model);

}  // namespace ballast::estimation
