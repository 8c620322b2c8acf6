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
//  * Ill-conditioned directions are damped. A task row whose part outside the span of the rows
//    before it (the levels above included) is small next to the row itself asks for a direction
//    the remaining freedom reaches only by huge steps: on a robot whose feet cannot yaw relative
//    to the pelvis (no hip yaw), the relative yaw of two stance feet, or the base's yaw over one
//    stance foot, is reachable only through a near-singular leg posture, and an exact solve turns
//    a millimetre of inconsistency in those rows into accelerations of thousands of rad/s². So a
//    pivot ρ_j = |R_jj|/‖row‖ (the sine of the angle between the row and what came before it)
//    below settings.dampingBelow gets d_j² = (μ‖row‖)² on its diagonal (μ: settings.damping):
//    the level minimises ½‖A_k x − b_k‖² + ½Σ d_j² w_j², which leaves the other rows met as
//    before and takes ρ²/(ρ² + μ²) of the exact step along that direction (at most 1/(2μ‖row‖)
//    per unit of residual). The direction stays out of the null space, so the levels below
//    cannot push along it either. Below settings.dependentBelow the row counts as dependent, as
//    rows under the rank tolerance do (the QR takes the row most independent of the others
//    instead, and stops when none is above it). A level without such pivots is solved as
//    before, bit for bit. (The humanoid's base level has such pivots for some ticks too: 230 of
//    the ticks of a 10 s walk at 0.5 m/s, two 60 N pushes and a stop from 1.2 m/s, down to 6e-6.)
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
  /// A row whose part outside the rows before it is below this × its norm counts as dependent.
  double dependentBelow = 1e-4;
  /// Pivots below this, relative to their row's norm, are damped (see the header comment); 0
  /// turns damping off.
  double dampingBelow = 3e-4;
  double damping = 1e-3;                ///< μ of damped levels (relative to the rows' norms)
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
  /// Smallest pivot of the level's independent rows relative to the row's norm (1: orthogonal to
  /// everything above; small: nearly dependent); 1 for a level without task rows.
  double conditioning = 1.0;
  bool damped = false;        ///< some of its directions were damped (conditioning < dampingBelow)
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
  int taskStep(const TaskStack& stack, int k, int r, HqpLevelResult& level);
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
  Eigen::VectorXd rowNorm_, rowWeight_;  // task rows' scaled norms; each pivot's damping d_j²
  bool damped_ = false;                  // the current level is damped
  // Z: null-space basis (n × r); Zp = Z·Q of the current level; B: (A_k Z)ᵀ factorised in place;
  // T: R's leading rows; N: T Tᵀ; DZ: inequality rows in the current coordinates.
  Eigen::MatrixXd Z_, Zp_, B_, T_, N_, DZ_;
  std::vector<int> perm_;
  std::vector<QpSolver> qp_;  // one per level (warm start across ticks), the last for slacks
  std::vector<HqpLevelResult> levels_;
  int rowsInForce_ = 0;
};

}  // namespace ballast::wbc
