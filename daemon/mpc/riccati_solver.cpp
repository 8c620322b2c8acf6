#include "mpc/riccati_solver.hpp"

#include <algorithm>
#include <chrono>

namespace ballast::mpc {
namespace {
double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

RiccatiSolver::RiccatiSolver(int horizonNodes, int nx, int nu)
    : N_(horizonNodes), nx_(nx), nu_(nu), proj_(horizonNodes), K_(horizonNodes),
      k_(horizonNodes), P_(nx, nx), PA_(nx, nx), PB_(nx, nu), Huu_(nu, nu), Hux_(nu, nx),
      p_(nx), Pb_(nx), hu_(nu) {}

bool RiccatiSolver::project(int k, const LqNode& n) {
  Projected& p = proj_[k];
  const int m = n.neq;
  // Sort inputs: fixed by a unit row, constrained by the other rows, or free.
  enum Kind : char { kFree, kFixed, kConstrained };
  std::vector<Kind> kind(nu_, kFree);
  std::vector<int> general;
  p.kc.setZero(nu_);
  for (int r = 0; r < m; ++r) {
    int entries = 0, column = -1;
    for (int j = 0; j < nu_; ++j)
      if (n.D(r, j) != 0.0) ++entries, column = j;
    if (entries == 1 && n.C.row(r).isZero(0.0)) {
      if (kind[column] == kFixed) return false;  // two rows fix the same input
      kind[column] = kFixed;
      p.kc[column] = -n.e[r] / n.D(r, column);
    } else {
      if (entries == 0) return false;  // a row no input can satisfy
      general.push_back(r);
    }
  }
  for (int r : general)
    for (int j = 0; j < nu_; ++j)
      if (n.D(r, j) != 0.0 && kind[j] != kFixed) kind[j] = kConstrained;
  p.free.clear();
  p.constrained.clear();
  std::vector<int> fixed;
  for (int j = 0; j < nu_; ++j)
    (kind[j] == kFree ? p.free : kind[j] == kFixed ? fixed : p.constrained).push_back(j);

  const int mg = static_cast<int>(general.size());
  const int nK = static_cast<int>(p.constrained.size());
  const int nF = static_cast<int>(p.free.size());
  if (nK < mg) return false;
  const auto& K = p.constrained;
  const auto& F = p.free;
  // The general rows with the fixed inputs substituted: D_K δu_K + C δx + e' = 0.
  if (mg > 0) {
    const Eigen::MatrixXd DK = n.D(general, K);
    const Eigen::VectorXd e = n.e(general) + n.D(general, fixed) * p.kc(fixed);
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(DK.transpose());
    const Eigen::VectorXd pivots = qr.matrixQR().diagonal().head(mg).cwiseAbs();
    if (!(pivots.minCoeff() > 1e-9 * std::max(1.0, pivots.maxCoeff()))) return false;
    const Eigen::MatrixXd Qfull = qr.householderQ();
    const auto Rd = qr.matrixQR().topLeftCorner(mg, mg).triangularView<Eigen::Upper>();
    const auto Y = Qfull.leftCols(mg);
    p.ZK = Qfull.rightCols(nK - mg);
    p.KcK.noalias() = -Y * Rd.transpose().solve(n.C(general, Eigen::all));
    p.kc(K) = -Y * Rd.transpose().solve(e);
  } else {
    p.ZK.setIdentity(nK, nK);
    p.KcK.setZero(nK, n.nx());
  }
  const int nwK = static_cast<int>(p.ZK.cols());
  p.nw = nF + nwK;

  // Dynamics: A' = A + B_K Kc_K, B' = [B_F, B_K Z_K], b' = b + B kc.
  const Eigen::MatrixXd BK = n.B(Eigen::all, K);
  p.A = n.A;
  p.A.noalias() += BK * p.KcK;
  p.B.resize(nx_, p.nw);
  p.B.leftCols(nF) = n.B(Eigen::all, F);
  p.B.rightCols(nwK).noalias() = BK * p.ZK;
  p.b = n.b;
  p.b.noalias() += n.B * p.kc;

  // Cost in (δx, w).
  const Eigen::MatrixXd RKc = n.R(Eigen::all, K) * p.KcK;  // R Kc, nu x nx
  const Eigen::VectorXd Rkc = n.R * p.kc;
  const Eigen::MatrixXd SK = n.S(K, Eigen::all);
  p.Q = n.Q;
  p.Q.noalias() += p.KcK.transpose() * SK;
  p.Q.noalias() += SK.transpose() * p.KcK;
  p.Q.noalias() += p.KcK.transpose() * RKc(K, Eigen::all);
  p.q = n.q;
  p.q.noalias() += p.KcK.transpose() * (n.r(K) + Rkc(K));
  p.q.noalias() += n.S.transpose() * p.kc;
  p.S.resize(p.nw, nx_);
  p.S.topRows(nF) = n.S(F, Eigen::all) + RKc(F, Eigen::all);
  p.S.bottomRows(nwK).noalias() = p.ZK.transpose() * (SK + RKc(K, Eigen::all));
  p.R.resize(p.nw, p.nw);
  p.R.topLeftCorner(nF, nF) = n.R(F, F);
  p.R.topRightCorner(nF, nwK).noalias() = n.R(F, K) * p.ZK;
  p.R.bottomLeftCorner(nwK, nF) = p.R.topRightCorner(nF, nwK).transpose();
  p.R.bottomRightCorner(nwK, nwK).noalias() = p.ZK.transpose() * n.R(K, K) * p.ZK;
  p.r.resize(p.nw);
  p.r.head(nF) = n.r(F) + Rkc(F);
  p.r.tail(nwK).noalias() = p.ZK.transpose() * (n.r(K) + Rkc(K));
  return true;
}

void RiccatiSolver::inputStep(const Projected& p, const Eigen::VectorXd& dx,
                              const Eigen::VectorXd& w, Eigen::VectorXd& du) const {
  const int nF = static_cast<int>(p.free.size());
  du = p.kc;
  du(p.free) += w.head(nF);
  du(p.constrained) += p.KcK * dx + p.ZK * w.tail(p.nw - nF);
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
    auto Hux = Hux_.topRows(nw);
    auto hu = hu_.head(nw);
    Huu = n.R;
    Huu.noalias() += n.B.transpose() * PB;
    Hux = n.S;
    Hux.noalias() += n.B.transpose() * PA_;
    hu = n.r;
    hu.noalias() += n.B.transpose() * Pb_;
    const Eigen::LLT<Eigen::MatrixXd> llt(Huu);
    if (llt.info() != Eigen::Success) return false;
    K_[k] = -llt.solve(Hux);
    k_[k] = -llt.solve(hu);
    // P ← Q + Aᵀ P A + Huxᵀ K;  p ← q + Aᵀ (P b + p) + Huxᵀ k
    Eigen::MatrixXd Pnew = n.Q;
    Pnew.noalias() += n.A.transpose() * PA_;
    Pnew.noalias() += Hux.transpose() * K_[k];
    P_ = 0.5 * (Pnew + Pnew.transpose());
    Eigen::VectorXd pnew = n.q;
    pnew.noalias() += n.A.transpose() * Pb_;
    pnew.noalias() += Hux.transpose() * k_[k];
    p_ = pnew;
  }

  dx.resize(N_ + 1);
  du.resize(N_);
  dx[0] = dx0;
  for (int k = 0; k < N_; ++k) {
    const Projected& n = proj_[k];
    const Eigen::VectorXd w = K_[k] * dx[k] + k_[k];
    inputStep(n, dx[k], w, du[k]);
    dx[k + 1] = nodes[k].A * dx[k] + nodes[k].B * du[k] + nodes[k].b;
  }
  timings_.riccatiMs = msSince(t0);
  return true;
}

}  // namespace ballast::mpc
