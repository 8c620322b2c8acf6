#include "wbc/hierarchical_qp.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/Householder>

namespace ballast::wbc {

const char* toString(HqpStatus status) {
  switch (status) {
    case HqpStatus::kOk: return "ok";
    case HqpStatus::kRelaxed: return "relaxed";
    case HqpStatus::kFailed: return "failed";
  }
  return "unknown";
}

HierarchicalQp::HierarchicalQp(int variables, int maxLevels, int maxLevelEqualityRows,
                               int maxInequalityRows, HqpSettings settings)
    : n_(variables), settings_(settings) {
  if (variables < 1 || maxLevels < 1 || maxLevelEqualityRows < 0 || maxInequalityRows < 0)
    throw std::invalid_argument("HierarchicalQp: needs variables and levels");
  const int n = variables, m = std::max(maxLevelEqualityRows, 1), p = std::max(maxInequalityRows, 1);
  scale_.setOnes(n);
  x_.setZero(n);
  xc_.setZero(n);
  w_.setZero(n);
  e_.setZero(2 * m);
  rowNorm_.setZero(m);
  rowWeight_.setZero(m);
  Dx_.setZero(p);
  relax_.setZero(p);
  work_.setZero(std::max(n, m) + 1);
  hCoeffs_.setZero(n);
  Z_.setZero(n, n);
  Zp_.setZero(n, n);
  B_.setZero(n, m);
  T_.setZero(n, m);
  N_.setZero(n, n);
  DZ_.setZero(p, n);
  perm_.assign(m, 0);
  qp_.reserve(maxLevels + 1);
  for (int k = 0; k < maxLevels; ++k) qp_.emplace_back(QpCapacity{n, 0, p}, settings.qp);
  qp_.emplace_back(QpCapacity{n + p, 0, 3 * p}, settings.qp);  // slack problems
  levels_.resize(maxLevels);
  maxLevelRows_ = maxLevelEqualityRows;
  maxInequalityRows_ = maxInequalityRows;
}

void HierarchicalQp::setVariableScale(const Eigen::VectorXd& scale) {
  if (scale.size() != n_ || !(scale.array() > 0.0).all() || !scale.allFinite())
    throw std::invalid_argument("HierarchicalQp: the variable scale needs " + std::to_string(n_) +
                                " positive finite entries");
  scale_ = scale;
}

int HierarchicalQp::totalIterations() const {
  int sum = 0;
  for (const auto& l : levels_) sum += l.iterations;
  return sum;
}

// The least-squares step of level k in the null space Z (n × r): pivoted Householder QR of
// (A_k Z)ᵀ = Q R Pᵀ. Leaves Zp = Z Q (its first `rank` columns span the task directions, the
// rest the new null space), T = R's first `rank` rows (zeros below the diagonal), e_ (second
// half) = Pᵀ(b_k − A_k x), and xc = x + Zp₁ w₁ with w₁ the minimum-norm least-squares step.
int HierarchicalQp::taskStep(const TaskStack& stack, int k, int r, HqpLevelResult& level) {
  const int m = stack.equalityRows(k), begin = stack.equalityBegin(k);
  Zp_.leftCols(r) = Z_.leftCols(r);
  xc_ = x_;
  damped_ = false;
  if (m == 0 || r == 0) return 0;

  const auto A = stack.A().middleRows(begin, m);
  auto B = B_.topLeftCorner(r, m);
  B.noalias() = Z_.leftCols(r).transpose() * A.transpose();
  auto e = e_.head(m);
  e = stack.b().segment(begin, m);
  e.noalias() -= A * x_;

  // Rows are dependent when what is left of them is small next to the largest scaled row.
  double largestRow = 0.0;
  for (int i = 0; i < m; ++i) {
    rowNorm_[i] = A.row(i).cwiseProduct(scale_.transpose()).norm();
    largestRow = std::max(largestRow, rowNorm_[i]);
  }
  const double threshold = settings_.rankTolerance * largestRow;

  for (int c = 0; c < m; ++c) perm_[c] = c;
  int rank = 0;
  for (int j = 0; j < std::min(r, m); ++j) {
    int pivot = j;
    double best = -1.0;
    for (int c = j; c < m; ++c) {
      const double norm2 = B.col(c).segment(j, r - j).squaredNorm();
      if (norm2 > best) best = norm2, pivot = c;
    }
    if (!(std::sqrt(best) > threshold)) break;
    if (std::sqrt(best) < settings_.dependentBelow * rowNorm_[perm_[pivot]]) {
      // Nearly dependent on what came before: take the row most independent of it instead, or
      // none if every row left is nearly dependent.
      double bestRho = -1.0;
      for (int c = j; c < m; ++c) {
        const double rho = B.col(c).segment(j, r - j).norm() / rowNorm_[perm_[c]];
        if (rowNorm_[perm_[c]] > 0.0 && rho > bestRho) bestRho = rho, pivot = c;
      }
      if (!(bestRho >= settings_.dependentBelow)) break;
    }
    if (pivot != j) {
      B.col(j).swap(B.col(pivot));
      std::swap(perm_[j], perm_[pivot]);
    }
    double tau = 0.0, beta = 0.0;
    B.col(j).segment(j, r - j).makeHouseholderInPlace(tau, beta);
    B(j, j) = beta;
    hCoeffs_[j] = tau;
    if (j + 1 < m)
      B.block(j, j + 1, r - j, m - j - 1)
          .applyHouseholderOnTheLeft(B.col(j).segment(j + 1, r - j - 1), tau, work_.data());
    ++rank;
  }
  if (rank == 0) return 0;
  for (int j = 0; j < rank; ++j)
    Zp_.middleCols(j, r - j).applyHouseholderOnTheRight(B.col(j).segment(j + 1, r - j - 1),
                                                        hCoeffs_[j], work_.data());
  auto T = T_.topLeftCorner(rank, m);
  T = B.topRows(rank);
  T.leftCols(rank).triangularView<Eigen::StrictlyLower>().setZero();
  auto ep = e_.segment(m, m);
  for (int i = 0; i < m; ++i) ep[i] = e[perm_[i]];

  // Pivots small next to their own row: damp their directions (d_j² on the diagonal).
  double conditioning = 1.0;
  auto d2 = rowWeight_.head(rank);
  for (int j = 0; j < rank; ++j) {
    const double norm = rowNorm_[perm_[j]], rho = std::abs(T(j, j)) / norm;
    conditioning = std::min(conditioning, rho);
    d2[j] = rho < settings_.dampingBelow ? settings_.damping * settings_.damping * norm * norm : 0.0;
  }
  level.conditioning = conditioning;
  damped_ = conditioning < settings_.dampingBelow;
  level.damped = damped_;

  auto w1 = w_.head(rank);
  if (damped_) {  // least squares, damped along the ill-conditioned pivots: (T Tᵀ + D²) w₁ = T Pᵀe
    auto N = N_.topLeftCorner(rank, rank);
    N.noalias() = T * T.transpose();
    N.diagonal() += d2;
    w1.noalias() = T * ep;
    Eigen::Ref<Eigen::MatrixXd> ref(N);
    Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> llt(ref);
    llt.solveInPlace(w1);
  } else if (rank == m) {  // independent rows: the task is met exactly, R₁₁ᵀw₁ = Pᵀe
    w1 = ep;
    T.leftCols(rank).triangularView<Eigen::Upper>().transpose().solveInPlace(w1);
  } else {  // dependent rows: least squares by the normal equations of Tᵀw₁ ≈ Pᵀe
    auto N = N_.topLeftCorner(rank, rank);
    N.noalias() = T * T.transpose();
    w1.noalias() = T * ep;
    Eigen::Ref<Eigen::MatrixXd> ref(N);
    Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> llt(ref);
    llt.solveInPlace(w1);
  }
  xc_.noalias() += Zp_.leftCols(rank) * w1;
  return rank;
}

bool HierarchicalQp::feasible(const TaskStack& stack, const Eigen::VectorXd& x, int rows) const {
  const double tol = settings_.feasibilityTolerance;
  for (int i = 0; i < rows; ++i) {
    const double v = stack.D().row(i).dot(x);
    const double lo = stack.lower()[i], hi = stack.upper()[i];
    if (lo > -kInf && v < lo - relax_[i] - tol * std::max(1.0, std::abs(lo))) return false;
    if (hi < kInf && v > hi + relax_[i] + tol * std::max(1.0, std::abs(hi))) return false;
  }
  return true;
}

// The level's QP in the rotated coordinates w (x = x_ + Zp w): task block T Tᵀ + λI on the first
// `rank` coordinates, λI on the rest; inequality rows 0..rows−1 hard with their relaxations.
void HierarchicalQp::setUpLevelQp(QpSolver& qp, const TaskStack& stack, int r, int rank, int m,
                                  int rowsAbove, int rows) {
  qp.resize(r, 0, rows);
  auto H = qp.H();
  H.diagonal().setConstant(settings_.regularization);
  if (rank > 0 && damped_) {  // as taskStep: damped along the ill-conditioned pivots
    const auto T = T_.topLeftCorner(rank, m);
    H.topLeftCorner(rank, rank).noalias() += T * T.transpose();
    H.diagonal().head(rank) += rowWeight_.head(rank);
    qp.g().head(rank).noalias() = -T * e_.segment(m, m);
  } else if (rank > 0) {
    const auto T = T_.topLeftCorner(rank, m);
    H.topLeftCorner(rank, rank).noalias() += T * T.transpose();
    qp.g().head(rank).noalias() = -T * e_.segment(m, m);
  }
  if (rows > 0) {
    qp.C() = DZ_.topLeftCorner(rows, r);
    for (int i = 0; i < rows; ++i) {
      qp.lower()[i] = stack.lower()[i] - relax_[i] - Dx_[i];
      qp.upper()[i] = stack.upper()[i] + relax_[i] - Dx_[i];
    }
    keepAnswerAboveFeasible(qp, rowsAbove);
  }
}

// Rows of the levels above hold at x up to the tolerance they were accepted with; let them stay
// as they are (w = 0 feasible) but not get worse. Without this, a row met to within 1e-11 on a
// degenerate vertex (a friction pyramid's apex with no freedom left to move that force) makes
// every QP below infeasible.
void HierarchicalQp::keepAnswerAboveFeasible(QpSolver& qp, int rowsAbove) const {
  for (int i = 0; i < rowsAbove; ++i) {
    qp.lower()[i] = std::min(qp.lower()[i], 0.0);
    qp.upper()[i] = std::max(qp.upper()[i], 0.0);
  }
}

// Minimal slacks for level k's own inequality rows (rowsAbove..rows−1), the rows above hard:
// minimise ½‖s‖² + ½λ‖w‖², row + s ≥ lower, row − s ≤ upper, s ≥ 0. Sets relax_ for the rows and
// w_ (r) to the slack problem's step.
bool HierarchicalQp::solveSlackQp(const TaskStack& stack, int k, int r, int rowsAbove, int rows) {
  const int p = rows - rowsAbove;
  int sides = 0;
  for (int i = rowsAbove; i < rows; ++i)
    sides += (stack.lower()[i] > -kInf) + (stack.upper()[i] < kInf);
  QpSolver& qp = qp_.back();
  qp.resize(r + p, 0, rowsAbove + sides);
  qp.H().diagonal().head(r).setConstant(settings_.regularization);
  qp.H().diagonal().tail(p).setOnes();
  auto C = qp.C();
  for (int i = 0; i < rowsAbove; ++i) {
    C.row(i).head(r) = DZ_.row(i).head(r);
    qp.lower()[i] = stack.lower()[i] - relax_[i] - Dx_[i];
    qp.upper()[i] = stack.upper()[i] + relax_[i] - Dx_[i];
  }
  keepAnswerAboveFeasible(qp, rowsAbove);
  int row = rowsAbove;
  for (int i = rowsAbove; i < rows; ++i) {
    const int s = r + (i - rowsAbove);
    if (stack.lower()[i] > -kInf) {
      C.row(row).head(r) = DZ_.row(i).head(r);
      C(row, s) = 1.0;
      qp.lower()[row++] = stack.lower()[i] - Dx_[i];
    }
    if (stack.upper()[i] < kInf) {
      C.row(row).head(r) = DZ_.row(i).head(r);
      C(row, s) = -1.0;
      qp.upper()[row++] = stack.upper()[i] - Dx_[i];
    }
  }
  qp.lowerBound().tail(p).setZero();
  const QpStatus status = qp.solve();
  levels_[k].iterations += qp.result().iterations;
  if (status != QpStatus::kOptimal) return false;
  const double tol = settings_.feasibilityTolerance;
  for (int i = rowsAbove; i < rows; ++i) {
    const double bound = std::max(std::abs(stack.lower()[i]) < kInf ? std::abs(stack.lower()[i]) : 0.0,
                                  std::abs(stack.upper()[i]) < kInf ? std::abs(stack.upper()[i]) : 0.0);
    const double s = qp.x()[r + (i - rowsAbove)];
    relax_[i] = s > tol * std::max(1.0, bound) ? s + tol * std::max(1.0, bound) : 0.0;
  }
  w_.head(r) = qp.x().head(r);
  return true;
}

HqpStatus HierarchicalQp::solve(const TaskStack& stack) {
  if (stack.variables() != n_ || stack.levels() > static_cast<int>(levels_.size()) ||
      stack.totalInequalityRows() > maxInequalityRows_)
    throw std::invalid_argument("HierarchicalQp::solve: the stack exceeds the solver's capacity");
  for (int k = 0; k < stack.levels(); ++k)
    if (stack.equalityRows(k) > maxLevelRows_)
      throw std::invalid_argument("HierarchicalQp::solve: level " + std::to_string(k) +
                                  " has more equality rows than the capacity");
  for (auto& qp : qp_) qp.settings() = settings_.qp;  // settings may have changed since
  x_.setZero();
  Z_.setZero();
  Z_.diagonal() = scale_;
  int r = n_;
  rowsInForce_ = 0;
  HqpStatus status = HqpStatus::kOk;
  bool failed = false;

  for (auto& level : levels_) level = HqpLevelResult{};
  for (int k = 0; k < stack.levels(); ++k) {
    HqpLevelResult& level = levels_[k];
    if (failed) {
      level.skipped = true;
      level.freedom = r;
      continue;
    }
    const int m = stack.equalityRows(k), p = stack.inequalityRows(k);
    const int rowsAbove = rowsInForce_, rows = rowsAbove + p;
    relax_.segment(rowsAbove, p).setZero();
    const int rank = taskStep(stack, k, r, level);

    if (feasible(stack, xc_, rows)) {
      x_ = xc_;
    } else {
      // The least-squares step breaks an inequality: solve the level's QP.
      DZ_.topLeftCorner(rows, r).noalias() = stack.D().topRows(rows) * Zp_.leftCols(r);
      Dx_.head(rows).noalias() = stack.D().topRows(rows) * x_;
      QpSolver& qp = qp_[k];
      setUpLevelQp(qp, stack, r, rank, m, rowsAbove, rows);
      QpStatus qpStatus = qp.solve();
      level.qpSolved = true;
      level.iterations += qp.result().iterations;
      if (qpStatus == QpStatus::kInfeasible && p > 0) {
        if (solveSlackQp(stack, k, r, rowsAbove, rows)) {
          level.relaxed = true;
          status = HqpStatus::kRelaxed;
          setUpLevelQp(qp, stack, r, rank, m, rowsAbove, rows);
          qpStatus = qp.solve();
          level.iterations += qp.result().iterations;
          if (qpStatus != QpStatus::kOptimal) {  // the slack step itself is feasible
            qpStatus = QpStatus::kOptimal;
            x_.noalias() += Zp_.leftCols(r) * w_.head(r);
          } else {
            x_.noalias() += Zp_.leftCols(r) * qp.x();
          }
        }
      } else if (qpStatus == QpStatus::kOptimal) {
        x_.noalias() += Zp_.leftCols(r) * qp.x();
      }
      level.qpStatus = qpStatus;
      if (qpStatus != QpStatus::kOptimal) {
        failed = true;
        status = HqpStatus::kFailed;
        level.freedom = r;
        continue;
      }
    }
    rowsInForce_ = rows;
    if (rank > 0) Z_.leftCols(r - rank) = Zp_.middleCols(rank, r - rank);
    r -= rank;
    level.rank = rank;
    level.freedom = r;
  }
  for (int k = 0; k < stack.levels(); ++k) levels_[k].residual = stack.residual(k, x_);
  return status;
}

}  // namespace ballast::wbc
