// Position and velocity of a frame origin as functions of the planner's state and input
// (x, u of centroidal_dynamics.hpp), with their Jacobians: what the MPC's contact-point
// constraints need (stance: velocity zero; swing: velocity tracks a trajectory).
//
//   frameKinematicsZyx(model, data, frame, x, u, Ax, Bu, out)
//     out.position p (3, world), out.velocity v = ṗ (3, world),
//     out.dPosition_dx (3 x nx), out.dVelocity_dx (3 x nx), out.dVelocity_du (3 x nu)
// Preconditions: centroidalDynamicsDerivatives(model, data, ..., x, u, xdot, Ax, Bu) has just
// run on the same x, u (this reads data.oMi, data.oS, data.ov and its Ax, Bu).
//
// v = J(q)·q̇ with q̇ = [ṗ_b, ż_b, v_j] and ṗ_b, ż_b from eq. (1), so
//   ∂v/∂x = ∂(J ν)/∂q |ν fixed + J_b ∂q̇_b/∂x,   ∂v/∂u = J_b ∂q̇_b/∂u + J_j.
// Turning joint i rotates the bodies below it: the frame's body velocity changes by
// S_i × (V − V_parent(i)) and the point moves by S_i's velocity at it (world frame). The base
// angles turn the whole robot about the base origin and also change ω = E(zyx)·ż.
#pragma once

#include "model/centroidal_dynamics.hpp"

namespace ballast::model {

struct FrameKinematicsZyx {
  Vec3<double> position, velocity;
  Mat3X<double> dPosition_dx, dVelocity_dx, dVelocity_du;
  FrameKinematicsZyx(int nx, int nu)
      : dPosition_dx(3, nx), dVelocity_dx(3, nx), dVelocity_du(3, nu) {}
};

template <typename X, typename MA, typename MB>
void frameKinematicsZyx(const Model& model, const Data<double>& data, int frame,
                        const Eigen::MatrixBase<X>& x, const Eigen::MatrixBase<MA>& Ax,
                        const Eigen::MatrixBase<MB>& Bu, FrameKinematicsZyx& out) {
  const CentroidalLayout L{model.nj(), static_cast<int>((Bu.cols() - model.nj()) / 3)};
  const Vec3<double> p = x.template segment<3>(L.kBasePosition);
  const Vec3<double> zyx = x.template segment<3>(L.kBaseZyx);
  const Mat3<double> E = zyxRateToAngularVelocity<double>(zyx);
  const int body = model.frames[frame].body;
  const Vec3<double> pc = framePlacement(model, data, frame).p;
  const Motion<double>& V = data.ov[body];
  const Motion<double>& V0 = data.ov[0];
  out.position = pc;
  out.velocity = V.pointVelocity(pc);

  out.dPosition_dx.setZero();
  out.dVelocity_dx.setZero();
  out.dVelocity_du.setZero();
  // Point velocity change for a configuration change that moves the body velocity by dV and
  // the point by dp.
  auto dv = [&](const Motion<double>& dV, const Vec3<double>& dp) {
    return Vec3<double>(dV.pointVelocity(pc) + V.angular.cross(dp));
  };
  for (int i = body; i > 0; i = model.parent[i]) {
    const Motion<double>& S = data.oS[i];
    const Vec3<double> dp = S.pointVelocity(pc);
    const int col = L.kJoints + i - 1;
    out.dPosition_dx.col(col) = dp;
    out.dVelocity_dx.col(col) = dv(S.cross(V - data.ov[model.parent[i]]), dp);
    out.dVelocity_du.col(L.jointVelocity() + i - 1) = dp;  // J_j: the joint's own rate
  }
  const Vec3<double> zyxRate = angularVelocityToZyxRate<double>(zyx, V0.angular);
  for (int k = 0; k < 3; ++k) {
    const Vec3<double> e = E.col(k);
    const Motion<double> S{p.cross(e), e};  // turning about the base origin
    const Vec3<double> dOmega = zyxRateToAngularVelocityDerivative(zyx, k, zyxRate);
    const Vec3<double> dp = e.cross(pc - p);
    out.dPosition_dx.col(L.kBaseZyx + k) = dp;
    out.dVelocity_dx.col(L.kBaseZyx + k) =
        dv(S.cross(V - V0) + Motion<double>{p.cross(dOmega), dOmega}, dp);
  }
  out.dPosition_dx.template middleCols<3>(L.kBasePosition).setIdentity();

  // Through the base rates of eq. (1): J_b = ∂v/∂[ṗ_b, ż_b] = [I, −[p_c − p]× E].
  Eigen::Matrix<double, 3, 6> Jb;
  Jb.template leftCols<3>().setIdentity();
  Jb.template rightCols<3>() = -skew<double>(pc - p) * E;
  out.dVelocity_dx.noalias() += Jb * Ax.template middleRows<6>(L.kBasePosition);
  out.dVelocity_du.noalias() += Jb * Bu.template middleRows<6>(L.kBasePosition);
}

}  // namespace ballast::model
