// Forward kinematics: placement, spatial velocity and spatial acceleration of every body.
//
//   forwardKinematics(model, data, q)        -> data.liMi, data.oMi
//   forwardKinematics(model, data, q, v)     -> + data.v  (body velocities, body frames)
//   forwardKinematics(model, data, q, v, a)  -> + data.a  (body accelerations, body frames)
//   forwardKinematicsBias(model, data, q, v)  = forwardKinematics(q, v, 0), without a zero vector
// q (nq), v and a (nv) follow model.hpp. data.a is the spatial acceleration d/dt v_i in body
// coordinates without gravity; the classical acceleration of a point is in frames.hpp.
// The overload taking a base placement and the joint positions serves callers that hold the
// base pose in other coordinates (ZYX Euler in the planner).
#pragma once

#include "model/data.hpp"
#include "model/joint.hpp"

namespace ballast::model {

/// Body placements from the base placement oM0 and the joint positions qj (nj).
template <typename S, typename QJ>
void forwardKinematicsFromBase(const Model& model, Data<S>& data, const SE3<S>& oM0,
                               const Eigen::MatrixBase<QJ>& qj) {
  data.liMi[0] = oM0;
  data.oMi[0] = oM0;
  for (int i = 1; i < model.nbodies(); ++i) {
    data.liMi[i] = model.jointPlacement[i].template cast<S>() *
                   jointMotion<S>(model.jointType[i], model.jointAxis[i], S(qj[i - 1]));
    data.oMi[i] = data.oMi[model.parent[i]] * data.liMi[i];
  }
}

template <typename S, typename Q>
void forwardKinematics(const Model& model, Data<S>& data, const Eigen::MatrixBase<Q>& q) {
  forwardKinematicsFromBase(model, data, basePlacement<S>(q.derived()),
                            q.derived().tail(model.nj()));
}

/// Body velocities (body frames) after placements are known; v = [v_b, ω_b, q̇_j].
template <typename S, typename V>
void propagateVelocities(const Model& model, Data<S>& data, const Eigen::MatrixBase<V>& v) {
  data.v[0] = Motion<S>{v.template head<3>(), v.template segment<3>(3)};
  for (int i = 1; i < model.nbodies(); ++i) {
    data.v[i] = data.liMi[i].actInv(data.v[model.parent[i]]) +
                jointSubspace<S>(model.jointType[i], model.jointAxis[i]) * S(v[5 + i]);
  }
}

template <typename S, typename Q, typename V>
void forwardKinematics(const Model& model, Data<S>& data, const Eigen::MatrixBase<Q>& q,
                       const Eigen::MatrixBase<V>& v) {
  forwardKinematics(model, data, q);
  propagateVelocities(model, data, v);
}

namespace detail {
/// Acceleration pass after velocities; `a` may be a null pointer for zero accelerations.
template <typename S, typename V, typename A>
void propagateAccelerations(const Model& model, Data<S>& data, const Eigen::MatrixBase<V>& v,
                            const A* a) {
  data.a[0] = a ? Motion<S>{a->template head<3>(), a->template segment<3>(3)} : Motion<S>{};
  for (int i = 1; i < model.nbodies(); ++i) {
    const Motion<S> Si = jointSubspace<S>(model.jointType[i], model.jointAxis[i]);
    data.a[i] = data.liMi[i].actInv(data.a[model.parent[i]]) + data.v[i].cross(Si * S(v[5 + i]));
    if (a) data.a[i] += Si * S((*a)[5 + i]);
  }
}
}  // namespace detail

template <typename S, typename Q, typename V, typename A>
void forwardKinematics(const Model& model, Data<S>& data, const Eigen::MatrixBase<Q>& q,
                       const Eigen::MatrixBase<V>& v, const Eigen::MatrixBase<A>& a) {
  forwardKinematics(model, data, q, v);
  detail::propagateAccelerations(model, data, v, &a);
}

/// forwardKinematics(q, v, 0): data.a holds the velocity-product (bias) accelerations, from
/// which frames.hpp gives J̇·v.
template <typename S, typename Q, typename V>
void forwardKinematicsBias(const Model& model, Data<S>& data, const Eigen::MatrixBase<Q>& q,
                           const Eigen::MatrixBase<V>& v) {
  forwardKinematics(model, data, q, v);
  detail::propagateAccelerations(model, data, v, static_cast<const Eigen::MatrixBase<V>*>(nullptr));
}

}  // namespace ballast::model
