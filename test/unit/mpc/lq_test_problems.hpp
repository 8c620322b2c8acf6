// Random linear-quadratic problems and their solution by one direct KKT solve, the reference
// for the Riccati solver and the SQP.
#pragma once

#include <Eigen/Dense>
#include <gtest/gtest.h>
#include <random>
#include <vector>

#include "mpc/lq_problem.hpp"

namespace ballast::mpc::testing {

/// Stage k: random dynamics, a PSD cost with cross terms, `eqAt(k)` equality rows.
template <typename EqCount>
std::vector<LqNode> randomLqProblem(int N, int nx, int nu, int maxEq, EqCount eqAt,
                                    std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  auto rnd = [&](int r, int c) { return Eigen::MatrixXd::NullaryExpr(r, c, [&] { return n(rng); }); };
  std::vector<LqNode> nodes(N + 1, LqNode(nx, nu, maxEq));
  for (int k = 0; k <= N; ++k) {
    LqNode& s = nodes[k];
    const Eigen::MatrixXd L = rnd(nx + nu, nx + nu);
    const Eigen::MatrixXd H = L * L.transpose() / (nx + nu) + 0.1 * Eigen::MatrixXd::Identity(nx + nu, nx + nu);
    s.Q = H.topLeftCorner(nx, nx);
    s.q = rnd(nx, 1);
    if (k == N) {
      s.A.setZero();
      s.B.setZero();
      continue;
    }
    s.R = H.bottomRightCorner(nu, nu);
    s.S = H.bottomLeftCorner(nu, nx);
    s.r = rnd(nu, 1);
    s.A = Eigen::MatrixXd::Identity(nx, nx) + 0.3 * rnd(nx, nx);
    s.B = rnd(nx, nu);
    s.b = 0.1 * rnd(nx, 1);
    s.neq = eqAt(k);
    s.C.topRows(s.neq) = rnd(s.neq, nx);
    s.D.topRows(s.neq) = rnd(s.neq, nu);
    s.e.head(s.neq) = rnd(s.neq, 1);
  }
  return nodes;
}

/// Minimiser of the LQ problem with δx_0 = dx0, by one KKT system over all variables.
inline void solveByKkt(const std::vector<LqNode>& nodes, const Eigen::VectorXd& dx0,
                       std::vector<Eigen::VectorXd>& dx, std::vector<Eigen::VectorXd>& du) {
  const int N = static_cast<int>(nodes.size()) - 1;
  const int nx = nodes[0].nx(), nu = nodes[0].nu();
  const int nz = (N + 1) * nx + N * nu;
  int ncon = (N + 1) * nx;
  for (int k = 0; k < N; ++k) ncon += nodes[k].neq;
  auto xi = [&](int k) { return k * nx; };
  auto ui = [&](int k) { return (N + 1) * nx + k * nu; };
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(nz, nz), E = Eigen::MatrixXd::Zero(ncon, nz);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(nz), f = Eigen::VectorXd::Zero(ncon);
  int row = 0;
  E.block(row, xi(0), nx, nx).setIdentity();
  f.segment(row, nx) = dx0;
  row += nx;
  for (int k = 0; k <= N; ++k) {
    const LqNode& s = nodes[k];
    H.block(xi(k), xi(k), nx, nx) = s.Q;
    g.segment(xi(k), nx) = s.q;
    if (k == N) break;
    H.block(ui(k), ui(k), nu, nu) = s.R;
    H.block(ui(k), xi(k), nu, nx) = s.S;
    H.block(xi(k), ui(k), nx, nu) = s.S.transpose();
    g.segment(ui(k), nu) = s.r;
    // δx_{k+1} − A δx − B δu = b
    E.block(row, xi(k + 1), nx, nx).setIdentity();
    E.block(row, xi(k), nx, nx) = -s.A;
    E.block(row, ui(k), nx, nu) = -s.B;
    f.segment(row, nx) = s.b;
    row += nx;
    E.block(row, xi(k), s.neq, nx) = s.C.topRows(s.neq);
    E.block(row, ui(k), s.neq, nu) = s.D.topRows(s.neq);
    f.segment(row, s.neq) = -s.e.head(s.neq);
    row += s.neq;
  }
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(nz + ncon, nz + ncon);
  K.topLeftCorner(nz, nz) = H;
  K.topRightCorner(nz, ncon) = E.transpose();
  K.bottomLeftCorner(ncon, nz) = E;
  Eigen::VectorXd rhs(nz + ncon);
  rhs << -g, f;
  const Eigen::VectorXd sol = K.fullPivLu().solve(rhs);
  dx.assign(N + 1, Eigen::VectorXd());
  du.assign(N, Eigen::VectorXd());
  for (int k = 0; k <= N; ++k) dx[k] = sol.segment(xi(k), nx);
  for (int k = 0; k < N; ++k) du[k] = sol.segment(ui(k), nu);
}

/// Expects (dx, du) to be the KKT solution (dxRef, duRef): each node's states and inputs within
/// 1e-8 of it, relative to its size.
inline void expectKktSolution(const std::vector<Eigen::VectorXd>& dx,
                              const std::vector<Eigen::VectorXd>& du,
                              const std::vector<Eigen::VectorXd>& dxRef,
                              const std::vector<Eigen::VectorXd>& duRef) {
  for (std::size_t k = 0; k < dxRef.size(); ++k)
    EXPECT_LT((dx[k] - dxRef[k]).norm(), 1e-8 * (1 + dxRef[k].norm())) << "node " << k;
  for (std::size_t k = 0; k < duRef.size(); ++k)
    EXPECT_LT((du[k] - duRef[k]).norm(), 1e-8 * (1 + duRef[k].norm())) << "node " << k;
}

}  // namespace ballast::mpc::testing
