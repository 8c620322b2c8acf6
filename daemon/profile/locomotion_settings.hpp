// The planner's settings (locomotion/locomotion_planner.hpp LocomotionSettings: gait, swing
// trajectories, footholds, MPC weights and constraints, SQP) from a profile's `gait` and
// `planner` sections, the robot's nominal posture and the whole-body controller's joint-space
// joints (the arms: the planner weighs them apart from the legs).
#pragma once

#include "control/settings.hpp"
#include "locomotion/locomotion_planner.hpp"
#include "model/model.hpp"
#include "profile/profile.hpp"
#include "wbc/settings.hpp"

namespace ballast::profile {

/// `control` supplies the nominal posture (model order) and `nominalHeight` the base height
/// standing in it. Throws ProfileError.
locomotion::LocomotionSettings locomotionSettings(const Profile& profile, const model::Model& model,
                                                  const control::ControlSettings& control,
                                                  const wbc::WbcSettings& wbc,
                                                  double nominalHeight);

}  // namespace ballast::profile
