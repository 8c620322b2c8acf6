// One-degree-of-freedom joint models: the transform a joint adds and its motion subspace S.
// Both are expressed in the child body frame (the joint frame): q ↦ Rot(axis, q) or Trans(axis·q).
#pragma once

#include "model/model.hpp"

namespace ballast::model {

/// Transform of the child body relative to the joint frame at rest, for joint position qj.
template <typename S>
SE3<S> jointMotion(JointType type, const Vec3<double>& axis, const S& qj) {
  if (type == JointType::Prismatic) return SE3<S>{Mat3<S>::Identity(), axis.cast<S>() * qj};
  return SE3<S>{axisAngleRotation<S>(axis, qj), Vec3<S>::Zero()};
}

/// Unit motion of the joint (S), in the child body frame.
template <typename S>
Motion<S> jointSubspace(JointType type, const Vec3<double>& axis) {
  if (type == JointType::Prismatic) return Motion<S>{axis.cast<S>(), Vec3<S>::Zero()};
  return Motion<S>{Vec3<S>::Zero(), axis.cast<S>()};
}

/// Body i's placement in its parent for configuration q (i ≥ 1).
template <typename S, typename Q>
SE3<S> bodyInParent(const Model& model, int i, const Q& q) {
  return model.jointPlacement[i].template cast<S>() *
         jointMotion<S>(model.jointType[i], model.jointAxis[i], S(q[Model::qIndexOfJoint(i - 1)]));
}

/// Base placement in the world from q = [p, quaternion xyzw, ...].
template <typename S, typename Q>
SE3<S> basePlacement(const Q& q) {
  return SE3<S>{quaternionToRotation<S>(q.template segment<4>(3)), q.template head<3>()};
}

}  // namespace ballast::model
