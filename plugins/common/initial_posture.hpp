// The posture a simulated robot starts in (the backends' initial_posture and initial_joints
// keys), so every simulation backend starts the same robot the same way.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "settings_schema.hpp"

namespace ballast::plugin {

/// Joint angles in the order of `joints` (movable joints): "stand" puts *hip_pitch at -0.4,
/// *knee at 0.8 and *ankle_pitch at -(hip_pitch + knee) so the soles are level, others 0;
/// "zero" all 0; `overrides` (joint -> rad) replace single joints. Throws std::runtime_error
/// naming the key (where.where("initial_joints.<joint>")) for an unknown joint or an angle
/// outside the joint's limits.
std::vector<double> initialPosture(const std::vector<std::string>& joints,
                                   const std::map<std::string, std::pair<double, double>>& limits,
                                   const std::string& posture, const schema::NamedNumbers& overrides,
                                   const schema::Locations& where, const std::string& urdfPath);

}  // namespace ballast::plugin
