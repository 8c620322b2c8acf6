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
      J_(model::Mat6X<double>::Zero(6, model.nv)) {
  // Feet: the bodies carrying the contact frames, in order of first appearance.
  int numFeet = 0;
  int footBody[2] = {-1, -1};
  for (const std::string& name : settings.contact_frames) {
    const int f = model.frameId(name);
    const int body = model.frames[f].body;
    if (body == footBody[0] || body == footBody[1]) continue;
    if (numFeet == 2)
      throw model::ModelError(model.sourceFile +
                              ": the contact frames lie on more than two bodies; a standing "
                              "posture needs exactly two feet");
    footBody[numFeet] = body;
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
    leg.target_in_stance = stanceFromBase * model::framePlacement(model_, data_, leg.frame);
}

double StandPosture::solve(double height, double roll, double pitch, double yaw, int iterations,
                           double* q_out) {
  const SE3<double> stanceFromBase{model::rotationFromZyx(Vec3<double>(yaw, pitch, roll)),
                                   Vec3<double>(0, 0, height)};
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
