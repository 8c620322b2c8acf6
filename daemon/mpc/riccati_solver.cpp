#include "mpc/riccati_solver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace ballast::mpc {
namespace {
double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

RiccatiSolver::RiccatiSolver(int horizonNodes, int nx, int nu)
    : N_(horizonNodes), nx_(nx), nu_(nu), proj_(horizonNodes), K_(horizonNodes),
      k_(horizonNodes), P_(nx, nx), PA_(nx, nx), PB_(nx, nu), Huu_(nu, nu), Hux_(nu, nx),
      p_(nx), Pb_(nx), hu_(nu), w_(nu) {
  for (Projected& p : proj_) {
    for (auto* v : {&p.free, &p.constrained, &p.fixed, &p.general}) v->reserve(nu);
    p.kind.resize(nu);
  }
  for (int k = 0; k < N_; ++k) {
    K_[k].resize(nu, nx);
    k_[k].resize(nu);
  }
}

bool RiccatiSolver::project(int k, const LqNode& n) {
  Projected& p = proj_[k];
  const int m = n.neq;
  // Sort inputs: fixed by a unit row, constrained by the other rows, or free.
  enum Kind : char { kFree, kFixed, kConstrained };
  std::fill(p.kind.begin(), p.kind.end(), kFree);
  p.general.clear();
  p.kc.setZero(nu_);
  for (int r = 0; r < m; ++r) {
    int entries = 0, column = -1;
    for (int j = 0; j < nu_; ++j)
      if (n.D(r, j) != 0.0) ++entries, column = j;
    if (entries == 1 && n.C.row(r).isZero(0.0)) {
      if (p.kind[column] == kFixed) return false;  // two rows fix the same input
      p.kind[column] = kFixed;
      p.kc[column] = -n.e[r] / n.D(r, column);
    } else {
      if (entries == 0) return false;  // a row no input can satisfy
      p.general.push_back(r);
    }
  }
  for (int r : p.general)
    for (int j = 0; j < nu_; ++j)
      if (n.D(r, j) != 0.0 && p.kind[j] != kFixed) p.kind[j] = kConstrained;
  p.free.clear();
  p.constrained.clear();
  p.fixed.clear();
  for (int j = 0; j < nu_; ++j)
    (p.kind[j] == kFree ? p.free : p.kind[j] == kFixed ? p.fixed : p.constrained).push_back(j);

  const auto& general = p.general;
  const auto& K = p.constrained;
  const auto& F = p.free;
  const int nK = static_cast<int>(K.size());
  const int nF = static_cast<int>(F.size());
  // A general row whose part outside the rows before it is below kDependentBelow of its norm is
  // dropped: it asks for what the others nearly fix already, and met exactly it would take
  // inputs of its disagreement with them over that sine. On legs without hip yaw the two feet's
  // yaw rates are both the base's (their rows' sine 1e-4..1e-2 standing and walking, 0 with level
  // feet); the humanoid's rows stay above 3e-2 walking. One row at a time, the most dependent.
  constexpr double kDependentBelow = 1e-2;
  for (int pass = 0;; ++pass) {
    const int rows = static_cast<int>(general.size());
    if (rows == 0) break;
    p.DKt.resize(nK, rows);
    for (int r = 0; r < rows; ++r)
      for (int i = 0; i < nK; ++i) p.DKt(i, r) = n.D(general[r], K[i]);
    p.qr.compute(p.DKt);
    if (rows == 1 || pass == 4) break;
    int worst = -1;
    double worstRho = kDependentBelow;
    for (int r = 1; r < rows; ++r) {
      const double norm = p.DKt.col(r).norm();
      const double rho = norm > 0.0 ? std::abs(p.qr.matrixQR()(r, r)) / norm : 1.0;
      if (rho < worstRho) worstRho = rho, worst = r;
    }
    if (worst < 0) break;
    p.general.erase(p.general.begin() + worst);
  }
  const int mg = static_cast<int>(general.size());
  if (nK < mg) return false;
  const int nz = nK - mg;
  // The general rows with the fixed inputs substituted: D_K δu_K + C δx + e' = 0.
  if (mg > 0) {
    p.ePrime = n.e(general);
    for (int r = 0; r < mg; ++r)
      for (int j : p.fixed) p.ePrime[r] += n.D(general[r], j) * p.kc[j];
    const auto pivots = p.qr.matrixQR().diagonal().head(mg).cwiseAbs();
    if (!(pivots.minCoeff() > 1e-9 * std::max(1.0, pivots.maxCoeff()))) return false;
    p.Qfull = p.qr.householderQ();
    const auto Rt = p.qr.matrixQR().topLeftCorner(mg, mg).triangularView<Eigen::Upper>().transpose();
    p.Y = p.Qfull.leftCols(mg);
    p.ZK = p.Qfull.rightCols(nz);
    p.Ct = -n.C(general, Eigen::all);
    Rt.solveInPlace(p.Ct);
    p.ct = -p.ePrime;
    Rt.solveInPlace(p.ct);
    p.kc(K) = p.Y * p.ct;
  } else {
    p.Y.resize(nK, 0);
    p.Ct.resize(0, nx_);
    p.ZK.setIdentity(nK, nK);
  }
  p.nw = nF + nz;

  // Dynamics: A' = A + (B_K Y) Ct, B' = [B_F, B_K Z_K], b' = b + B kc.
  p.BK = n.B(Eigen::all, K);
  p.BY.noalias() = p.BK * p.Y;
  p.A = n.A;
  p.A.noalias() += p.BY * p.Ct;
  p.B.resize(nx_, p.nw);
  p.B.leftCols(nF) = n.B(Eigen::all, F);
  p.B.rightCols(nz).noalias() = p.BK * p.ZK;
  p.b = n.b;
  p.b.noalias() += n.B * p.kc;

  // Cost in (δx, w), with Kc_K = Y Ct:
  //   Q' = Q + Kcᵀ S_K + S_Kᵀ Kc + Kcᵀ R_KK Kc = Q + Ctᵀ W + Wᵀ Ct,  W = Yᵀ S_K + ½ (Yᵀ R_KK Y) Ct
  //   q' = q + Ctᵀ Yᵀ (r_K + (R kc)_K) + Sᵀ kc
  //   S' = [S_F + (R_FK Y) Ct;  Z_Kᵀ S_K + (Z_Kᵀ R_KK Y) Ct],  R' = [R_FF, R_FK Z_K; ., Z_Kᵀ R_KK Z_K]
  p.RKK = n.R(K, K);
  p.RY.noalias() = p.RKK * p.Y;
  p.W.noalias() = p.Y.transpose() * n.S(K, Eigen::all);
  p.ZRY.noalias() = p.Y.transpose() * p.RY;  // Yᵀ R_KK Y (scratch)
  p.W.noalias() += 0.5 * p.ZRY * p.Ct;
  p.Q = n.Q;
  p.Q.noalias() += p.Ct.transpose() * p.W;
  p.Q.noalias() += p.W.transpose() * p.Ct;
  p.Rkc.noalias() = n.R * p.kc;
  p.rK = n.r(K) + p.Rkc(K);
  p.q = n.q;
  p.q.noalias() += n.S.transpose() * p.kc;
  p.ct.noalias() = p.Y.transpose() * p.rK;
  p.q.noalias() += p.Ct.transpose() * p.ct;

  p.RFK = n.R(F, K);
  p.S.resize(p.nw, nx_);
  p.S.topRows(nF) = n.S(F, Eigen::all);
  p.BY.noalias() = p.RFK * p.Y;  // R_FK Y (scratch)
  p.S.topRows(nF).noalias() += p.BY * p.Ct;
  p.S.bottomRows(nz).noalias() = p.ZK.transpose() * n.S(K, Eigen::all);
  p.ZRY.noalias() = p.ZK.transpose() * p.RY;
  p.S.bottomRows(nz).noalias() += p.ZRY * p.Ct;
  p.R.resize(p.nw, p.nw);
  p.R.topLeftCorner(nF, nF) = n.R(F, F);
  p.R.topRightCorner(nF, nz).noalias() = p.RFK * p.ZK;
  p.R.bottomLeftCorner(nz, nF) = p.R.topRightCorner(nF, nz).transpose();
  p.RY.noalias() = p.RKK * p.ZK;  // R_KK Z (scratch)
  p.R.bottomRightCorner(nz, nz).noalias() = p.ZK.transpose() * p.RY;
  p.r.resize(p.nw);
  p.r.head(nF) = n.r(F) + p.Rkc(F);
  p.r.tail(nz).noalias() = p.ZK.transpose() * p.rK;
  return true;
}

void RiccatiSolver::inputStep(const Projected& p, const Eigen::VectorXd& dx,
                              const Eigen::VectorXd& w, Eigen::VectorXd& du) const {
  const int nF = static_cast<int>(p.free.size());
  du = p.kc;
  du(p.free) += w.head(nF);
  du(p.constrained) += p.Y * (p.Ct * dx) + p.ZK * w.segment(nF, p.nw - nF);
}

bool RiccatiSolver::solve(const std::vector<LqNode>& nodes, const Eigen::VectorXd& dx0,
                          std::vector<Eigen::VectorXd>& dx, std::vector<Eigen::VectorXd>& du) {
  for (int k = 0; k < N_; ++k)
    if (!project(k, nodes[k])) return false;
  return sweep(nodes, dx0, dx, du);
}

bool RiccatiSolver::sweep(const std::vector<LqNode>& nodes, const Eigen::VectorXd& dx0,
                          std::vector<Eigen::VectorXd>& dx, std::vector<Eigen::VectorXd>& du) {
  const auto t0 = std::chrono::steady_clock::now();
  P_ = nodes[N_].Q;
  p_ = nodes[N_].q;
  for (int k = N_ - 1; k >= 0; --k) {
    const Projected& n = proj_[k];
    const int nw = n.nw;
    PA_.noalias() = P_ * n.A;
    auto PB = PB_.leftCols(nw);
    PB.noalias() = P_ * n.B;
    Pb_ = p_;
    Pb_.noalias() += P_ * n.b;  // P b + p
    auto Huu = Huu_.topLeftCorner(nw, nw);
    auto G = Hux_.topRows(nw);
    auto g = hu_.head(nw);
    Huu.triangularView<Eigen::Lower>() = n.R;
    Huu.triangularView<Eigen::Lower>() += n.B.transpose() * PB;
    G = n.S;
    G.noalias() += n.B.transpose() * PA_;
    g = n.r;
    g.noalias() += n.B.transpose() * Pb_;
    // H_uu = L Lᵀ (in place); G = L⁻¹ H_ux, g = L⁻¹ h_u; K = −L⁻ᵀ G, k = −L⁻ᵀ g.
    Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>, Eigen::Lower> llt(Huu);
    if (llt.info() != Eigen::Success) return false;
    const auto L = Huu.triangularView<Eigen::Lower>();
    L.solveInPlace(G);
    L.solveInPlace(g);
    auto Kk = K_[k].topRows(nw);
    Kk = -G;
    L.transpose().solveInPlace(Kk);
    auto kk = k_[k].head(nw);
    kk = -g;
    L.transpose().solveInPlace(kk);
    // P ← Q + AᵀPA − GᵀG (Hux_ᵀ K = −GᵀG);  p ← q + Aᵀ(P b + p) − Gᵀ g
    P_.triangularView<Eigen::Lower>() = n.Q;
    P_.triangularView<Eigen::Lower>() += n.A.transpose() * PA_;
    P_.selfadjointView<Eigen::Lower>().rankUpdate(G.transpose(), -1.0);
    for (int j = 1; j < nx_; ++j)
      for (int i = 0; i < j; ++i) P_(i, j) = P_(j, i);
    p_ = n.q;
    p_.noalias() += n.A.transpose() * Pb_;
    p_.noalias() -= G.transpose() * g;
  }

  dx.resize(N_ + 1);
  du.resize(N_);
  dx[0] = dx0;
  for (int k = 0; k < N_; ++k) {
    const Projected& n = proj_[k];
    auto w = w_.head(n.nw);
    w = k_[k].head(n.nw);
    w.noalias() += K_[k].topRows(n.nw) * dx[k];
    inputStep(n, dx[k], w_, du[k]);
    dx[k + 1] = nodes[k].A * dx[k] + nodes[k].B * du[k] + nodes[k].b;
  }
  timings_.riccatiMs = msSince(t0);
  return true;
}

}  // namespace ballast::mpc
