// Hierarchical quadratic programming over a TaskStack (Bellicoso et al., "Perception-less
// terrain adaptation through whole body control and hierarchical optimization", 2016; the
// scheme of legged_control's HoQp), as a sequence of QPs solved with QpSolver.
//
// Level k is solved in the null space of the equality tasks of levels 0..k−1:
//   x = x_{k−1} + Z_{k−1} w,      Z_0 = diag(variable scale)
//   minimise   ½‖A_k (x_{k−1} + Z_{k−1} w) − b_k‖² + ½λ‖w‖²
//   subject to the inequality rows of levels 0..k (those above relaxed by their slacks), hard;
//              rows above that x_{k−1} meets only to the tolerance may stay as they are.
// then Z_k spans the null space of A_k Z_{k−1}, so lower levels cannot change what level k and
// the levels above achieved. Inequality rows that cannot all be met get slacks s ≥ 0 (minimised:
// ½‖s‖² + ½λ‖w‖²) and stay relaxed by s for every level below.
//
// Differences from HoQp, and why:
//  * One pivoted Householder QR of (A_k Z_{k−1})ᵀ per level gives the rank, the new null-space
//    basis and the minimum-norm least-squares step together. When that step violates no
//    inequality it is the level's QP optimum (λ → 0) and no QP is solved: in steady standing
//    most levels need none. Otherwise the QP runs in the rotated coordinates, where its Hessian
//    is block-diagonal (the task block R Rᵀ + λI, and λI on the free directions).
//  * Slack QPs are solved only when a level's hard QP is infeasible (HoQp solves one every
//    level). Within a level, inequalities come before its equality task: give physics
//    equalities a level of their own above the limits and they are never traded for slack.
//  * Task rows found dependent by the pivoted QR (rank tolerance relative to the largest row)
//    drop out of the null-space update but still count in the least-squares fit.
//  * The variable scale sets the metric of the minimum-norm choices and of λ (e.g. newtons vs
//    m/s² in a whole-body controller), which keeps every QP well conditioned.
//
// All memory is sized at construction; solve() allocates nothing.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "wbc/qp_solver.hpp"
#include "wbc/task_stack.hpp"

namespace ballast::wbc {

struct HqpSettings {
  double regularization = 1e-8;         ///< λ, weight of ‖w‖² at each level (scaled units)
  double rankTolerance = 1e-9;          ///< task row dependent below this × the largest row norm
  double feasibilityTolerance = 1e-8;   ///< inequality violation accepted, × max(1, |bound|)
  QpSettings qp;                        ///< for every QP of the sequence
};

enum class HqpStatus : std::uint8_t {
  kOk,        ///< every level solved, all inequalities met
  kRelaxed,   ///< every level solved; some inequality rows needed slack (see slack())
  kFailed,    ///< a QP failed (iteration limit, numerical): that level and those below were
              ///< skipped; solution() is the last level's answer, which met the levels above
};
const char* toString(HqpStatus status);

struct HqpLevelResult {
  int rank = 0;               ///< independent task rows in the remaining null space
  int freedom = 0;            ///< null-space dimension left after the level
  bool qpSolved = false;      ///< false: the least-squares step was feasible, no QP needed
  bool relaxed = false;       ///< its inequality rows needed slack
  bool skipped = false;       ///< not solved (an earlier level failed)
  QpStatus qpStatus = QpStatus::kOptimal;
  int iterations = 0;         ///< QP iterations spent on the level
  double residual = 0.0;      ///< ‖A_k x − b_k‖ at the final x
};

class HierarchicalQp {
 public:
  /// Capacity as the stack's: variables, levels, equality rows of one level (the largest), and
  /// inequality rows in total.
  HierarchicalQp(int variables, int maxLevels, int maxLevelEqualityRows, int maxInequalityRows,
                 HqpSettings settings = {});

  /// Scale of each variable (positive; default 1): the solver works on x/scale, so this is the
  /// metric of minimum-norm choices and of the regularisation.
  void setVariableScale(const Eigen::VectorXd& scale);

  /// Solves the stack (its sizes within the capacity). Allocates nothing.
  HqpStatus solve(const TaskStack& stack);

  const Eigen::VectorXd& solution() const { return x_; }
  const HqpLevelResult& level(int k) const { return levels_[k]; }
  /// Relaxation of each inequality row of the stack (0: met as given).
  Eigen::VectorBlock<const Eigen::VectorXd> slack() const { return relax_.head(rowsInForce_); }
  int totalIterations() const;
  /// The QP solver of level k (the last one of a solve that needed it), for diagnostics.
  const QpSolver& levelQp(int k) const { return qp_[k]; }
  HqpSettings& settings() { return settings_; }

 private:
  int taskStep(const TaskStack& stack, int k, int r);
  bool feasible(const TaskStack& stack, const Eigen::VectorXd& x, int rows) const;
  void setUpLevelQp(QpSolver& qp, const TaskStack& stack, int r, int rank, int m, int rowsAbove,
                    int rows);
  void keepAnswerAboveFeasible(QpSolver& qp, int rowsAbove) const;
  bool solveSlackQp(const TaskStack& stack, int k, int r, int rowsAbove, int rows);

  int n_;
  int maxLevelRows_ = 0, maxInequalityRows_ = 0;
  HqpSettings settings_;
  Eigen::VectorXd scale_;
  Eigen::VectorXd x_, xc_, w_, e_, Dx_, relax_, work_, hCoeffs_;
  // Z: null-space basis (n × r); Zp = Z·Q of the current level; B: (A_k Z)ᵀ factorised in place;
  // T: R's leading rows; N: T Tᵀ; DZ: inequality rows in the current coordinates.
  Eigen::MatrixXd Z_, Zp_, B_, T_, N_, DZ_;
  std::vector<int> perm_;
  std::vector<QpSolver> qp_;  // one per level (warm start across ticks), the last for slacks
  std::vector<HqpLevelResult> levels_;
  int rowsInForce_ = 0;
};

}  // namespace ballast::wbc
