#include "wbc/settings.hpp"

#include <cmath>
#include <set>
#include <string>

#include "common/format.hpp"  // plugins/common

namespace ballast::wbc {

const char* toString(WbcVariant variant) {
  switch (variant) {
    case WbcVariant::kHierarchical: return "hierarchical";
    case WbcVariant::kWeighted: return "weighted";
    case WbcVariant::kInverseDynamics: return "inverse_dynamics";
  }
  return "unknown";
}

namespace {
bool positiveFinite(double x) { return std::isfinite(x) && x > 0.0; }
bool nonNegativeFinite(double x) { return std::isfinite(x) && x >= 0.0; }
}  // namespace

model::SettingsProblem validateSettings(const WbcSettings& s, const model::Model& model) {
  using Problem = model::SettingsProblem;
  if (model.findFrame(s.baseFrame) < 0)
    return Problem{&s.baseFrame, "the model " + model.sourceFile + " has no frame '" + s.baseFrame + "'"};
  if (model.frames[model.findFrame(s.baseFrame)].body != 0)
    return Problem{&s.baseFrame, "'" + s.baseFrame + "' is not attached to the floating base"};
  if (s.contactFrames.empty()) return Problem{&s.contactFrames, "needs at least one contact point"};
  std::set<std::string> seen;
  for (const auto& name : s.contactFrames) {
    if (model.findFrame(name) < 0)
      return Problem{&s.contactFrames, "the model " + model.sourceFile + " has no frame '" + name + "'"};
    if (!seen.insert(name).second) return Problem{&s.contactFrames, "'" + name + "' is listed twice"};
  }
  seen.clear();
  for (const auto& name : s.jointSpaceJoints) {
    if (model.findJoint(name) < 0)
      return Problem{&s.jointSpaceJoints,
                     "the model " + model.sourceFile + " has no movable joint '" + name + "'"};
    if (!seen.insert(name).second) return Problem{&s.jointSpaceJoints, "'" + name + "' is listed twice"};
  }
  for (const double* gain : {&s.swingKp, &s.swingKd, &s.jointKp, &s.jointKd})
    if (!nonNegativeFinite(*gain))
      return Problem{gain, "must be a finite number ≥ 0, got " + formatNumber(*gain)};
  for (int i = 0; i < 6; ++i) {
    if (!nonNegativeFinite(s.baseKp[i]))
      return Problem{&s.baseKp[i], "element " + std::to_string(i + 1) + " must be ≥ 0, got " +
                                       formatNumber(s.baseKp[i])};
    if (!nonNegativeFinite(s.baseKd[i]))
      return Problem{&s.baseKd[i], "element " + std::to_string(i + 1) + " must be ≥ 0, got " +
                                       formatNumber(s.baseKd[i])};
  }
  if (!positiveFinite(s.frictionCoefficient) || s.frictionCoefficient > 10.0)
    return Problem{&s.frictionCoefficient, "must be in (0, 10], got " + formatNumber(s.frictionCoefficient)};
  if (!s.torqueLimit.empty()) {
    if (static_cast<int>(s.torqueLimit.size()) != model.nj())
      return Problem{&s.torqueLimit, "needs " + std::to_string(model.nj()) +
                                         " torque limits (one per joint), got " +
                                         std::to_string(s.torqueLimit.size())};
    for (int j = 0; j < model.nj(); ++j)
      if (!positiveFinite(s.torqueLimit[j]))
        return Problem{&s.torqueLimit, "the torque limit of joint '" + model.jointName[j + 1] +
                                           "' must be > 0, got " + formatNumber(s.torqueLimit[j])};
  } else {
    for (int j = 0; j < model.nj(); ++j)
      if (!positiveFinite(model.effortLimit[j]))
        return Problem{&s.torqueLimit, "no torque limits given and the model's effort limit of joint '" +
                                           model.jointName[j + 1] + "' is " +
                                           formatNumber(model.effortLimit[j])};
  }
  for (const double* weight : {&s.limbWeight, &s.baseWeight, &s.contactForceWeight})
    if (!nonNegativeFinite(*weight))
      return Problem{weight, "must be a finite number ≥ 0, got " + formatNumber(*weight)};
  if (!positiveFinite(s.regularization) || s.regularization > 1e-2)
    return Problem{&s.regularization, "must be in (0, 0.01], got " + formatNumber(s.regularization)};
  if (s.maxQpIterations < 1 || s.maxQpIterations > 100000)
    return Problem{&s.maxQpIterations,
                   "must be in [1, 100000], got " + std::to_string(s.maxQpIterations)};
  if (!positiveFinite(s.period) || s.period > 0.1)
    return Problem{&s.period, "the control period must be in (0, 0.1] s, got " + formatNumber(s.period)};
  return {};
}

}  // namespace ballast::wbc
