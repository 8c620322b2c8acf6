// Centroidal momentum (Orin, Goswami & Lee 2013): h_G = A(q) v, and its bias Ȧ(q, v) v.
//
//   ccrba(model, data, q, v)               -> data.Ag (6 x nv), data.hg, data.com, data.mass
//   centroidalMomentumBias(model, data, q, v) -> data.dhg = Ȧ v (6), data.hg, data.com
// h_G = [linear momentum; angular momentum about the CoM], both with world axes — the order of
// the paper's h_com. v is the model's velocity (base block in the base frame, model.hpp);
// ZYX-Euler base coordinates are mapped in base_conventions.hpp. Ȧ v is the rate of h_G when
// v̇ = 0, i.e. ḣ_G = A v̇ + Ȧ v.
#pragma once

#include "model/center_of_mass.hpp"

namespace ballast::model {

template <typename S, typename Q, typename V>
const Mat6X<S>& ccrba(const Model& model, Data<S>& data, const Eigen::MatrixBase<Q>& q,
                      const Eigen::MatrixBase<V>& v) {
  forwardKinematics(model, data, q);
  compositeWorldInertias(model, data);
  const Vec3<S>& c = data.com;
  auto putColumn = [&](int col, const Inertia<S>& Y, const Motion<S>& worldMotion) {
    const Force<S> h = (Y * worldMotion).shiftedTo(c);
    data.Ag.template block<3, 1>(0, col) = h.linear;
    data.Ag.template block<3, 1>(3, col) = h.angular;
  };
  for (int i = 1; i < model.nbodies(); ++i)
    putColumn(5 + i, data.oYcrb[i],
              data.oMi[i].act(jointSubspace<S>(model.jointType[i], model.jointAxis[i])));
  for (int k = 0; k < 6; ++k) {
    Motion<S> e;
    (k < 3 ? e.linear : e.angular)[k % 3] = S(1);
    putColumn(k, data.oYcrb[0], data.oMi[0].act(e));
  }
  data.hg.noalias() = data.Ag * v;
  return data.Ag;
}

template <typename S, typename Q, typename V>
const Vec6<S>& centroidalMomentumBias(const Model& model, Data<S>& data,
                                      const Eigen::MatrixBase<Q>& q,
                                      const Eigen::MatrixBase<V>& v) {
  forwardKinematicsBias(model, data, q, v);
  compositeWorldInertias(model, data);
  // Net force on each body = rate of its momentum; summed in the world about the fixed origin.
  Force<S> h, dh;
  for (int i = 0; i < model.nbodies(); ++i) {
    const Inertia<S> I = model.inertia[i].template cast<S>();
    const Force<S> hi = I * data.v[i];
    h += data.oMi[i].act(hi);
    dh += data.oMi[i].act(I * data.a[i] + crossForce(data.v[i], hi));
  }
  // About the moving CoM: d/dt(c × p) adds ċ × m ċ = 0, so only the shift remains.
  data.hg << h.linear, h.shiftedTo(data.com).angular;
  data.dhg << dh.linear, dh.shiftedTo(data.com).angular;
  return data.dhg;
}

}  // namespace ballast::model
