#include "control/stand_posture.hpp"

#include <algorithm>
#include <cmath>

#include "model/base_conventions.hpp"
#include "model/forward_kinematics.hpp"
#include "model/frames.hpp"

namespace ballast::control {

using model::Mat3;
using model::SE3;
using model::Vec3;

StandPosture::StandPosture(const model::Model& model, const ControlSettings& settings)
    : model_(model),
      data_(model),
      qj_(model::VecX<double>::Zero(model.nj())),
      q_feet_(model::VecX<double>::Zero(model.nj())),
      J_(model::Mat6X<double>::Zero(6, model.nv)) {
  // Feet: the bodies carrying the contact frames, in order of first appearance.
  int numFeet = 0;
  int footBody[2] = {-1, -1};
  for (int c = 0; c < kNumContacts; ++c) {
    const int f = model.frameId(settings.contact_frames[c]);
    const int body = model.frames[f].body;
    if (body == footBody[0] || body == footBody[1]) {
      foot_of_contact_[c] = body == footBody[0] ? 0 : 1;
      continue;
    }
    if (numFeet == 2)
      throw model::ModelError(model.sourceFile +
                              ": the contact frames lie on more than two bodies; a standing "
                              "posture needs exactly two feet");
    footBody[numFeet] = body;
    foot_of_contact_[c] = numFeet;
    legs_[numFeet].frame = f;
    ++numFeet;
  }
  if (numFeet != 2)
    throw model::ModelError(model.sourceFile + ": the contact frames lie on " +
                            std::to_string(numFeet) + " body; a standing posture needs two feet");
  for (int l = 0; l < 2; ++l) {
    Leg& leg = legs_[l];
    for (int b = footBody[l]; b > 0; b = model.parent[b]) {
      if (leg.num_joints == kMaxLegJoints)
        throw model::ModelError(model.sourceFile + ": the leg of '" + model.frames[leg.frame].name +
                                "' has more than 8 joints");
      leg.joints[leg.num_joints++] = b - 1;
    }
    if (leg.num_joints == 0)
      throw model::ModelError(model.sourceFile + ": contact frame '" +
                              model.frames[leg.frame].name +
                              "' is on the base: no leg to stand on");
  }
  in_leg_.assign(model.nj(), 0);
  for (const Leg& leg : legs_)
    for (int k = 0; k < leg.num_joints; ++k) in_leg_[leg.joints[k]] = true;
  setNominal(settings);
}

void StandPosture::setNominal(const ControlSettings& settings) {
  for (int j = 0; j < model_.nj(); ++j) qj_[j] = settings.nominal_q[j];
  model::forwardKinematicsFromBase(model_, data_, SE3<double>{}, qj_);
  double zmin = 1e300;
  for (const std::string& name : settings.contact_frames)
    zmin = std::min(zmin, model::framePlacement(model_, data_, model_.frameId(name)).p.z());
  nominal_height_ = -zmin;
  const SE3<double> stanceFromBase{Mat3<double>::Identity(), Vec3<double>(0, 0, nominal_height_)};
  for (Leg& leg : legs_)
    leg.nominal_in_stance = stanceFromBase * model::framePlacement(model_, data_, leg.frame);
  if (anchored_)
    placeAnchor();
  else
    unanchor();
}

void StandPosture::unanchor() {
  for (Leg& leg : legs_) leg.target_in_stance = leg.nominal_in_stance;
  anchored_ = false;
}

namespace {
/// Heading of a frame: the angle of its x axis about the vertical (of its y axis, turned back a
/// quarter, when the x axis is near the vertical).
double heading(const Mat3<double>& R) {
  if (std::hypot(R(0, 0), R(1, 0)) > 1e-6) return std::atan2(R(1, 0), R(0, 0));
  return std::atan2(R(1, 1), R(0, 1)) - 0.5 * M_PI;
}
}  // namespace

void StandPosture::anchor(const Mat3<double>& worldFromBase, const double* qj, AnchorPart part) {
  // The feet in the level frame at the base: the base's rotation, not its position.
  for (int j = 0; j < model_.nj(); ++j) q_feet_[j] = qj[j];
  model::forwardKinematicsFromBase(model_, data_, SE3<double>{}, q_feet_);
  const SE3<double> levelFromBase{worldFromBase, Vec3<double>::Zero()};
  for (int l = 0; l < 2; ++l)
    legs_[l].anchor_in_level = levelFromBase * model::framePlacement(model_, data_, legs_[l].frame);
  if (part == AnchorPart::kWhole || !anchored_) {
    placeAnchor();
    return;
  }
  // Height and tilt only: each foot keeps its place along the ground and its heading.
  std::array<SE3<double>, 2> kept;
  for (int l = 0; l < 2; ++l) kept[l] = legs_[l].target_in_stance;
  placeAnchor();
  for (int l = 0; l < 2; ++l) {
    SE3<double>& target = legs_[l].target_in_stance;
    const Vec3<double> zyx = model::zyxFromRotation(target.R);
    const double keptHeading = model::zyxFromRotation(kept[l].R)[0];
    target.R = model::rotationFromZyx(Vec3<double>(keptHeading, zyx[1], zyx[2]));
    target.p.head<2>() = kept[l].p.head<2>();
  }
}

void StandPosture::placeAnchor() {
  const SE3<double>* feet[2] = {&legs_[0].anchor_in_level, &legs_[1].anchor_in_level};
  // Mean heading (of the headings' unit vectors) and position, the feet's and the nominal's.
  double s = 0.0, c = 0.0, sn = 0.0, cn = 0.0;
  Vec3<double> mean = Vec3<double>::Zero(), meanNominal = Vec3<double>::Zero();
  for (int l = 0; l < 2; ++l) {
    const double h = heading(feet[l]->R), hn = heading(legs_[l].nominal_in_stance.R);
    s += std::sin(h);
    c += std::cos(h);
    sn += std::sin(hn);
    cn += std::cos(hn);
    mean += 0.5 * feet[l]->p;
    meanNominal += 0.5 * legs_[l].nominal_in_stance.p;
  }
  const double yaw = std::atan2(s, c) - std::atan2(sn, cn);
  // levelFromStance: level, turned by yaw, the nominal feet's mean onto the feet's.
  SE3<double> levelFromStance{model::rotationFromZyx(Vec3<double>(yaw, 0, 0)),
                              Vec3<double>::Zero()};
  levelFromStance.p = mean - levelFromStance.R * meanNominal;
  level_from_stance_ = levelFromStance;
  const SE3<double> stanceFromLevel = levelFromStance.inverse();
  for (int l = 0; l < 2; ++l) legs_[l].target_in_stance = stanceFromLevel * *feet[l];
  anchored_ = true;
}

SE3<double> StandPosture::baseInStance(const Mat3<double>& worldFromBase) const {
  const SE3<double> levelFromBase{worldFromBase, Vec3<double>::Zero()};
  if (anchored_) return level_from_stance_.inverse() * levelFromBase;
  // Unanchored: the base over the nominal stance, turned and tilted as it is.
  return SE3<double>{worldFromBase, Vec3<double>(0, 0, nominal_height_)};
}

void StandPosture::warmStart(const double* qj) {
  for (const Leg& leg : legs_)
    for (int k = 0; k < leg.num_joints; ++k) qj_[leg.joints[k]] = qj[leg.joints[k]];
}

double StandPosture::solve(double height, double roll, double pitch, double yaw, int iterations,
                           double* q_out) {
  return solve(SE3<double>{model::rotationFromZyx(Vec3<double>(yaw, pitch, roll)),
                           Vec3<double>(0, 0, height)},
               iterations, q_out);
}

double StandPosture::solve(const SE3<double>& stanceFromBase, int iterations, double* q_out) {
  const SE3<double> baseFromStance = stanceFromBase.inverse();
  double worst = 0.0;
  for (int it = 0; it < iterations; ++it) {
    model::forwardKinematicsFromBase(model_, data_, SE3<double>{}, qj_);
    worst = 0.0;
    for (Leg& leg : legs_) {
      const SE3<double> target = baseFromStance * leg.target_in_stance;
      const SE3<double> current = model::framePlacement(model_, data_, leg.frame);
      model::Vec6<double> e;
      e.head<3>() = target.p - current.p;
      const Eigen::AngleAxisd aa(Mat3<double>(target.R * current.R.transpose()));
      e.tail<3>() = aa.axis() * aa.angle();
      worst = std::max(worst, e.norm());
      model::frameJacobian(model_, data_, leg.frame, J_);
      // Damped least squares on the leg's columns: dq = Jlᵀ (Jl Jlᵀ + λ²I)⁻¹ e.
      Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, kMaxLegJoints> Jl(6, leg.num_joints);
      for (int k = 0; k < leg.num_joints; ++k)
        Jl.col(k) = J_.col(model::Model::vIndexOfJoint(leg.joints[k]));
      model::Mat6<double> A = Jl * Jl.transpose();
      A.diagonal().array() += 1e-6;
      const model::Vec6<double> y = A.ldlt().solve(e);
      const Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxLegJoints, 1> dq = Jl.transpose() * y;
      for (int k = 0; k < leg.num_joints; ++k) {
        const int j = leg.joints[k];
        qj_[j] =
            std::clamp(qj_[j] + dq[k], model_.lowerPositionLimit[j], model_.upperPositionLimit[j]);
      }
    }
  }
  for (int j = 0; j < model_.nj(); ++j) q_out[j] = qj_[j];
  return worst;
}

}  // namespace ballast::control
