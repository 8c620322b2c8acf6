// The whole-body controller's settings (wbc/settings.hpp) from a profile's `wbc` section and
// robot.contact_frames / robot.joint_groups, checked by the controller's own validateSettings()
// with its message placed at the key's file:line:column.
#pragma once

#include "model/model.hpp"
#include "profile/profile.hpp"
#include "wbc/settings.hpp"

namespace ballast::profile {

/// Throws ProfileError. period is the control period (1 / control.rate).
wbc::WbcSettings wbcSettings(const Profile& profile, const model::Model& model);

}  // namespace ballast::profile
