// Inverse dynamics by the recursive Newton-Euler algorithm, and n(q, v).
//
//   rnea(model, data, q, v, a)         -> data.tau = M(q) a + n(q, v)   (nv)
//   nonLinearEffects(model, data, q, v) -> data.nle = n(q, v)            (nv)
// n holds Coriolis, centrifugal and gravity terms, with no contact forces. The base entries
// are the force and torque on the base in the base frame, [f; n]. Gravity is model.gravity.
// The joints' armature acts on their own acceleration only (armature · a_j; none in n).
#pragma once

#include "model/forward_kinematics.hpp"

namespace ballast::model {

namespace detail {
/// Shared body of rnea/nonLinearEffects; `a` may be a null pointer for zero accelerations.
template <typename S, typename Q, typename V, typename A>
void rneaPasses(const Model& model, Data<S>& data, const Eigen::MatrixBase<Q>& q,
                const Eigen::MatrixBase<V>& v, const A* a, VecX<S>& out) {
  forwardKinematics(model, data, q);
  const Mat3<S>& R0 = data.oMi[0].R;
  data.v[0] = Motion<S>{v.template head<3>(), v.template segment<3>(3)};
  // Gravity enters as an upward acceleration of the base.
  data.a_gf[0] = Motion<S>{-(R0.transpose() * model.gravity.cast<S>()), Vec3<S>::Zero()};
  if (a) data.a_gf[0] += Motion<S>{a->template head<3>(), a->template segment<3>(3)};

  for (int i = 0; i < model.nbodies(); ++i) {
    if (i > 0) {
      const int p = model.parent[i];
      const Motion<S> vJ = jointSubspace<S>(model.jointType[i], model.jointAxis[i]) * S(v[5 + i]);
      data.v[i] = data.liMi[i].actInv(data.v[p]) + vJ;
      data.a_gf[i] = data.liMi[i].actInv(data.a_gf[p]) + data.v[i].cross(vJ);
      if (a)
        data.a_gf[i] +=
            jointSubspace<S>(model.jointType[i], model.jointAxis[i]) * S((*a)[5 + i]);
    }
    const Inertia<S> I = model.inertia[i].template cast<S>();
    data.f[i] = I * data.a_gf[i] + crossForce(data.v[i], I * data.v[i]);
  }
  for (int i = model.nbodies() - 1; i > 0; --i) {
    out[5 + i] = dot(jointSubspace<S>(model.jointType[i], model.jointAxis[i]), data.f[i]);
    if (a) out[5 + i] += S(model.armature[i - 1]) * S((*a)[5 + i]);
    data.f[model.parent[i]] += data.liMi[i].act(data.f[i]);
  }
  out.template head<3>() = data.f[0].linear;
  out.template segment<3>(3) = data.f[0].angular;
}
}  // namespace detail

template <typename S, typename Q, typename V, typename A>
const VecX<S>& rnea(const Model& model, Data<S>& data, const Eigen::MatrixBase<Q>& q,
                    const Eigen::MatrixBase<V>& v, const Eigen::MatrixBase<A>& a) {
  detail::rneaPasses(model, data, q, v, &a, data.tau);
  return data.tau;
}

template <typename S, typename Q, typename V>
const VecX<S>& nonLinearEffects(const Model& model, Data<S>& data, const Eigen::MatrixBase<Q>& q,
                                const Eigen::MatrixBase<V>& v) {
  detail::rneaPasses(model, data, q, v, static_cast<const Eigen::MatrixBase<V>*>(nullptr),
                     data.nle);
  return data.nle;
}

}  // namespace ballast::model
