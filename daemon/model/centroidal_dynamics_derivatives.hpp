// Analytic Jacobians of the planner's dynamics, paper eq. (1) (centroidal_dynamics.hpp):
//
//   centroidalDynamicsDerivatives(model, data, contacts, x, u, xdot, Ax, Bu[, derivatives])
//     xdot (nx) = f(x, u),  Ax (nx x nx) = ∂f/∂x,  Bu (nx x nu) = ∂f/∂u (left as they are
//     when derivatives is false)
// O(n) in the number of bodies, double precision, no allocation (data holds the scratch).
//
// The base rates solve A(q)·[q̇_b; v_j] = h, so ∂q̇_b/∂q = −A_b⁻¹ ∂(A(q) ν)/∂q at fixed
// ν = [q̇_b; v_j]. Turning joint j by dε rigidly turns its subtree about the joint's world axis
// S_j; with every generalised velocity fixed, the momentum about the world origin changes by
//     ∂h_O/∂q_j = S_j ×* h_sub(j) − Y_crb(j) (S_j × V_parent(j))
// where h_sub(j) is the subtree's momentum, Y_crb(j) its composite inertia and V_parent(j) the
// parent body's velocity (all world frame, about the origin). The base ZYX angles turn the whole
// robot about the base origin (axis E(zyx)_k) and also change ω = E(zyx)·ż. Checked against
// ceres::Jet and finite differences in test/unit/model/derivatives_test.cpp.
#pragma once

#include "model/centroidal_dynamics.hpp"

namespace ballast::model {

template <typename X, typename U, typename Xd, typename MA, typename MB>
void centroidalDynamicsDerivatives(const Model& model, Data<double>& data,
                                   const std::vector<int>& contactFrames,
                                   const Eigen::MatrixBase<X>& x, const Eigen::MatrixBase<U>& u,
                                   const Eigen::MatrixBase<Xd>& xdot_,
                                   const Eigen::MatrixBase<MA>& Ax_,
                                   const Eigen::MatrixBase<MB>& Bu_, bool derivatives = true) {
  auto& xdot = const_cast<Eigen::MatrixBase<Xd>&>(xdot_);
  auto& Ax = const_cast<Eigen::MatrixBase<MA>&>(Ax_);
  auto& Bu = const_cast<Eigen::MatrixBase<MB>&>(Bu_);
  const CentroidalLayout L{model.nj(), static_cast<int>(contactFrames.size())};
  const int nb = model.nbodies();

  const Vec3<double> p = x.template segment<3>(L.kBasePosition);
  const Vec3<double> zyx = x.template segment<3>(L.kBaseZyx);
  const auto vj = u.segment(L.jointVelocity(), L.nj);
  forwardKinematicsFromBase(model, data, SE3<double>{rotationFromZyx<double>(zyx), p},
                            x.segment(L.kJoints, L.nj));

  // World joint axes, body inertias, and velocities and momenta of the joint motion with the
  // base held still; then composite inertias and subtree momenta.
  for (int i = 0; i < nb; ++i) {
    data.oYcrb[i] = model.inertia[i].transformedBy(data.oMi[i]);
    if (i == 0) {
      data.ov[0] = Motion<double>{};
    } else {
      data.oS[i] = data.oMi[i].act(jointSubspace<double>(model.jointType[i], model.jointAxis[i]));
      data.ov[i] = data.ov[model.parent[i]] + data.oS[i] * vj[i - 1];
    }
    data.oh[i] = data.oYcrb[i] * data.ov[i];
  }
  for (int i = nb - 1; i > 0; --i) {
    data.oYcrb[model.parent[i]] += data.oYcrb[i];
    data.oh[model.parent[i]] += data.oh[i];
  }
  const Force<double> hj = data.oh[0];
  const double m = data.mass = data.oYcrb[0].mass;
  const Vec3<double> c = data.com = data.oYcrb[0].com();
  const Mat3<double> IGinv = data.oYcrb[0].inertiaAboutCom().inverse();
  const Mat3<double> E = zyxRateToAngularVelocity<double>(zyx);
  const Mat3<double> Einv = E.inverse();

  // Base motion from the momentum (centroidal_dynamics.hpp); A_b⁻¹ as a function.
  struct BaseRates {
    Vec3<double> pdot, omega;
  };
  auto solveBase = [&](const Vec3<double>& hLin, const Vec3<double>& hAngG) {
    const Vec3<double> omega = IGinv * hAngG;
    return BaseRates{hLin / m + (c - p).cross(omega), omega};
  };
  const Vec3<double> hLin = x.template segment<3>(0);
  const Vec3<double> hAngG = x.template segment<3>(3);
  const BaseRates base = solveBase(hLin - hj.linear, hAngG - hj.shiftedTo(c).angular);
  const Motion<double> V0{base.pdot - base.omega.cross(p), base.omega};

  // Add the base motion: full world velocities and subtree momenta.
  for (int i = 0; i < nb; ++i) {
    data.ov[i] += V0;
    data.oh[i] += data.oYcrb[i] * V0;
  }
  const Force<double>& hTotal = data.oh[0];

  // f(x, u).
  Vec3<double> force = m * model.gravity, torque = Vec3<double>::Zero();
  for (int k = 0; k < L.nc; ++k) {
    const Vec3<double> f = u.template segment<3>(L.force(k));
    force += f;
    torque += (framePlacement(model, data, contactFrames[k]).p - c).cross(f);
  }
  xdot.template segment<3>(0) = force;
  xdot.template segment<3>(3) = torque;
  xdot.template segment<3>(L.kBasePosition) = base.pdot;
  xdot.template segment<3>(L.kBaseZyx) = Einv * base.omega;
  xdot.segment(L.kJoints, L.nj) = vj;
  if (!derivatives) return;  // f alone (data.ov, data.oMi as with them): the SQP's line search
  Ax.setZero();
  Bu.setZero();

  // Writes −A_b⁻¹·(∂h_G) and the torque row's CoM term into column `col` of Ax.
  auto putConfigurationColumn = [&](int col, const Force<double>& dhO, const Vec3<double>& dc) {
    const Vec3<double> dhAngG = dhO.angular - c.cross(dhO.linear) - dc.cross(hTotal.linear);
    const BaseRates d = solveBase(-dhO.linear, -dhAngG);
    Ax.template block<3, 1>(L.kBasePosition, col) = d.pdot;
    Ax.template block<3, 1>(L.kBaseZyx, col) = Einv * d.omega;
    Vec3<double> dTorque = Vec3<double>::Zero();
    for (int k = 0; k < L.nc; ++k) dTorque -= dc.cross(u.template segment<3>(L.force(k)));
    Ax.template block<3, 1>(3, col) = dTorque;
  };
  for (int i = 1; i < nb; ++i) {
    const Motion<double>& S = data.oS[i];
    const Force<double> dhO = crossForce(S, data.oh[i]) -
                              data.oYcrb[i] * S.cross(data.ov[model.parent[i]]);
    putConfigurationColumn(L.kJoints + i - 1, dhO, (data.oYcrb[i] * S).linear / m);
  }
  const Vec3<double> zyxRate = Einv * base.omega;
  for (int k = 0; k < 3; ++k) {
    const Vec3<double> e = E.col(k);
    const Motion<double> S{p.cross(e), e};  // rotation about the base origin
    const Vec3<double> dOmega = zyxRateToAngularVelocityDerivative(zyx, k, zyxRate);
    const Force<double> dhO = crossForce(S, hTotal) - data.oYcrb[0] * S.cross(V0) +
                              data.oYcrb[0] * Motion<double>{p.cross(dOmega), dOmega};
    putConfigurationColumn(L.kBaseZyx + k, dhO, e.cross(c - p));
  }
  // Contact points move with every joint above them, and with the base rotation.
  for (int k = 0; k < L.nc; ++k) {
    const Vec3<double> f = u.template segment<3>(L.force(k));
    const Vec3<double> pc = framePlacement(model, data, contactFrames[k]).p;
    for (int i = model.frames[contactFrames[k]].body; i > 0; i = model.parent[i])
      Ax.template block<3, 1>(3, L.kJoints + i - 1) += data.oS[i].pointVelocity(pc).cross(f);
    for (int j = 0; j < 3; ++j)
      Ax.template block<3, 1>(3, L.kBaseZyx + j) += E.col(j).cross(pc - p).cross(f);
    // ∂/∂f: Σf and (p_c − c) × f.
    Bu.template block<3, 3>(0, L.force(k)).setIdentity();
    Bu.template block<3, 3>(3, L.force(k)) = skew<double>(pc - c);
  }
  // ∂/∂h: A_b⁻¹.
  for (int k = 0; k < 3; ++k) {
    Ax(L.kBasePosition + k, k) = 1.0 / m;
    const BaseRates d = solveBase(Vec3<double>::Zero(), Vec3<double>::Unit(k));
    Ax.template block<3, 1>(L.kBasePosition, 3 + k) = d.pdot;
    Ax.template block<3, 1>(L.kBaseZyx, 3 + k) = Einv * d.omega;
  }
  // ∂/∂v_j: −A_b⁻¹ A_j, and q̇_j = v_j.
  for (int i = 1; i < nb; ++i) {
    const Force<double> Aj = (data.oYcrb[i] * data.oS[i]).shiftedTo(c);
    const BaseRates d = solveBase(-Aj.linear, -Aj.angular);
    Bu.template block<3, 1>(L.kBasePosition, L.jointVelocity() + i - 1) = d.pdot;
    Bu.template block<3, 1>(L.kBaseZyx, L.jointVelocity() + i - 1) = Einv * d.omega;
    Bu(L.kJoints + i - 1, L.jointVelocity() + i - 1) = 1.0;
  }
}

}  // namespace ballast::model
