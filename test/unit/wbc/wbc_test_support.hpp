// Whole-body controller fixtures: states that respect the stance constraints, and reference sets
// consistent with a chosen motion (the standing pose is test_support.hpp's).
#pragma once

#include <algorithm>
#include <random>
#include <vector>

#include <Eigen/Dense>

#include "model/algorithms.hpp"
#include "test/unit/test_support.hpp"
#include "wbc/whole_body_controller.hpp"

namespace ballast::test {

/// Stacked Jacobian (3·nc × nv) and J̇v of the contact points flagged in `which`.
inline void contactKinematics(const model::Model& m, const model::VecX<double>& q,
                              const model::VecX<double>& v, const std::vector<int>& frames,
                              Eigen::MatrixXd& J, Eigen::VectorXd& Jdv) {
  model::Data<double> d(m);
  model::forwardKinematicsBias(m, d, q, v);
  J.setZero(3 * frames.size(), m.nv);
  Jdv.setZero(3 * frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    model::frameJacobian(m, d, frames[i], J.middleRows(3 * i, 3));
    Jdv.segment<3>(3 * i) = model::frameClassicalAcceleration(m, d, frames[i]).linear;
  }
}

/// A motion ξ* = [v̇*; F*] and the state it starts from, such that the physics rows hold exactly:
/// stance points neither move nor accelerate, swing points carry no force, and the floating-base
/// rows of the dynamics hold, and a foot on both its points does not roll. v̇* is the random v̇₀ changed as little as possible: only where the
/// stance points or the contact forces cannot absorb it (in flight, or about the line through a
/// single foot's toe and heel); F* is the equal share of the weight changed as little as possible.
struct ConsistentMotion {
  model::VecX<double> q, v, vdot, F;
};

inline ConsistentMotion consistentMotion(const model::Model& m, const std::vector<int>& frames,
                                         const std::vector<bool>& stance, std::mt19937& rng,
                                         double speed = 0.2, double acceleration = 0.5,
                                         double jointNoise = 0.1) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int nc = static_cast<int>(frames.size()), nv = m.nv;
  int nStance = 0;
  for (int i = 0; i < nc; ++i) nStance += stance[i] ? 1 : 0;
  ConsistentMotion c;
  c.q = standingConfiguration(m);
  for (int j = 0; j < m.nj(); ++j) c.q[7 + j] += jointNoise * u(rng);
  // Velocity: random, projected so that stance points do not move.
  Eigen::MatrixXd J;
  Eigen::VectorXd Jdv;
  contactKinematics(m, c.q, Eigen::VectorXd::Zero(nv), frames, J, Jdv);
  Eigen::MatrixXd Js = Eigen::MatrixXd::Zero(3 * nc, nv);
  for (int i = 0; i < nc; ++i)
    if (stance[i]) Js.middleRows(3 * i, 3) = J.middleRows(3 * i, 3);
  const Eigen::VectorXd v0 = Eigen::VectorXd::NullaryExpr(nv, [&] { return speed * u(rng); });
  c.v = v0 - Js.completeOrthogonalDecomposition().solve(Js * v0);
  // At (q, v): G = J_bᵀ of the stance points (the wrenches contact forces can make).
  contactKinematics(m, c.q, c.v, frames, J, Jdv);
  model::Data<double> d(m);
  model::crba(m, d, c.q);
  model::nonLinearEffects(m, d, c.q, c.v);
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(6, 3 * nc);
  Eigen::VectorXd F0 = Eigen::VectorXd::Zero(3 * nc);
  for (int i = 0; i < nc; ++i)
    if (stance[i]) {
      G.middleCols(3 * i, 3) = J.block(3 * i, 0, 3, 6).transpose();
      F0[3 * i + 2] = m.totalMass() * 9.81 / nStance;
    }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(G, Eigen::ComputeFullU | Eigen::ComputeFullV);
  svd.setThreshold(1e-9);
  const Eigen::MatrixXd U0 = svd.matrixU().rightCols(6 - svd.rank());  // wrenches F cannot make
  // v̇: stance rows J_s v̇ = −J̇_s v; a foot on both its points does not roll about the line
  // through them; and U0ᵀ(M_b v̇ + n_b) = 0.
  std::vector<std::pair<int, int>> feet;
  for (int i = 0; i < nc; ++i)
    for (int k = i + 1; k < nc; ++k)
      if (stance[i] && stance[k] && m.frames[frames[i]].body == m.frames[frames[k]].body)
        feet.emplace_back(i, k);
  const int nFeet = static_cast<int>(feet.size());
  Eigen::MatrixXd R(3 * nc + nFeet + U0.cols(), nv);
  Eigen::VectorXd rhs(R.rows());
  for (int i = 0; i < nc; ++i) {
    if (stance[i]) Js.middleRows(3 * i, 3) = J.middleRows(3 * i, 3);
    rhs.segment<3>(3 * i) = stance[i] ? Eigen::Vector3d(-Jdv.segment<3>(3 * i)) : Eigen::Vector3d::Zero();
  }
  R.topRows(3 * nc) = Js;
  model::Data<double> dk(m);
  model::forwardKinematicsBias(m, dk, c.q, c.v);
  for (int f = 0; f < nFeet; ++f) {
    const auto [i, k] = feet[f];
    const Eigen::Vector3d axis = (model::framePlacement(m, dk, frames[i]).p -
                                  model::framePlacement(m, dk, frames[k]).p).normalized();
    Eigen::MatrixXd J6(6, nv);
    model::frameJacobian(m, dk, frames[i], J6);
    R.row(3 * nc + f) = axis.transpose() * J6.bottomRows(3);
    rhs[3 * nc + f] = -axis.dot(model::frameClassicalAcceleration(m, dk, frames[i]).angular);
  }
  R.bottomRows(U0.cols()) = U0.transpose() * d.M.topRows(6);
  rhs.tail(U0.cols()) = -U0.transpose() * d.nle.head(6);
  const Eigen::VectorXd a0 = Eigen::VectorXd::NullaryExpr(nv, [&] { return acceleration * u(rng); });
  c.vdot = a0 - R.completeOrthogonalDecomposition().solve(R * a0 - rhs);
  const Eigen::VectorXd wrench = d.M.topRows(6) * c.vdot + d.nle.head(6);
  c.F = F0 - svd.solve(G * F0 - wrench);
  return c;
}

/// Whether the stance forces of F lie inside the friction pyramid (with a margin, in N).
inline bool insidePyramid(const Eigen::VectorXd& F, const std::vector<bool>& stance, double mu,
                          double margin = 1.0) {
  for (std::size_t i = 0; i < stance.size(); ++i) {
    if (!stance[i]) continue;
    const Eigen::Vector3d f = F.segment<3>(3 * i);
    if (f.z() < margin || std::abs(f.x()) > mu * f.z() - margin || std::abs(f.y()) > mu * f.z() - margin)
      return false;
  }
  return true;
}

/// References under which ξ* of `c` meets every task exactly: positions and velocities equal the
/// state's (no feedback), accelerations and forces from ξ*.
inline void consistentReferences(const model::Model& m, const wbc::WholeBodyController& wbc,
                                 const ConsistentMotion& c, wbc::WbcReference& ref) {
  model::Data<double> d(m);
  model::forwardKinematicsBias(m, d, c.q, c.v);
  for (int i = 0; i < wbc.contactCount(); ++i) {
    const int f = wbc.contactFrames()[i];
    Eigen::MatrixXd J(3, m.nv);
    model::frameJacobian(m, d, f, J);
    ref.contactPosition.col(i) = model::framePlacement(m, d, f).p;
    ref.contactVelocity.col(i) = model::frameVelocity(m, d, f).linear;
    ref.contactAcceleration.col(i) = J * c.vdot + model::frameClassicalAcceleration(m, d, f).linear;
  }
  ref.jointPosition = c.q.tail(m.nj());
  ref.jointVelocity = c.v.tail(m.nj());
  ref.jointAcceleration = c.vdot.tail(m.nj());
  const int b = wbc.baseFrame();
  Eigen::MatrixXd Jb(6, m.nv);
  model::frameJacobian(m, d, b, Jb);
  const auto placement = model::framePlacement(m, d, b);
  const auto velocity = model::frameVelocity(m, d, b);
  const auto bias = model::frameClassicalAcceleration(m, d, b);
  ref.basePosition = placement.p;
  ref.baseOrientation = Eigen::Quaterniond(placement.R);
  ref.baseLinearVelocity = velocity.linear;
  ref.baseAngularVelocity = velocity.angular;
  const Eigen::VectorXd a = Jb * c.vdot;
  ref.baseLinearAcceleration = a.head<3>() + bias.linear;
  ref.baseAngularAcceleration = a.tail<3>() + bias.angular;
  ref.contactForce = c.F;
}

}  // namespace ballast::test
