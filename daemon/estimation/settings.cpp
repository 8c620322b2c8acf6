#include "estimation/settings.hpp"

#include <cmath>

#include "common/format.hpp"  // plugins/common

namespace ballast::estimation {

model::SettingsProblem validateSettings(const EstimatorSettings& s, const model::Model& model) {
  using S = EstimatorSettings;
  // What the filters need: σ > 0 where they divide by it or take its logarithm, ≥ 0 where 0
  // switches a term off. The profile's bounds (schema.cpp) are narrower.
  const struct {
    double S::*field;
    double min;
    bool open;  ///< min itself is refused
  } numbers[] = {
      {&S::gyroNoiseDensity, 0, true},          {&S::gyroBiasRandomWalk, 0, false},
      {&S::gyroBiasInitial, 0, false},          {&S::orientationNoise, 0, true},
      {&S::accelerometerNoiseDensity, 0, true}, {&S::kinematicsPositionNoise, 0, true},
      {&S::kinematicsVelocityNoise, 0, true},   {&S::kinematicsVelocityGate, 0, false},
      {&S::footHeightNoise, 0, true},           {&S::contactDriftNoise, 0, true},
      {&S::swingNoiseScale, 1, false},          {&S::initialPositionNoise, 0, true},
      {&S::initialVelocityNoise, 0, true},      {&S::contactForceThreshold, 0, false},
      {&S::contactForceRelease, 0, false},      {&S::contactForceReleaseTime, 0, false},
      {&S::contactForceBandwidth, 0, true},     {&S::contactForceRegularization, 0, true},
      {&S::externalForceBandwidth, 0, true},    {&S::externalForceDeadbandPerKg, 0, false},
  };
  for (const auto& n : numbers) {
    const double x = s.*n.field;
    if (!std::isfinite(x) || x < n.min || (n.open && x == n.min))
      return {&(s.*n.field), std::string("must be a finite number ") + (n.open ? "> " : "≥ ") +
                                 formatNumber(n.min) + ", got " + formatNumber(x)};
  }
  if (s.contactForceRelease > 1.0)
    return {&s.contactForceRelease,
            "must be at most 1 (a fraction of the threshold), got " + formatNumber(s.contactForceRelease)};
  if (!std::isfinite(s.period) || s.period <= 0.0 || s.period > 0.1)
    return {&s.period, "the estimator needs a period in (0, 0.1] s, got " + formatNumber(s.period)};

  const int imu = model.findFrame(s.imuFrame);
  if (imu < 0)
    return {&s.imuFrame, "the model " + model.sourceFile + " has no frame '" + s.imuFrame + "'"};
  if (model.frames[imu].body != 0)
    return {&s.imuFrame, "'" + s.imuFrame + "' is not rigidly attached to the floating base '" +
                             model.bodyName[0] + "'"};
  for (int c = 0; c < kContactPoints; ++c) {
    const std::string& name = s.contactFrames[c];
    const int f = model.findFrame(name);
    if (f < 0)
      return {&s.contactFrames[c], "the model " + model.sourceFile + " has no frame '" + name + "'"};
    if (model.frames[f].body == 0)
      return {&s.contactFrames[c],
              "'" + name + "' is on the floating base: a contact point must be on a leg"};
    for (int d = 0; d < c; ++d)
      if (s.contactFrames[d] == name) return {&s.contactFrames[c], "'" + name + "' is listed twice"};
  }
  return {};
}

}  // namespace ballast::estimation
