#include "wbc/qp_solver.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/Cholesky>

namespace ballast::wbc {

namespace {
constexpr std::uint8_t kEquality = 0, kInequality = 1, kBound = 2;

/// √(a² + b²) without std::hypot's overflow guard (a fifth of a solve's time); the entries of J
/// and R are far from the range where a² overflows.
inline double norm2(double a, double b) { return std::sqrt(a * a + b * b); }

/// Rotates columns a and b of M: (a, b) <- (c·a + s·b, −s·a + c·b).
template <typename M, typename W>
void rotateColumns(M&& m, int a, int b, double c, double s, W&& work) {
  work = c * m.col(a) + s * m.col(b);
  m.col(b) = -s * m.col(a) + c * m.col(b);
  m.col(a) = work;
}
}  // namespace

const char* toString(QpStatus status) {
  switch (status) {
    case QpStatus::kOptimal: return "optimal";
    case QpStatus::kInfeasible: return "infeasible";
    case QpStatus::kIterationLimit: return "iteration limit";
    case QpStatus::kInvalidInput: return "invalid input";
  }
  return "unknown";
}

QpSolver::QpSolver(QpCapacity capacity, QpSettings settings)
    : capacity_(capacity), settings_(settings) {
  if (capacity.variables < 1 || capacity.equalities < 0 || capacity.inequalities < 0)
    throw std::invalid_argument("QpSolver: capacity needs at least one variable and no negative "
                                "row counts");
  const int n = capacity.variables, me = capacity.equalities, mi = capacity.inequalities;
  H_.setZero(n, n);
  g_.setZero(n);
  A_.setZero(std::max(me, 1), n);
  b_.setZero(std::max(me, 1));
  C_.setZero(std::max(mi, 1), n);
  lower_.setZero(std::max(mi, 1));
  upper_.setZero(std::max(mi, 1));
  lowerBound_.setZero(n);
  upperBound_.setZero(n);
  L_.setZero(n, n);
  J_.setZero(n, n);
  R_.setZero(n, n);
  x_.setZero(n);
  d_.setZero(n);
  z_.setZero(n);
  r_.setZero(n);
  u_.setZero(n);
  work_.setZero(std::max(n, std::max(me, mi)));
  rowNormA_.setZero(std::max(me, 1));
  rowNormC_.setZero(std::max(mi, 1));
  active_.resize(n);
  activeC_.assign(std::max(mi, 1), 0);
  activeBound_.assign(n, 0);
  dependentEq_.assign(std::max(me, 1), 0);
  lambdaEq_.setZero(std::max(me, 1));
  lambdaC_.setZero(std::max(mi, 1));
  lambdaBound_.setZero(n);
  warm_.resize(n);
  resize(n, me, mi);
}

void QpSolver::resize(int variables, int equalities, int inequalities) {
  if (variables < 1 || variables > capacity_.variables || equalities < 0 ||
      equalities > capacity_.equalities || inequalities < 0 ||
      inequalities > capacity_.inequalities)
    throw std::invalid_argument(
        "QpSolver::resize: " + std::to_string(variables) + " variables, " +
        std::to_string(equalities) + " equalities, " + std::to_string(inequalities) +
        " inequalities exceed the capacity (" + std::to_string(capacity_.variables) + ", " +
        std::to_string(capacity_.equalities) + ", " + std::to_string(capacity_.inequalities) + ")");
  n_ = variables;
  me_ = equalities;
  mi_ = inequalities;
  H().setZero();
  g().setZero();
  A().setZero();
  b().setZero();
  C().setZero();
  lower().setConstant(-kInf);
  upper().setConstant(kInf);
  lowerBound().setConstant(-kInf);
  upperBound().setConstant(kInf);
}

bool QpSolver::inputValid() {
  const auto finite = [](const auto& m) { return m.allFinite(); };
  if (!finite(H()) || !finite(g()) || !finite(A()) || !finite(b()) || !finite(C())) {
    result_.reason = "H, g, A, b or C holds a NaN or an infinity";
    return false;
  }
  const auto sidesValid = [](double lo, double hi) {
    return !std::isnan(lo) && !std::isnan(hi) && lo <= hi && lo < kInf && hi > -kInf;
  };
  for (int i = 0; i < mi_; ++i)
    if (!sidesValid(lower_[i], upper_[i])) {
      result_.reason = "a row of C has lower > upper, a NaN side, or lower = +inf / upper = -inf";
      return false;
    }
  for (int i = 0; i < n_; ++i)
    if (!sidesValid(lowerBound_[i], upperBound_[i])) {
      result_.reason = "a bound has lower > upper, a NaN side, or lower = +inf / upper = -inf";
      return false;
    }
  return true;
}

bool QpSolver::factorize() {
  const int n = n_;
  const double scale = std::max(1.0, H().diagonal().cwiseAbs().maxCoeff());
  const double rho = settings_.regularization * scale;
  auto L = L_.topLeftCorner(n, n);
  L = H();
  {
    Eigen::Ref<Eigen::MatrixXd> ref(L);
    Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> llt(ref);
    const bool ok = llt.info() == Eigen::Success &&
                    L.diagonal().cwiseAbs2().minCoeff() > rho;
    if (!ok) {
      L = H();
      L.diagonal().array() += rho;
      Eigen::Ref<Eigen::MatrixXd> ref2(L);
      Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> llt2(ref2);
      if (llt2.info() != Eigen::Success) return false;
      result_.regularized = true;
    }
  }
  // J = L⁻ᵀ: the columns are H-conjugate directions, JᵀHJ = I.
  auto J = J_.topLeftCorner(n, n);
  J.setIdentity();
  L.triangularView<Eigen::Lower>().transpose().solveInPlace(J);
  return J.allFinite();
}

double QpSolver::normalDot(const Active& c, const Eigen::VectorXd& v) const {
  switch (c.kind) {
    case kEquality: return A_.row(c.index).head(n_).dot(v.head(n_));
    case kInequality: return c.side * C_.row(c.index).head(n_).dot(v.head(n_));
    default: return c.side * v[c.index];
  }
}

double QpSolver::rhs(const Active& c) const {
  switch (c.kind) {
    case kEquality: return b_[c.index];
    case kInequality: return c.side > 0 ? lower_[c.index] : -upper_[c.index];
    default: return c.side > 0 ? lowerBound_[c.index] : -upperBound_[c.index];
  }
}

double QpSolver::normalNorm(const Active& c) const {
  switch (c.kind) {
    case kEquality: return rowNormA_[c.index];
    case kInequality: return rowNormC_[c.index];
    default: return 1.0;
  }
}

char& QpSolver::isActive(const Active& c) {
  return c.kind == kInequality ? activeC_[c.index] : activeBound_[c.index];
}

// d = Jᵀn, z = J₂d₂ (primal step direction), r = R⁻¹d₁ (dual step direction).
void QpSolver::computeDirections(const Active& c) {
  const int n = n_, q = q_;
  projectNormal(c);
  const auto J = J_.topLeftCorner(n, n);
  z_.head(n).noalias() = J.rightCols(n - q) * d_.segment(q, n - q);
  r_.head(q) = d_.head(q);
  R_.topLeftCorner(q, q).triangularView<Eigen::Upper>().solveInPlace(r_.head(q));
}

// d = Jᵀn only.
void QpSolver::projectNormal(const Active& c) {
  const int n = n_;
  const auto J = J_.topLeftCorner(n, n);
  switch (c.kind) {
    case kEquality:
      d_.head(n).noalias() = J.transpose() * A_.row(c.index).head(n).transpose();
      break;
    case kInequality:
      d_.head(n).noalias() = J.transpose() * C_.row(c.index).head(n).transpose();
      if (c.side < 0) d_.head(n) = -d_.head(n);
      break;
    default:
      d_.head(n) = c.side * J.row(c.index).transpose();
  }
}

// Appends c to the active set; d_ must hold Jᵀn for c. Rotations fold d₂ into its first entry.
void QpSolver::addActive(const Active& c, double multiplier) {
  const int n = n_;
  auto J = J_.topLeftCorner(n, n);
  for (int j = n - 1; j > q_; --j) {
    const double a = d_[j - 1], b = d_[j];
    if (b == 0.0) continue;
    const double h = norm2(a, b);
    d_[j - 1] = h;
    d_[j] = 0.0;
    rotateColumns(J, j - 1, j, a / h, b / h, work_.head(n));
  }
  R_.col(q_).head(q_ + 1) = d_.head(q_ + 1);
  active_[q_] = c;
  u_[q_] = multiplier;
  if (c.kind != kEquality) isActive(c) = 1;
  ++q_;
}

// Removes the active constraint at `position`; rotations restore R's triangular shape.
void QpSolver::dropActive(int position) {
  const int n = n_;
  isActive(active_[position]) = 0;
  for (int k = position; k < q_ - 1; ++k) {
    active_[k] = active_[k + 1];
    u_[k] = u_[k + 1];
    R_.col(k).head(k + 2) = R_.col(k + 1).head(k + 2);
  }
  --q_;
  auto J = J_.topLeftCorner(n, n);
  for (int j = position; j < q_; ++j) {
    const double a = R_(j, j), b = R_(j + 1, j);
    if (b == 0.0) continue;
    const double h = norm2(a, b), c = a / h, s = b / h;
    R_(j, j) = h;
    R_(j + 1, j) = 0.0;
    for (int k = j + 1; k < q_; ++k) {
      const double t1 = R_(j, k), t2 = R_(j + 1, k);
      R_(j, k) = c * t1 + s * t2;
      R_(j + 1, k) = -s * t1 + c * t2;
    }
    rotateColumns(J, j, j + 1, c, s, work_.head(n));
  }
}

// The minimiser with the active set as equalities, and its multipliers, in closed form:
// x = J₁R⁻ᵀb_A − J₂J₂ᵀg,  u = R⁻¹(R⁻ᵀb_A + J₁ᵀg).
void QpSolver::recomputeFromActiveSet() {
  const int n = n_, q = q_;
  const auto J = J_.topLeftCorner(n, n);
  const auto R = R_.topLeftCorner(q, q);
  for (int k = 0; k < q; ++k) work_[k] = rhs(active_[k]);
  R.triangularView<Eigen::Upper>().transpose().solveInPlace(work_.head(q));
  d_.segment(q, n - q).noalias() = J.rightCols(n - q).transpose() * g_.head(n);
  x_.head(n).noalias() = J.leftCols(q) * work_.head(q);
  x_.head(n).noalias() -= J.rightCols(n - q) * d_.segment(q, n - q);
  u_.head(q) = work_.head(q);
  u_.head(q).noalias() += J.leftCols(q).transpose() * g_.head(n);
  R.triangularView<Eigen::Upper>().solveInPlace(u_.head(q));
}

// The inactive constraint with the largest violation per unit row norm.
bool QpSolver::selectMostViolated(Active& out) {
  const double tol = settings_.feasibilityTolerance;
  double best = 0.0;
  bool found = false;
  auto consider = [&](std::uint8_t kind, int index, double value, double lo, double hi,
                      double norm) {
    const double scale = norm > 0.0 ? norm : 1.0;
    if (lo > -kInf && lo - value > tol * std::max(1.0, std::abs(lo)) &&
        (lo - value) / scale > best) {
      best = (lo - value) / scale;
      out = Active{kind, +1, index};
      found = true;
    }
    if (hi < kInf && value - hi > tol * std::max(1.0, std::abs(hi)) &&
        (value - hi) / scale > best) {
      best = (value - hi) / scale;
      out = Active{kind, -1, index};
      found = true;
    }
  };
  if (mi_ > 0) work_.head(mi_).noalias() = C_.topLeftCorner(mi_, n_) * x_.head(n_);
  for (int i = 0; i < mi_; ++i)
    if (!activeC_[i]) consider(kInequality, i, work_[i], lower_[i], upper_[i], rowNormC_[i]);
  for (int i = 0; i < n_; ++i)
    if (!activeBound_[i]) consider(kBound, i, x_[i], lowerBound_[i], upperBound_[i], 1.0);
  return found;
}

void QpSolver::computeViolation() {
  double worst = 0.0;
  for (int i = 0; i < me_; ++i)
    worst = std::max(worst, std::abs(A_.row(i).head(n_).dot(x_.head(n_)) - b_[i]));
  for (int i = 0; i < mi_; ++i) {
    const double v = C_.row(i).head(n_).dot(x_.head(n_));
    worst = std::max({worst, lower_[i] - v, v - upper_[i]});
  }
  for (int i = 0; i < n_; ++i)
    worst = std::max({worst, lowerBound_[i] - x_[i], x_[i] - upperBound_[i]});
  result_.maxViolation = worst;
}

void QpSolver::finish(QpStatus status, const char* reason) {
  if (status != QpStatus::kInvalidInput && !x_.head(n_).allFinite()) {
    status = QpStatus::kInvalidInput;
    reason = "numerical breakdown (non-finite iterate)";
  }
  lambdaEq_.head(me_).setZero();
  lambdaC_.head(mi_).setZero();
  lambdaBound_.head(n_).setZero();
  if (status == QpStatus::kInvalidInput) {
    x_.head(n_).setZero();
    q_ = 0;
  }
  warmSize_ = 0;
  for (int k = 0; k < q_; ++k) {
    const Active& c = active_[k];
    switch (c.kind) {
      case kEquality: lambdaEq_[c.index] = u_[k]; break;
      case kInequality: lambdaC_[c.index] = c.side * u_[k]; break;
      default: lambdaBound_[c.index] = c.side * u_[k];
    }
    if (c.kind != kEquality && status == QpStatus::kOptimal)
      warm_[warmSize_++] = QpActiveConstraint{
          c.kind == kInequality ? QpActiveConstraint::kInequality : QpActiveConstraint::kBound,
          c.index, c.side};
  }
  result_.status = status;
  result_.reason = reason;
  result_.activeConstraints = q_;
  result_.dependentEqualities = nDependent_;
  const auto x = x_.head(n_);
  work_.head(n_).noalias() = H() * x;
  result_.objective = 0.5 * x.dot(work_.head(n_)) + g().dot(x);
  computeViolation();
}

QpStatus QpSolver::solve() {
  const int n = n_;
  result_ = QpResult{};
  q_ = qEq_ = nDependent_ = 0;
  std::fill(activeC_.begin(), activeC_.begin() + std::max(mi_, 1), 0);
  std::fill(activeBound_.begin(), activeBound_.begin() + n, 0);

  if (!inputValid()) {
    finish(QpStatus::kInvalidInput, result_.reason);
    return result_.status;
  }
  for (int i = 0; i < me_; ++i) rowNormA_[i] = A_.row(i).head(n).norm();
  for (int i = 0; i < mi_; ++i) rowNormC_[i] = C_.row(i).head(n).norm();
  if (!factorize()) {
    finish(QpStatus::kInvalidInput, "H is not positive semidefinite");
    return result_.status;
  }
  const auto J = J_.topLeftCorner(n, n);
  d_.head(n).noalias() = J.transpose() * g_.head(n);
  x_.head(n).noalias() = -J * d_.head(n);  // unconstrained minimum −H⁻¹g

  // A constraint is dependent on the active set when its normal has (almost) no component in
  // the remaining free directions J₂.
  auto dependent = [&](double d2norm) {
    return d2norm <= settings_.dependenceTolerance * std::max(d_.head(n).norm(), 1e-300);
  };
  // Equalities and the warm start's constraints join the active set regardless of the
  // multipliers' signs: only the factorisation is updated here; x and the multipliers follow in
  // closed form once all have joined.
  auto forceActive = [&](const Active& c) {
    projectNormal(c);
    if (dependent(d_.segment(q_, n - q_).norm())) return false;
    addActive(c, 0.0);
    return true;
  };

  for (int i = 0; i < me_; ++i) {
    if (forceActive(Active{kEquality, +1, i})) {
      ++qEq_;
    } else {
      dependentEq_[nDependent_++] = i;
    }
  }

  if (settings_.warmStart && warmSize_ > 0) {
    for (int k = 0; k < warmSize_ && q_ < n; ++k) {
      const QpActiveConstraint& w = warm_[k];
      const bool isRow = w.kind == QpActiveConstraint::kInequality;
      if (w.index < 0 || w.index >= (isRow ? mi_ : n)) continue;
      const Active c{isRow ? kInequality : kBound, w.side, w.index};
      const double side = isRow ? (w.side > 0 ? lower_[w.index] : upper_[w.index])
                                : (w.side > 0 ? lowerBound_[w.index] : upperBound_[w.index]);
      if (!std::isfinite(side) || isActive(c)) continue;
      forceActive(c);
    }
  }
  if (q_ > 0) recomputeFromActiveSet();
  if (q_ > qEq_) {
    // Back to dual feasibility: drop the most negative inequality multiplier until none is left.
    for (;;) {
      int worst = -1;
      for (int k = qEq_; k < q_; ++k)
        if (u_[k] < 0.0 && (worst < 0 || u_[k] < u_[worst])) worst = k;
      if (worst < 0) break;
      dropActive(worst);
      ++result_.iterations;
      recomputeFromActiveSet();
    }
  }

  Active c{};
  while (selectMostViolated(c)) {
    double s = normalDot(c, x_) - rhs(c);  // < 0: violated
    double multiplier = 0.0;
    for (;;) {
      if (++result_.iterations > settings_.maxIterations) {
        finish(QpStatus::kIterationLimit, "iteration limit reached");
        return result_.status;
      }
      computeDirections(c);
      const double d2sq = d_.segment(q_, n - q_).squaredNorm();
      // Dual step length: the first active inequality whose multiplier reaches zero.
      double t1 = kInf;
      int blocking = -1;
      for (int k = qEq_; k < q_; ++k)
        if (r_[k] > 0.0 && u_[k] / r_[k] < t1) {
          t1 = std::max(0.0, u_[k] / r_[k]);
          blocking = k;
        }
      // Primal step length: the full step that satisfies c.
      const double t2 = dependent(std::sqrt(d2sq)) ? kInf : -s / d2sq;
      if (t1 == kInf && t2 == kInf) {
        finish(QpStatus::kInfeasible, "the constraints cannot all be satisfied");
        return result_.status;
      }
      if (t2 == kInf) {  // c depends on the active set: step in the dual space only
        u_.head(q_) -= t1 * r_.head(q_);
        multiplier += t1;
        dropActive(blocking);
        continue;
      }
      const double t = std::min(t1, t2);
      x_.head(n) += t * z_.head(n);
      u_.head(q_) -= t * r_.head(q_);
      multiplier += t;
      s += t * d2sq;
      if (t2 <= t1) {
        addActive(c, multiplier);
        break;
      }
      dropActive(blocking);
    }
  }

  // The iterate accumulates rounding over the steps (badly so when H was regularised and the
  // unconstrained minimum lies far away): recompute it from the final active set.
  recomputeFromActiveSet();
  for (int k = 0; k < nDependent_; ++k) {
    const int i = dependentEq_[k];
    const double residual = A_.row(i).head(n).dot(x_.head(n)) - b_[i];
    const double scale = std::max({1.0, std::abs(b_[i]), rowNormA_[i] * x_.head(n).norm()});
    if (std::abs(residual) > 100.0 * settings_.feasibilityTolerance * scale) {
      finish(QpStatus::kInfeasible, "linearly dependent equality rows are inconsistent");
      return result_.status;
    }
  }
  finish(QpStatus::kOptimal, "");
  return result_.status;
}

}  // namespace ballast::wbc
