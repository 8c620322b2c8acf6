#include "control/leg_odometry.hpp"

#include <algorithm>

#include "model/base_conventions.hpp"
#include "model/forward_kinematics.hpp"
#include "model/frames.hpp"

namespace ballast::control {

using model::Mat3;
using model::Vec3;

void fillRpy(BaseState& base) {
  const Mat3<double> R = model::quaternionToRotation<double>(base.orientation);
  const Vec3<double> rpy = model::rpyFromRotation(R);
  for (int i = 0; i < 3; ++i) base.rpy[i] = rpy[i];
}

LegOdometry::LegOdometry(const model::Model& model, const ControlSettings& settings)
    : model_(model),
      settings_(&settings),
      data_(model),
      q_(model::VecX<double>::Zero(model.nq)),
      v_(model::VecX<double>::Zero(model.nv)) {
  for (int c = 0; c < kNumContacts; ++c)
    contact_frame_[c] = model.frameId(settings.contact_frames[c]);
  const int imu = model.frameId(settings.imu_frame);
  if (model.frames[imu].body != 0)
    throw model::ModelError(model.sourceFile + ": IMU frame '" + settings.imu_frame +
                            "' must be on the floating base (body '" + model.bodyName[0] + "')");
  imu_in_base_ = model.frames[imu].placement.R;
}

void LegOdometry::update(const backend::Sensors& sensors, const double* q, const double* dq,
                         const double* tau, double dt, EstimatedState& out) {
  const int nj = model_.nj();
  const ControlSettings& s = *settings_;
  out.t = sensors.time;
  out.num_joints = nj;
  for (int j = 0; j < nj; ++j) {
    out.q[j] = q[j];
    out.dq[j] = dq[j];
    out.tau[j] = tau[j];
  }

  // Orientation and angular velocity (world) from the IMU.
  Vec3<double> omega = Vec3<double>::Zero();
  if (sensors.imu_valid) {
    const Mat3<double> Rwi = model::quaternionToRotation<double>(sensors.imu.orientation);
    rotation_ = Rwi * imu_in_base_.transpose();
    omega = Rwi * Vec3<double>(sensors.imu.angular_velocity);
  }

  // Contact points relative to the base origin, world axes, with the base at rest in translation.
  const Eigen::Quaterniond quat(rotation_);
  q_.head<3>().setZero();
  q_.segment<4>(3) << quat.x(), quat.y(), quat.z(), quat.w();
  v_.head<3>().setZero();
  v_.segment<3>(3) = rotation_.transpose() * omega;
  for (int j = 0; j < nj; ++j) {
    q_[model::Model::qIndexOfJoint(j)] = q[j];
    v_[model::Model::vIndexOfJoint(j)] = dq[j];
  }
  model::forwardKinematics(model_, data_, q_, v_);
  std::array<Vec3<double>, kNumContacts> r, rdot;
  double zmin = 1e300;
  for (int c = 0; c < kNumContacts; ++c) {
    r[c] = model::framePlacement(model_, data_, contact_frame_[c]).p;
    rdot[c] = model::frameVelocity(model_, data_, contact_frame_[c]).linear;
    zmin = std::min(zmin, r[c].z());
  }

  if (!initialised_) {
    position_ = Vec3<double>(0.0, 0.0, s.ground_height - zmin);
    velocity_.setZero();
    for (int c = 0; c < kNumContacts; ++c) {
      anchor_[c] = position_ + r[c];
      in_contact_[c] = r[c].z() < zmin + s.contact_height;
    }
    initialised_ = true;
  }

  if (s.use_truth && sensors.has_truth) {
    const backend::Truth& tr = sensors.truth;
    position_ = Vec3<double>(tr.base_position);
    velocity_ = Vec3<double>(tr.base_linear_velocity);
    rotation_ = model::quaternionToRotation<double>(tr.base_orientation);
    omega = Vec3<double>(tr.base_angular_velocity);
    for (int c = 0; c < kNumContacts; ++c) in_contact_[c] = tr.contact[c];
  } else {
    // Predict, then correct from the anchored contact points.
    Vec3<double> predicted = position_ + velocity_ * dt;
    int n = 0;
    Vec3<double> sumPosition = Vec3<double>::Zero(), sumVelocity = Vec3<double>::Zero();
    for (int c = 0; c < kNumContacts; ++c) {
      const bool contact = r[c].z() < zmin + s.contact_height;
      if (contact && !in_contact_[c]) anchor_[c] = predicted + r[c];
      in_contact_[c] = contact;
      if (!contact) continue;
      sumPosition += anchor_[c] - r[c];
      sumVelocity -= rdot[c];
      ++n;
    }
    if (n > 0) {
      position_ = sumPosition / n;
      velocity_ = sumVelocity / n;
    } else if (sensors.imu_valid) {
      const Vec3<double> f =
          rotation_ * imu_in_base_ * Vec3<double>(sensors.imu.linear_acceleration);
      velocity_ += (f + model_.gravity) * dt;
      position_ = predicted;
    }
  }

  BaseState& b = out.base;
  const Eigen::Quaterniond qb(rotation_);
  b.orientation[0] = qb.x();
  b.orientation[1] = qb.y();
  b.orientation[2] = qb.z();
  b.orientation[3] = qb.w();
  for (int i = 0; i < 3; ++i) {
    b.position[i] = position_[i];
    b.linear_velocity[i] = velocity_[i];
    b.angular_velocity[i] = omega[i];
  }
  fillRpy(b);
  for (int c = 0; c < kNumContacts; ++c) {
    out.contact[c] = in_contact_[c];
    for (int i = 0; i < 3; ++i) out.contact_position[c][i] = position_[i] + r[c][i];
  }
}

}  // namespace ballast::control
