#include "wbc/settings.hpp"

#include <cmath>
#include <cstdio>
#include <set>
#include <string>

#include "common/format.hpp"  // plugins/common

namespace ballast::wbc {

const char* toString(WbcVariant variant) {
  switch (variant) {
    case WbcVariant::kHierarchical: return "hierarchical";
    case WbcVariant::kWeighted: return "weighted";
  }
  return "unknown";
}

namespace {
bool positiveFinite(double x) { return std::isfinite(x) && x > 0.0; }
bool nonNegativeFinite(double x) { return std::isfinite(x) && x >= 0.0; }
}  // namespace

std::string validateSettings(const WbcSettings& s, const model::Model& model) {
  if (model.findFrame(s.baseFrame) < 0)
    return "wbc.base_frame: the model " + model.sourceFile + " has no frame '" + s.baseFrame + "'";
  if (model.frames[model.findFrame(s.baseFrame)].body != 0)
    return "wbc.base_frame: '" + s.baseFrame + "' is not attached to the floating base";
  if (s.contactFrames.empty()) return "wbc.contact_frames: needs at least one contact point";
  std::set<std::string> seen;
  for (const auto& name : s.contactFrames) {
    if (model.findFrame(name) < 0)
      return "wbc.contact_frames: the model " + model.sourceFile + " has no frame '" + name + "'";
    if (!seen.insert(name).second) return "wbc.contact_frames: '" + name + "' is listed twice";
  }
  seen.clear();
  for (const auto& name : s.jointSpaceJoints) {
    if (model.findJoint(name) < 0)
      return "wbc.joint_space_joints: the model " + model.sourceFile + " has no movable joint '" +
             name + "'";
    if (!seen.insert(name).second) return "wbc.joint_space_joints: '" + name + "' is listed twice";
  }
  const struct {
    const char* key;
    double value;
  } gains[] = {{"wbc.swing_kp", s.swingKp}, {"wbc.swing_kd", s.swingKd},
               {"wbc.joint_kp", s.jointKp}, {"wbc.joint_kd", s.jointKd}};
  for (const auto& g : gains)
    if (!nonNegativeFinite(g.value))
      return std::string(g.key) + ": must be a finite number ≥ 0, got " + formatNumber(g.value);
  for (int i = 0; i < 6; ++i) {
    if (!nonNegativeFinite(s.baseKp[i]))
      return "wbc.base_kp[" + std::to_string(i) + "]: must be ≥ 0, got " + formatNumber(s.baseKp[i]);
    if (!nonNegativeFinite(s.baseKd[i]))
      return "wbc.base_kd[" + std::to_string(i) + "]: must be ≥ 0, got " + formatNumber(s.baseKd[i]);
  }
  if (!positiveFinite(s.frictionCoefficient) || s.frictionCoefficient > 10.0)
    return "wbc.friction_coefficient: must be in (0, 10], got " + formatNumber(s.frictionCoefficient);
  if (!s.torqueLimit.empty()) {
    if (static_cast<int>(s.torqueLimit.size()) != model.nj())
      return "wbc.torque_limit: needs " + std::to_string(model.nj()) + " entries (one per joint), got " +
             std::to_string(s.torqueLimit.size());
    for (int j = 0; j < model.nj(); ++j)
      if (!positiveFinite(s.torqueLimit[j]))
        return "wbc.torque_limit[" + std::to_string(j) + "] (" + model.jointName[j + 1] +
               "): must be > 0, got " + formatNumber(s.torqueLimit[j]);
  } else {
    for (int j = 0; j < model.nj(); ++j)
      if (!positiveFinite(model.effortLimit[j]))
        return "wbc.torque_limit: not given and the model's effort limit of joint '" +
               model.jointName[j + 1] + "' is " + formatNumber(model.effortLimit[j]);
  }
  const struct {
    const char* key;
    double value;
  } weights[] = {{"wbc.limb_weight", s.limbWeight},
                 {"wbc.base_weight", s.baseWeight},
                 {"wbc.contact_force_weight", s.contactForceWeight}};
  for (const auto& w : weights)
    if (!nonNegativeFinite(w.value))
      return std::string(w.key) + ": must be a finite number ≥ 0, got " + formatNumber(w.value);
  if (!positiveFinite(s.regularization) || s.regularization > 1e-2)
    return "wbc.regularization: must be in (0, 0.01], got " + formatNumber(s.regularization);
  if (s.maxQpIterations < 1 || s.maxQpIterations > 100000)
    return "wbc.max_qp_iterations: must be in [1, 100000], got " + std::to_string(s.maxQpIterations);
  if (!positiveFinite(s.period) || s.period > 0.1)
    return "wbc.period: must be in (0, 0.1] s, got " + formatNumber(s.period);
  return "";
}

}  // namespace ballast::wbc
