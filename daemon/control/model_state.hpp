// The estimated state in the model's coordinates (model.hpp): q = [base position (world),
// quaternion (x, y, z, w) world <- base, q_j], v = [base linear velocity, ω (both in the base
// frame), q̇_j]. EstimatedState keeps base velocities in the world frame.
#pragma once

#include <Eigen/Core>

#include "control/types.hpp"
#include "model/base_conventions.hpp"
#include "model/model.hpp"

namespace ballast::control {

/// q (nq) and v (nv) must be sized; no allocation.
inline void toModelState(const model::Model& model, const EstimatedState& state, Eigen::VectorXd& q,
                         Eigen::VectorXd& v) {
  const BaseState& b = state.base;
  const model::Mat3<double> R = model::quaternionToRotation<double>(b.orientation);
  q.head<3>() = Eigen::Map<const Eigen::Vector3d>(b.position);
  q.segment<4>(3) = Eigen::Map<const Eigen::Vector4d>(b.orientation).normalized();
  v.head<3>().noalias() = R.transpose() * Eigen::Map<const Eigen::Vector3d>(b.linear_velocity);
  v.segment<3>(3).noalias() = R.transpose() * Eigen::Map<const Eigen::Vector3d>(b.angular_velocity);
  for (int j = 0; j < model.nj(); ++j) {
    q[model::Model::qIndexOfJoint(j)] = state.q[j];
    v[model::Model::vIndexOfJoint(j)] = state.dq[j];
  }
}

}  // namespace ballast::control
