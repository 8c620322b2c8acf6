// Frames (URDF links, contact points, the IMU): placement, velocity, classical acceleration and
// Jacobian. Results are LOCAL_WORLD_ALIGNED: at the frame origin, with world axes:
//   velocity     [ṗ (3); ω (3)]      of the frame origin, world axes
//   acceleration [p̈ (3); ω̇ (3)]      classical (not spatial) acceleration, world axes
//   Jacobian     J (6 x nv) with [ṗ; ω] = J v
// Velocity needs forwardKinematics(q, v); acceleration needs forwardKinematics(q, v, a). After
// forwardKinematicsBias(q, v) (a = 0) it is J̇·v, the bias term of contact and swing-foot tasks.
#pragma once

#include "model/data.hpp"
#include "model/joint.hpp"

namespace ballast::model {

template <typename S>
SE3<S> framePlacement(const Model& model, const Data<S>& data, int frame) {
  const Frame& f = model.frames[frame];
  return data.oMi[f.body] * f.placement.template cast<S>();
}

/// data.oMf for every frame (after forwardKinematics).
template <typename S>
void updateFramePlacements(const Model& model, Data<S>& data) {
  for (int k = 0; k < static_cast<int>(model.frames.size()); ++k)
    data.oMf[k] = framePlacement(model, data, k);
}

template <typename S>
Motion<S> frameVelocity(const Model& model, const Data<S>& data, int frame) {
  const Frame& f = model.frames[frame];
  const Mat3<S>& R = data.oMi[f.body].R;
  const Motion<S>& v = data.v[f.body];
  return Motion<S>{R * v.pointVelocity(f.placement.p.template cast<S>()), R * v.angular};
}

template <typename S>
Motion<S> frameClassicalAcceleration(const Model& model, const Data<S>& data, int frame) {
  const Frame& f = model.frames[frame];
  const Mat3<S>& R = data.oMi[f.body].R;
  const Motion<S>& v = data.v[f.body];
  const Motion<S>& a = data.a[f.body];
  const Vec3<S> r = f.placement.p.template cast<S>();
  const Vec3<S> lin = a.pointVelocity(r) + v.angular.cross(v.pointVelocity(r));
  return Motion<S>{R * lin, R * a.angular};
}

/// Jacobian of the frame (after forwardKinematics(q)). J has 6 rows ([ṗ; ω]) or 3 rows (ṗ only,
/// a point Jacobian); columns outside the frame's support are set to zero.
template <typename S, typename Out>
void frameJacobian(const Model& model, const Data<S>& data, int frame,
                   const Eigen::MatrixBase<Out>& J_) {
  auto& J = const_cast<Eigen::MatrixBase<Out>&>(J_);
  static_assert(Out::RowsAtCompileTime == 3 || Out::RowsAtCompileTime == 6 ||
                    Out::RowsAtCompileTime == Eigen::Dynamic,
                "a frame Jacobian has 3 or 6 rows");
  const bool withAngular = J.rows() == 6;
  J.setZero();
  const Vec3<S> p = framePlacement(model, data, frame).p;
  auto putColumn = [&](int col, const Motion<S>& worldMotion) {
    J.template block<3, 1>(0, col) = worldMotion.pointVelocity(p);
    if (withAngular) J.template block<3, 1>(3, col) = worldMotion.angular;
  };
  for (int i = model.frames[frame].body; i > 0; i = model.parent[i])
    putColumn(5 + i, data.oMi[i].act(jointSubspace<S>(model.jointType[i], model.jointAxis[i])));
  for (int k = 0; k < 6; ++k) {
    Motion<S> e;
    (k < 3 ? e.linear : e.angular)[k % 3] = S(1);
    putColumn(k, data.oMi[0].act(e));
  }
}

}  // namespace ballast::model
