// From a validated profile and the robot model to the control loop's settings, with the checks
// that need the model: joint and frame names exist, every actuated joint is in exactly one
// group, every group has gains, the nominal posture is within the joint limits, and limits
// that come in pairs are ordered. Problems read like the loader's: "file:line:column: key: ...".
#pragma once

#include "control/settings.hpp"
#include "model/model.hpp"
#include "profile/profile.hpp"

namespace ballast::profile {

/// Throws ProfileError listing every problem.
control::ControlSettings buildSettings(const Profile& profile, const model::Model& model);

/// Loads the profile's robot.urdf; a model error becomes a ProfileError naming the key.
model::Model loadModel(const Profile& profile);

}  // namespace ballast::profile
