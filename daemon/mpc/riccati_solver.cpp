#include "mpc/riccati_solver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace ballast::mpc {

namespace {
// An index list as Eigen's indexed views take it without copying it: a view on a std::vector
// holds a copy of the vector, one allocation each time it indexes (thousands per solve).
using IndexList = Eigen::Map<const Eigen::VectorXi>;
IndexList indices(const std::vector<int>& v) {
  return IndexList(v.data(), static_cast<Eigen::Index>(v.size()));
}
}  // namespace

RiccatiSolver::RiccatiSolver(int horizonNodes, int nx, int nu)
    : N_(horizonNodes), nx_(nx), nu_(nu), proj_(horizonNodes), L_(horizonNodes), G_(horizonNodes),
      g_(horizonNodes), P_(horizonNodes + 1, Eigen::MatrixXd::Zero(nx, nx)), swept_(horizonNodes),
      M_(nx, nx + nu), H_(nx + nu, nx + nu), p_(nx), Pb_(nx), y_(nx + nu), w_(nu), CtDx_(nu),
      KcDx_(nu), ZKw_(nu) {
  for (int k = 0; k < N_; ++k) {
    Projected& p = proj_[k];
    for (auto* v : {&p.free, &p.constrained, &p.fixed, &p.general}) v->reserve(nu);
    p.kind.resize(nu);
    p.fixedBy.resize(nu);
    L_[k].resize(nu, nu);
    G_[k].resize(nu, nx);
    g_[k].resize(nu);
  }
}

void RiccatiSolver::useSizes(Projected& p, const Sizes& sizes) {
  ++p.clock;
  if (!(p.sized().sizes == sizes)) {
    // The set of these sizes, or the least recently used (to be resized); the present one,
    // used last, is never that.
    int pick = 0;
    for (int i = 0; i < kSizeSets; ++i) {
      if (p.sets[i].sizes == sizes) {
        pick = i;
        break;
      }
      if (p.sets[i].lastUsed < p.sets[pick].lastUsed) pick = i;
    }
    p.current = pick;
    p.sized().sizes = sizes;
  }
  p.sized().lastUsed = p.clock;
}

bool RiccatiSolver::project(int k, const LqNode& n) {
  if (!projectMatrices(k, n)) return false;
  projectVectors(k, n);
  return true;
}

bool RiccatiSolver::projectMatrices(int k, const LqNode& n) {
  Projected& p = proj_[k];
  ++p.generation;
  p.matricesProjected = false;
  const int m = n.neq;
  // Sort inputs: fixed by a unit row, constrained by the other rows, or free.
  enum Kind : char { kFree, kFixed, kConstrained };
  std::fill(p.kind.begin(), p.kind.end(), kFree);
  p.general.clear();
  for (int r = 0; r < m; ++r) {
    int entries = 0, column = -1;
    for (int j = 0; j < nu_; ++j)
      if (n.D(r, j) != 0.0) ++entries, column = j;
    if (entries == 1 && n.C.row(r).isZero(0.0)) {
      if (p.kind[column] == kFixed) return false;  // two rows fix the same input
      p.kind[column] = kFixed;
      p.fixedBy[column] = r;
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
  const IndexList K = indices(p.constrained), F = indices(p.free);
  const int nK = static_cast<int>(K.size());
  const int nF = static_cast<int>(F.size());
  useSizes(p, Sizes{nK, static_cast<int>(general.size()), nF});
  SizedMatrices& s = p.sized();
  // A general row whose part outside the rows before it is below kDependentBelow of its norm is
  // dropped: it asks for what the others nearly fix already, and met exactly it would take
  // inputs of its disagreement with them over that sine. On legs without hip yaw the two feet's
  // yaw rates are both the base's (their rows' sine 1e-4..1e-2 standing and walking, 0 with level
  // feet); the humanoid's rows stay above 3e-2 walking. One row at a time, the most dependent.
  constexpr double kDependentBelow = 1e-2;
  for (int pass = 0;; ++pass) {
    const int rows = static_cast<int>(general.size());
    if (rows == 0) break;
    s.DKt.resize(nK, rows);
    for (int r = 0; r < rows; ++r)
      for (int i = 0; i < nK; ++i) s.DKt(i, r) = n.D(general[r], K[i]);
    s.qr.compute(s.DKt);
    if (rows == 1 || pass == 4) break;
    int worst = -1;
    double worstRho = kDependentBelow;
    for (int r = 1; r < rows; ++r) {
      // A row past the nK-th lies in the span of the ones before (R has nK rows).
      const double norm = s.DKt.col(r).norm();
      const double rho = r >= nK       ? 0.0
                         : norm > 0.0 ? std::abs(s.qr.matrixQR()(r, r)) / norm
                                      : 1.0;
      if (rho < worstRho) worstRho = rho, worst = r;
    }
    if (worst < 0) break;
    p.general.erase(p.general.begin() + worst);
  }
  const int mg = static_cast<int>(general.size());
  if (nK < mg) return false;
  const int nz = nK - mg;
  // Qfull = [Y Z_K] from the QR of D_Kᵀ; every product with Y and with Z_K below is taken with
  // Qfull at once (one larger product instead of two small ones), and its parts read from that.
  if (mg > 0) {
    const auto pivots = s.qr.matrixQR().diagonal().head(mg).cwiseAbs();
    if (!(pivots.minCoeff() > 1e-9 * std::max(1.0, pivots.maxCoeff()))) return false;
    s.Qfull.resize(nK, nK);
    s.qWork.resize(nK);
    s.qr.householderQ().evalTo(s.Qfull, s.qWork);  // with a workspace: no allocation
    const auto Rt = s.qr.matrixQR().topLeftCorner(mg, mg).triangularView<Eigen::Upper>().transpose();
    s.Y = s.Qfull.leftCols(mg);
    s.ZK = s.Qfull.rightCols(nz);
    s.Ct = -n.C(indices(general), Eigen::all);
    Rt.solveInPlace(s.Ct);
  } else {
    s.Y.resize(nK, 0);
    s.Ct.resize(0, nx_);
    s.ZK.setIdentity(nK, nK);
    s.Qfull.setIdentity(nK, nK);
  }
  p.nw = nF + nz;

  // Dynamics: A' = A + (B_K Y) Ct, B' = [B_F, B_K Z_K], b' = b + B kc.
  s.AB.resize(nx_, nx_ + p.nw);
  auto A = s.AB.leftCols(nx_);
  auto B = s.AB.rightCols(p.nw);
  s.BK = n.B(Eigen::all, K);
  s.BQ.noalias() = s.BK * s.Qfull;  // [B_K Y, B_K Z_K]
  A = n.A;
  A.noalias() += s.BQ.leftCols(mg) * s.Ct;
  B.leftCols(nF) = n.B(Eigen::all, F);
  B.rightCols(nz) = s.BQ.rightCols(nz);

  // Cost in (δx, w), with Kc_K = Y Ct:
  //   Q' = Q + Kcᵀ S_K + S_Kᵀ Kc + Kcᵀ R_KK Kc = Q + Ctᵀ W + Wᵀ Ct,  W = Yᵀ S_K + ½ (Yᵀ R_KK Y) Ct
  //   q' = q + Ctᵀ Yᵀ (r_K + (R kc)_K) + Sᵀ kc
  //   S' = [S_F + (R_FK Y) Ct;  Z_Kᵀ S_K + (Z_Kᵀ R_KK Y) Ct],  R' = [R_FF, R_FK Z_K; ., Z_Kᵀ R_KK Z_K]
  // T = Qfullᵀ R_KK Qfull holds Yᵀ R_KK Y, Z_Kᵀ R_KK Y and Z_Kᵀ R_KK Z_K in its lower triangle.
  s.SK = n.S(K, Eigen::all);
  s.QtSK.noalias() = s.Qfull.transpose() * s.SK;  // [Yᵀ S_K; Z_Kᵀ S_K]
  s.RKK = n.R(K, K);
  s.RQ.noalias() = s.RKK * s.Qfull;
  s.T.resize(nK, nK);
  s.T.triangularView<Eigen::Lower>() = s.Qfull.transpose() * s.RQ;
  // CW = [Ct; W], WC = [W; Ct]: Ctᵀ W + Wᵀ Ct = CWᵀ WC, one symmetric product.
  s.CW.resize(2 * mg, nx_);
  s.WC.resize(2 * mg, nx_);
  auto W = s.WC.topRows(mg);
  p.Q = n.Q;
  if (mg > 0) {
    W = s.QtSK.topRows(mg);
    W.noalias() += 0.5 * s.T.topLeftCorner(mg, mg).selfadjointView<Eigen::Lower>() * s.Ct;
    s.WC.bottomRows(mg) = s.Ct;
    s.CW.topRows(mg) = s.Ct;
    s.CW.bottomRows(mg) = W;
    p.Q.triangularView<Eigen::Lower>() += s.CW.transpose() * s.WC;
  }
  s.RFK = n.R(F, K);
  s.S.resize(p.nw, nx_);
  s.S.topRows(nF) = n.S(F, Eigen::all);
  s.RFY.noalias() = s.RFK * s.Y;
  s.S.topRows(nF).noalias() += s.RFY * s.Ct;
  s.S.bottomRows(nz) = s.QtSK.bottomRows(nz);
  s.S.bottomRows(nz).noalias() += s.T.bottomLeftCorner(nz, mg) * s.Ct;
  s.R.resize(p.nw, p.nw);
  s.R.topLeftCorner(nF, nF) = n.R(F, F);
  s.R.bottomLeftCorner(nz, nF).noalias() = s.ZK.transpose() * s.RFK.transpose();
  s.R.bottomRightCorner(nz, nz).triangularView<Eigen::Lower>() = s.T.bottomRightCorner(nz, nz);
  p.matricesProjected = true;
  return true;
}

void RiccatiSolver::projectVectors(int k, const LqNode& n) {
  Projected& p = proj_[k];
  SizedMatrices& s = p.sized();
  const auto& general = p.general;
  const IndexList K = indices(p.constrained), F = indices(p.free);
  const int nF = static_cast<int>(F.size());
  const int mg = static_cast<int>(general.size());
  const int nz = p.nw - nF;
  p.kc.setZero(nu_);
  for (int j : p.fixed) p.kc[j] = -n.e[p.fixedBy[j]] / n.D(p.fixedBy[j], j);
  // The general rows with the fixed inputs substituted: D_K δu_K + C δx + e' = 0.
  if (mg > 0) {
    s.ePrime = n.e(indices(general));
    for (int r = 0; r < mg; ++r)
      for (int j : p.fixed) s.ePrime[r] += n.D(general[r], j) * p.kc[j];
    const auto Rt =
        s.qr.matrixQR().topLeftCorner(mg, mg).triangularView<Eigen::Upper>().transpose();
    s.ct = -s.ePrime;
    Rt.solveInPlace(s.ct);
    s.kcK.noalias() = s.Y * s.ct;
    p.kc(K) = s.kcK;
  }
  p.b = n.b;
  p.b.noalias() += n.B * p.kc;
  p.Rkc.noalias() = n.R * p.kc;
  s.rK = n.r(K) + p.Rkc(K);
  p.q = n.q;
  p.q.noalias() += n.S.transpose() * p.kc;
  s.ct.noalias() = s.Y.transpose() * s.rK;
  p.q.noalias() += s.Ct.transpose() * s.ct;
  s.r.resize(p.nw);
  s.r.head(nF) = n.r(F) + p.Rkc(F);
  s.r.tail(nz).noalias() = s.ZK.transpose() * s.rK;
}

void RiccatiSolver::inputStep(const Projected& p, const Eigen::VectorXd& dx, const Eigen::VectorXd& w,
                              Eigen::VectorXd& du) {
  const SizedMatrices& s = p.sized();
  const int nF = static_cast<int>(p.free.size());
  du = p.kc;
  du(indices(p.free)) += w.head(nF);
  // δu_K += Kc_K δx + Z_K w_K, with Kc_K δx = Y (Ct δx).
  auto CtDx = CtDx_.head(s.Ct.rows());
  auto KcDx = KcDx_.head(s.Y.rows());
  auto ZKw = ZKw_.head(s.ZK.rows());
  CtDx.noalias() = s.Ct * dx;
  KcDx.noalias() = s.Y * CtDx;
  ZKw.noalias() = s.ZK * w.segment(nF, p.nw - nF);
  du(indices(p.constrained)) += KcDx + ZKw;
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
  beginSweep(nodes[N_]);
  for (int k = N_ - 1; k >= 0; --k)
    if (!sweepNode(k)) return false;
  forwardPass(nodes, dx0, dx, du);
  timings_.riccatiMs = msSince(t0);
  return true;
}

void RiccatiSolver::beginSweep(const LqNode& terminal) {
  beginMatrixSweep(terminal);
  p_ = terminal.q;
  keptSweeps_ = 0;
}

bool RiccatiSolver::sweepNode(int k, bool sameMatrices) {
  if (sameMatrices && swept_[k] == proj_[k].generation) {
    ++keptSweeps_;
  } else if (!sweepMatrices(k)) {
    return false;
  }
  sweepVectors(k);
  return true;
}

void RiccatiSolver::beginMatrixSweep(const LqNode& terminal) {
  // A node's sweep is kept only on the same P after it: on a terminal Q the same to the bit.
  Eigen::MatrixXd& PN = P_[N_];
  if (sameBits(PN, terminal.Q)) return;
  PN = terminal.Q;
  std::fill(swept_.begin(), swept_.end(), 0);
}

bool RiccatiSolver::sweepMatrices(int k) {
  // The nodes below are swept on this one's P: theirs were of another, until swept again.
  std::fill(swept_.begin(), swept_.begin() + k + 1, 0);  // no projection's generation
  const int nx = nx_;
  const Projected& n = proj_[k];
  const SizedMatrices& s = n.sized();
  const int nw = n.nw, nab = nx + nw;
  const Eigen::MatrixXd& Pnext = P_[k + 1];
  // H = [A B]ᵀ P [A B] (lower triangle): AᵀPA, BᵀPA and BᵀPB in one product.
  auto M = M_.leftCols(nab);
  M.noalias() = Pnext * s.AB;
  auto H = H_.topLeftCorner(nab, nab);
  H.triangularView<Eigen::Lower>() = s.AB.transpose() * M;
  auto Huu = L_[k].topLeftCorner(nw, nw);
  auto G = G_[k].topRows(nw);
  Huu.triangularView<Eigen::Lower>() = s.R + H.bottomRightCorner(nw, nw);
  G = s.S + H.bottomLeftCorner(nw, nx);
  // H_uu = L Lᵀ (in place); G = L⁻¹ H_ux (K = −L⁻ᵀ G).
  Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>, Eigen::Lower> llt(Huu);
  if (llt.info() != Eigen::Success) return false;
  const auto L = Huu.triangularView<Eigen::Lower>();
  L.solveInPlace(G);
  // P ← Q + AᵀPA − GᵀG (Hux_ᵀ K = −GᵀG).
  Eigen::MatrixXd& P = P_[k];
  P.triangularView<Eigen::Lower>() = n.Q + H.topLeftCorner(nx, nx);
  P.selfadjointView<Eigen::Lower>().rankUpdate(G.transpose(), -1.0);
  for (int j = 1; j < nx; ++j)
    for (int i = 0; i < j; ++i) P(i, j) = P(j, i);
  swept_[k] = n.generation;
  return true;
}

void RiccatiSolver::sweepVectors(int k) {
  const int nx = nx_;
  const Projected& n = proj_[k];
  const SizedMatrices& s = n.sized();
  const int nw = n.nw, nab = nx + nw;
  Pb_ = p_;
  Pb_.noalias() += P_[k + 1] * n.b;  // P b + p
  auto y = y_.head(nab);
  y.noalias() = s.AB.transpose() * Pb_;  // [Aᵀ; Bᵀ] (P b + p)
  auto g = g_[k].head(nw);
  g = s.r + y.tail(nw);
  // g = L⁻¹ h_u (k = −L⁻ᵀ g);  p ← q + Aᵀ(P b + p) − Gᵀ g
  L_[k].topLeftCorner(nw, nw).triangularView<Eigen::Lower>().solveInPlace(g);
  p_ = n.q + y.head(nx);
  p_.noalias() -= G_[k].topRows(nw).transpose() * g;
}

void RiccatiSolver::forwardPass(const std::vector<LqNode>& nodes, const Eigen::VectorXd& dx0,
                                std::vector<Eigen::VectorXd>& dx, std::vector<Eigen::VectorXd>& du) {
  dx.resize(N_ + 1);
  du.resize(N_);
  dx[0] = dx0;
  for (int k = 0; k < N_; ++k) {
    const Projected& n = proj_[k];
    const int nw = n.nw;
    auto w = w_.head(nw);  // w = −L⁻ᵀ (g + G δx)
    w = g_[k].head(nw);
    w.noalias() += G_[k].topRows(nw) * dx[k];
    L_[k].topLeftCorner(nw, nw).triangularView<Eigen::Lower>().transpose().solveInPlace(w);
    w = -w;
    inputStep(n, dx[k], w_, du[k]);
    dx[k + 1] = nodes[k].b;
    dx[k + 1].noalias() += nodes[k].A * dx[k];
    dx[k + 1].noalias() += nodes[k].B * du[k];
  }
}

}  // namespace ballast::mpc
