// The planner's system dynamics, paper eq. (1): centroidal momentum with full kinematics.
//
//   x = [h_com (6), p_b (3), zyx_b (3), q_j (nj)]     nx = 12 + nj
//   u = [f_c1 .. f_cnc (3 each, world), v_j (nj)]     nu = 3·nc + nj
//   ẋ = [ Σf + m g ; Σ (p_ci − c) × f_ci ;  q̇_b = A_b⁻¹ (h_com − A_j v_j) ;  v_j ]
// h_com is [linear; angular about the CoM] with world axes (centroidal.hpp). q̇_b = [ṗ_b; d(zyx)/dt].
// A_b⁻¹ needs no 6x6 inverse: a locked robot moving with base velocity (ṗ, ω) has
// h = [m (ṗ + ω × (c − p)); I_G ω], solved for ṗ and ω, then ω mapped to ZYX rates.
#pragma once

#include <vector>

#include "model/base_conventions.hpp"
#include "model/center_of_mass.hpp"
#include "model/frames.hpp"

namespace ballast::model {

/// Index layout of the planner's state and input.
struct CentroidalLayout {
  int nj = 0;  ///< actuated joints
  int nc = 0;  ///< contact points
  static constexpr int kMomentum = 0;
  static constexpr int kBasePosition = 6;
  static constexpr int kBaseZyx = 9;
  static constexpr int kJoints = 12;
  int nx() const { return 12 + nj; }
  int nu() const { return 3 * nc + nj; }
  static int force(int contact) { return 3 * contact; }
  int jointVelocity() const { return 3 * nc; }
};

/// Writes ẋ = f(x, u) into xdot (nx). contactFrames lists the nc contact frames (model frames).
template <typename S, typename X, typename U, typename Out>
void centroidalDynamics(const Model& model, Data<S>& data, const std::vector<int>& contactFrames,
                        const Eigen::MatrixBase<X>& x, const Eigen::MatrixBase<U>& u,
                        const Eigen::MatrixBase<Out>& xdot_) {
  auto& xdot = const_cast<Eigen::MatrixBase<Out>&>(xdot_);
  const CentroidalLayout L{model.nj(), static_cast<int>(contactFrames.size())};
  const Vec3<S> p = x.template segment<3>(L.kBasePosition);
  const Vec3<S> zyx = x.template segment<3>(L.kBaseZyx);
  forwardKinematicsFromBase(model, data, SE3<S>{rotationFromZyx<S>(zyx), p},
                            x.segment(L.kJoints, L.nj));
  compositeWorldInertias(model, data);
  const Vec3<S>& c = data.com;
  const S m = data.mass;

  // Momentum change: contact forces and gravity.
  Vec3<S> force = m * model.gravity.cast<S>();
  Vec3<S> torque = Vec3<S>::Zero();
  for (int k = 0; k < L.nc; ++k) {
    const Vec3<S> f = u.template segment<3>(L.force(k));
    force += f;
    torque += (framePlacement(model, data, contactFrames[k]).p - c).cross(f);
  }

  // A_j v_j: momentum of the joint motion with the base held still, about the world origin.
  Force<S> hj;
  const auto vj = u.segment(L.jointVelocity(), L.nj);
  data.v[0] = Motion<S>{};
  for (int i = 1; i < model.nbodies(); ++i) {
    data.v[i] = data.liMi[i].actInv(data.v[model.parent[i]]) +
                jointSubspace<S>(model.jointType[i], model.jointAxis[i]) * S(vj[i - 1]);
    hj += data.oMi[i].act(model.inertia[i].template cast<S>() * data.v[i]);
  }
  const Vec3<S> hLin = x.template segment<3>(0) - hj.linear;
  const Vec3<S> hAng = x.template segment<3>(3) - hj.shiftedTo(c).angular;

  // Solve the locked-robot momentum for the base motion.
  const Mat3<S> IG = data.oYcrb[0].inertiaAboutCom();
  const Vec3<S> omega = IG.inverse() * hAng;  // 3x3 cofactor inverse: differentiable with Jet
  const Vec3<S> pdot = hLin / m + (c - p).cross(omega);

  xdot.template segment<3>(0) = force;
  xdot.template segment<3>(3) = torque;
  xdot.template segment<3>(L.kBasePosition) = pdot;
  xdot.template segment<3>(L.kBaseZyx) = angularVelocityToZyxRate<S>(zyx, omega);
  xdot.segment(L.kJoints, L.nj) = vj;
}

}  // namespace ballast::model
