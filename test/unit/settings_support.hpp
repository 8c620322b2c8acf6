// The settings the tests run on. The profile schema (daemon/profile/schema.cpp) holds every
// default; nothing else declares them. simFlat(): the shipped default profile on the humanoid, as
// ballastd builds it (the joint groups resolved: the arms are the controller's joint-space
// joints); controlDefaults(): the schema's defaults alone.
#pragma once

#include <string>

#include "profile/settings.hpp"
#include "test/unit/test_support.hpp"

namespace ballast::test {

inline const profile::Settings& simFlat() {
  static const profile::Settings s = profile::settingsFor(
      profile::Profile::load(std::string(BALLAST_SOURCE_DIR) + "/profiles/sim-flat.yaml"),
      humanoid());
  return s;
}

inline const control::ControlSettings& controlDefaults() {
  static const control::ControlSettings c = profile::defaultSettings().control;
  return c;
}

/// The default profile's whole-body controller, estimator and planner settings.
inline wbc::WbcSettings wbcSettings() { return simFlat().control.wbc; }
inline estimation::EstimatorSettings estimatorSettings() { return simFlat().control.estimator; }
inline locomotion::LocomotionSettings locomotionSettings() { return simFlat().control.locomotion; }

}  // namespace ballast::test
