// A dense convex quadratic program, solved by a dual active-set method (Goldfarb & Idnani 1983,
// "A numerically stable dual method for solving strictly convex quadratic programs"):
//
//   minimise    ½ xᵀ H x + gᵀ x                     x ∈ ℝⁿ, H symmetric positive (semi)definite
//   subject to  A x = b                              me equality rows
//               lower ≤ C x ≤ upper                  mi two-sided rows (±∞ for an absent side)
//               lowerBound ≤ x ≤ upperBound          n simple bounds (±∞ for an absent side)
//
// Why dual: starting from the unconstrained minimum, each iteration adds the most violated
// constraint (scaled by its row norm) and drops one whose multiplier would turn negative, so
// every iterate is dual feasible and the optimum is reached in about as many iterations as
// there are active constraints; infeasibility shows up as a violated constraint that no step
// can repair. The factorisation J = L⁻ᵀQ, R (Hx = LLᵀ, JᵀN = [R; 0] for the active normals N)
// is updated by Givens rotations: O(n²) per added or dropped constraint.
//
// Memory: every buffer is sized at construction for the capacity given; resize() and solve()
// never allocate, so the solver can live in the 1 kHz path.
//
// Warm start: solve() first re-activates the previous solution's active set (its inequality
// and bound entries, those still valid for the current sizes), drops the ones whose multiplier
// comes out negative, and continues with ordinary dual iterations from that dual-feasible
// point. For a strictly convex QP the result is the same optimum as a cold start.
//
// Degenerate data:
//  * H semidefinite (a Cholesky pivot L_ii² below settings.regularization·max(1, max H_ii)):
//    H + ρI is used with ρ = settings.regularization·max(1, max H_ii); result().regularized says
//    so. The answer is then the optimum of the regularised problem: among minimisers of a
//    semidefinite problem, approximately the one of least norm.
//  * Equality rows linearly dependent on earlier ones are skipped; if such a row is not met by
//    the final x (inconsistent equalities), the status is kInfeasible.
//
// Failure results are always finite and flagged by the status:
//  * kInvalidInput: non-finite data, lower > upper, or H not positive semidefinite: x = 0.
//  * kInfeasible / kIterationLimit: x is the last iterate, the minimiser over the equalities and
//    the constraints activated so far; result().maxViolation says by how much it misses the rest.
//
// Multipliers: at the solution H x + g = Aᵀλ_eq + Cᵀλ_C + λ_bound, with λ_C,i ≥ 0 when the
// lower side of row i is active, ≤ 0 when the upper side is, 0 when inactive (same for bounds).
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>

namespace ballast::wbc {

/// The value of a side that does not bind: lower = −kInf, upper = +kInf.
inline constexpr double kInf = std::numeric_limits<double>::infinity();

/// Largest problem a QpSolver instance can take.
struct QpCapacity {
  int variables = 0;
  int equalities = 0;
  int inequalities = 0;
};

struct QpSettings {
  int maxIterations = 200;          ///< added + dropped constraints before kIterationLimit
  double feasibilityTolerance = 1e-10;  ///< row violation accepted, relative to max(1, |bound|)
  double dependenceTolerance = 1e-11;   ///< a normal whose null-space part is this small (relative) is dependent
  double regularization = 1e-10;    ///< ρ (relative to max(1, max H_ii)) for semidefinite H
  bool warmStart = true;            ///< begin from the previous solution's active set
};

enum class QpStatus : std::uint8_t {
  kOptimal,
  kInfeasible,      ///< constraints cannot all be met (x: last iterate, see maxViolation)
  kIterationLimit,  ///< settings.maxIterations reached (x: last iterate)
  kInvalidInput,    ///< non-finite data, crossed bounds or indefinite H (x = 0)
};
const char* toString(QpStatus status);

struct QpResult {
  QpStatus status = QpStatus::kInvalidInput;
  const char* reason = "not solved yet";  ///< static text for failures ("" when optimal)
  int iterations = 0;          ///< constraints added or dropped
  int activeConstraints = 0;   ///< equalities included
  int dependentEqualities = 0; ///< equality rows skipped as linearly dependent
  bool regularized = false;    ///< H + ρI was used
  double objective = 0.0;      ///< ½xᵀHx + gᵀx with the H given
  double maxViolation = 0.0;   ///< largest absolute violation of any constraint by x
};

/// One entry of an active set: which inequality row or bound, and which side.
struct QpActiveConstraint {
  enum Kind : std::uint8_t { kInequality, kBound };
  Kind kind = kInequality;
  int index = 0;
  std::int8_t side = +1;  ///< +1: lower side active, −1: upper side active
};

class QpSolver {
 public:
  using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

  explicit QpSolver(QpCapacity capacity, QpSettings settings = {});

  /// Sizes of the next problem (within the capacity; throws std::invalid_argument otherwise) and
  /// its data reset to: H = 0, g = 0, A = 0, b = 0, C = 0, C rows and bounds unbounded (±∞).
  /// The previous active set is kept for the warm start.
  void resize(int variables, int equalities, int inequalities);

  // The problem data, written in place (views into preallocated storage).
  Eigen::Block<Eigen::MatrixXd> H() { return H_.topLeftCorner(n_, n_); }
  Eigen::VectorBlock<Eigen::VectorXd> g() { return g_.head(n_); }
  Eigen::Block<RowMatrix> A() { return A_.topLeftCorner(me_, n_); }
  Eigen::VectorBlock<Eigen::VectorXd> b() { return b_.head(me_); }
  Eigen::Block<RowMatrix> C() { return C_.topLeftCorner(mi_, n_); }
  Eigen::VectorBlock<Eigen::VectorXd> lower() { return lower_.head(mi_); }
  Eigen::VectorBlock<Eigen::VectorXd> upper() { return upper_.head(mi_); }
  Eigen::VectorBlock<Eigen::VectorXd> lowerBound() { return lowerBound_.head(n_); }
  Eigen::VectorBlock<Eigen::VectorXd> upperBound() { return upperBound_.head(n_); }

  /// Solves the problem held; allocates nothing. See the header comment for failure results.
  QpStatus solve();

  const QpResult& result() const { return result_; }
  Eigen::VectorBlock<const Eigen::VectorXd> x() const { return x_.head(n_); }
  Eigen::VectorBlock<const Eigen::VectorXd> equalityMultipliers() const { return lambdaEq_.head(me_); }
  Eigen::VectorBlock<const Eigen::VectorXd> inequalityMultipliers() const { return lambdaC_.head(mi_); }
  Eigen::VectorBlock<const Eigen::VectorXd> boundMultipliers() const { return lambdaBound_.head(n_); }

  /// Inequality and bound entries of the last solution's active set (the warm start).
  const QpActiveConstraint* activeSet() const { return warm_.data(); }
  int activeSetSize() const { return warmSize_; }
  /// Forget the active set: the next solve starts cold.
  void clearWarmStart() { warmSize_ = 0; }

  int variables() const { return n_; }
  int equalities() const { return me_; }
  int inequalities() const { return mi_; }
  const QpCapacity& capacity() const { return capacity_; }
  QpSettings& settings() { return settings_; }

 private:
  struct Active {
    std::uint8_t kind;  // 0 equality, 1 inequality, 2 bound
    std::int8_t side;
    int index;
  };

  bool inputValid();
  bool factorize();
  double normalDot(const Active& c, const Eigen::VectorXd& v) const;
  double rhs(const Active& c) const;
  double normalNorm(const Active& c) const;
  void computeDirections(const Active& c);
  void projectNormal(const Active& c);
  void addActive(const Active& c, double multiplier);
  void dropActive(int position);
  void recomputeFromActiveSet();
  bool selectMostViolated(Active& out);
  char& isActive(const Active& c);
  void finish(QpStatus status, const char* reason);
  void computeViolation();

  QpCapacity capacity_;
  QpSettings settings_;
  int n_ = 0, me_ = 0, mi_ = 0;

  // Problem data.
  Eigen::MatrixXd H_;
  Eigen::VectorXd g_;
  RowMatrix A_;
  Eigen::VectorXd b_;
  RowMatrix C_;
  Eigen::VectorXd lower_, upper_, lowerBound_, upperBound_;

  // Factorisation and iterates.
  Eigen::MatrixXd L_, J_, R_;
  Eigen::VectorXd x_, d_, z_, r_, u_, work_;
  Eigen::VectorXd rowNormA_, rowNormC_;
  std::vector<Active> active_;  // first q_ entries used; equalities first
  std::vector<char> activeC_, activeBound_;
  std::vector<int> dependentEq_;
  int q_ = 0, qEq_ = 0, nDependent_ = 0;
  Eigen::VectorXd lambdaEq_, lambdaC_, lambdaBound_;

  std::vector<QpActiveConstraint> warm_;
  int warmSize_ = 0;

  QpResult result_;
};

}  // namespace ballast::wbc
