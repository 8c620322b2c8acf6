#include "profile/wbc_settings.hpp"

namespace ballast::profile {

wbc::WbcSettings wbcSettings(const Profile& p, const model::Model& model) {
  wbc::WbcSettings s;
  s.variant = p.text("wbc.variant") == "weighted" ? wbc::WbcVariant::kWeighted
                                                  : wbc::WbcVariant::kHierarchical;
  s.baseFrame = p.text("wbc.base_frame");
  const auto frames = p.strings("robot.contact_frames");
  s.contactFrames.assign(frames.begin(), frames.end());
  // Joint-space joints: URDF joints, or joint groups standing for their joints.
  const auto groups = p.groupMap("robot.joint_groups");
  s.jointSpaceJoints.clear();
  for (const std::string& name : p.strings("wbc.joint_space_joints")) {
    if (const auto g = groups.find(name); g != groups.end())
      s.jointSpaceJoints.insert(s.jointSpaceJoints.end(), g->second.begin(), g->second.end());
    else
      s.jointSpaceJoints.push_back(name);
  }
  s.swingKp = p.number("wbc.swing_kp");
  s.swingKd = p.number("wbc.swing_kd");
  s.jointKp = p.number("wbc.joint_kp");
  s.jointKd = p.number("wbc.joint_kd");
  const auto kp = p.numbers("wbc.base_kp"), kd = p.numbers("wbc.base_kd");
  for (int i = 0; i < 6; ++i) {
    s.baseKp[i] = kp[i];
    s.baseKd[i] = kd[i];
  }
  s.frictionCoefficient = p.number("wbc.friction_coefficient");
  const double scale = p.number("wbc.torque_limit_scale");
  s.torqueLimit.resize(model.nj());
  for (int j = 0; j < model.nj(); ++j) s.torqueLimit[j] = scale * model.effortLimit[j];
  s.limbWeight = p.number("wbc.limb_weight");
  s.baseWeight = p.number("wbc.base_weight");
  s.contactForceWeight = p.number("wbc.contact_force_weight");
  s.regularization = p.number("wbc.regularization");
  s.maxQpIterations = static_cast<int>(p.integer("wbc.max_qp_iterations"));
  s.period = 1.0 / p.number("control.rate");

  if (const std::string why = wbc::validateSettings(s, model); !why.empty()) {
    // "wbc.key[...]: what" -> the key's place in the profile. Keys the controller names that the
    // profile spells differently point at the profile's own key.
    std::string key = why.substr(0, why.find_first_of(":["));
    if (key == "wbc.contact_frames") key = "robot.contact_frames";
    if (key == "wbc.torque_limit") key = "wbc.torque_limit_scale";
    if (key == "wbc.period") key = "control.rate";
    if (!findKey(key)) key = "wbc.variant";
    throw ProfileError({p.problem(key, why.substr(why.find(':') + 2))});
  }
  return s;
}

}  // namespace ballast::profile
