#include "mpc/riccati_solver.hpp"

#include <algorithm>
#include <chrono>

namespace ballast::mpc {
namespace {
double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

RiccatiSolver::RiccatiSolver(int horizonNodes, int nx, int nu, int maxEq)
    : N_(horizonNodes), nx_(nx), nu_(nu), proj_(horizonNodes), K_(horizonNodes),
      fullK_(horizonNodes), k_(horizonNodes), P_(nx, nx), PA_(nx, nx), PB_(nx, nu),
      Huu_(nu, nu), Hux_(nu, nx), Dt_(nu, maxEq), p_(nx), Pb_(nx), hu_(nu) {}

bool RiccatiSolver::project(int k, const LqNode& n) {
  Projected& p = proj_[k];
  const int m = n.neq;
  if (m == 0) {
    p.nw = nu_;
    p.Kc.setZero(nu_, nx_);
    p.kc.setZero(nu_);
    p.Z.setIdentity(nu_, nu_);
    p.A = n.A;
    p.B = n.B;
    p.b = n.b;
    p.Q = n.Q;
    p.S = n.S;
    p.R = n.R;
    p.q = n.q;
    p.r = n.r;
    return true;
  }
  // Dᵀ = [Y Z] [Rd; 0]: Y spans D's rows, Z its null space.
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(n.D.topRows(m).transpose());
  const Eigen::MatrixXd Qfull = qr.householderQ();
  const auto Rd = qr.matrixQR().topLeftCorner(m, m).triangularView<Eigen::Upper>();
  const Eigen::VectorXd pivots = qr.matrixQR().diagonal().head(m).cwiseAbs();
  if (!(pivots.minCoeff() > 1e-9 * std::max(1.0, pivots.maxCoeff()))) return false;
  const auto Y = Qfull.leftCols(m);
  p.nw = nu_ - m;
  p.Z = Qfull.rightCols(p.nw);
  // Kc = −Y Rd⁻ᵀ C, kc = −Y Rd⁻ᵀ e.
  const Eigen::MatrixXd RinvTC = Rd.transpose().solve(n.C.topRows(m));
  const Eigen::VectorXd RinvTe = Rd.transpose().solve(n.e.head(m));
  p.Kc.noalias() = -Y * RinvTC;
  p.kc.noalias() = -Y * RinvTe;

  p.A = n.A;
  p.A.noalias() += n.B * p.Kc;
  p.B.noalias() = n.B * p.Z;
  p.b = n.b;
  p.b.noalias() += n.B * p.kc;
  const Eigen::MatrixXd RKc = n.R * p.Kc;              // nu x nx
  const Eigen::MatrixXd SplusRKc = n.S + RKc;           // nu x nx
  p.Q = n.Q;
  p.Q.noalias() += p.Kc.transpose() * n.S;
  p.Q.noalias() += n.S.transpose() * p.Kc;
  p.Q.noalias() += p.Kc.transpose() * RKc;
  p.S.noalias() = p.Z.transpose() * SplusRKc;
  p.R.noalias() = p.Z.transpose() * n.R * p.Z;
  p.q = n.q;
  p.q.noalias() += p.Kc.transpose() * n.r;
  p.q.noalias() += SplusRKc.transpose() * p.kc;
  p.r.noalias() = p.Z.transpose() * (n.r + n.R * p.kc);
  return true;
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
    du[k] = n.Kc * dx[k] + n.kc + n.Z * w;
    fullK_[k] = n.Kc + n.Z * K_[k];
    dx[k + 1] = nodes[k].A * dx[k] + nodes[k].B * du[k] + nodes[k].b;
  }
  timings_.riccatiMs = msSince(t0);
  return true;
}

}  // namespace ballast::mpc
