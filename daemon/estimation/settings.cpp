#include "estimation/settings.hpp"

#include <cmath>
#include <cstdio>

#include "common/format.hpp"  // plugins/common

namespace ballast::estimation {

namespace {
using S = EstimatorSettings;

}  // namespace

const std::vector<EstimatorNumberKey>& estimatorNumberKeys() {
  static const std::vector<EstimatorNumberKey> keys{
      {"gyro_noise_density", &S::gyroNoiseDensity, 1e-7, 1.0, "rad/s/√Hz",
       "gyro white noise"},
      {"gyro_bias_random_walk", &S::gyroBiasRandomWalk, 0.0, 1.0, "rad/s/√s",
       "how fast the gyro bias may wander"},
      {"gyro_bias_initial", &S::gyroBiasInitial, 0.0, 1.0, "rad/s",
       "σ of the gyro bias before any measurement"},
      {"orientation_noise", &S::orientationNoise, 1e-6, 0.5, "rad",
       "σ of the IMU's orientation output per sample"},
      {"accelerometer_noise_density", &S::accelerometerNoiseDensity, 1e-6, 100.0, "m/s²/√Hz",
       "accelerometer white noise plus unmodelled accelerations (bias, vibration)"},
      {"kinematics_position_noise", &S::kinematicsPositionNoise, 1e-6, 1.0, "m",
       "σ of a contact point's position relative to the base from the joint encoders"},
      {"kinematics_velocity_noise", &S::kinematicsVelocityNoise, 1e-6, 10.0, "m/s",
       "σ of a contact point's velocity relative to the base from the joint encoders"},
      {"kinematics_velocity_gate", &S::kinematicsVelocityGate, 0.0, 100.0, "σ",
       "a stance point whose leg velocity is further from the prediction is slipping: swing for "
       "that tick (0: off)"},
      {"foot_height_noise", &S::footHeightNoise, 1e-6, 1.0, "m",
       "σ of a stance contact point's height above the terrain"},
      {"contact_drift_noise", &S::contactDriftNoise, 1e-6, 1.0, "m/√s",
       "how fast a stance contact point may slip"},
      {"swing_noise_scale", &S::swingNoiseScale, 1.0, 1e9, "",
       "variance multiplier for contact points in swing"},
      {"initial_position_noise", &S::initialPositionNoise, 1e-6, 100.0, "m",
       "σ of the base position at start"},
      {"initial_velocity_noise", &S::initialVelocityNoise, 1e-6, 100.0, "m/s",
       "σ of the base velocity at start"},
      {"contact_force_threshold", &S::contactForceThreshold, 0.0, 1e4, "N",
       "estimated normal force on the foot (all its contact points) that confirms a scheduled contact"},
      {"contact_force_release", &S::contactForceRelease, 0.0, 1.0, "",
       "fraction of the threshold below which a confirmed contact is released"},
      {"contact_force_bandwidth", &S::contactForceBandwidth, 0.1, 1e4, "1/s",
       "gain of the momentum observer that estimates the contact forces"},
  };
  return keys;
}

std::string validateSettings(const EstimatorSettings& s, const model::Model& model) {
  for (const EstimatorNumberKey& k : estimatorNumberKeys()) {
    const double x = s.*k.field;
    if (!std::isfinite(x) || x < k.min || x > k.max)
      return std::string("estimator.") + k.key + ": must be in [" + formatNumber(k.min) + ", " +
             formatNumber(k.max) + "]" + (k.unit[0] ? std::string(" ") + k.unit : std::string()) +
             ", got " + formatNumber(x);
  }
  if (!std::isfinite(s.period) || s.period <= 0.0 || s.period > 0.1)
    return "control.rate: the estimator needs a period in (0, 0.1] s, got " + formatNumber(s.period);

  const int imu = model.findFrame(s.imuFrame);
  if (imu < 0)
    return "robot.imu_frame: the model " + model.sourceFile + " has no frame '" + s.imuFrame + "'";
  if (model.frames[imu].body != 0)
    return "robot.imu_frame: '" + s.imuFrame + "' is not rigidly attached to the floating base '" +
           model.bodyName[0] + "'";
  for (int c = 0; c < kContactPoints; ++c) {
    const std::string& name = s.contactFrames[c];
    const int f = model.findFrame(name);
    if (f < 0)
      return "robot.contact_frames[" + std::to_string(c) + "]: the model " + model.sourceFile +
             " has no frame '" + name + "'";
    if (model.frames[f].body == 0)
      return "robot.contact_frames[" + std::to_string(c) + "]: '" + name +
             "' is on the floating base: a contact point must be on a leg";
    for (int d = 0; d < c; ++d)
      if (s.contactFrames[d] == name)
        return "robot.contact_frames[" + std::to_string(c) + "]: '" + name + "' is listed twice";
  }
  return "";
}

}  // namespace ballast::estimation
