// Multiple-shooting Gauss-Newton SQP for an optimal control problem (the kino-dynamic one of
// kinodynamic_problem.hpp), one real-time iteration per iterate() call, and in solve() more while
// the plan is far from feasible (the paper solves it with OCS2's
// SQP at ~100 Hz; this is ours, on Eigen).
//
// iterate(t0, x̂):
//   1. warm start: the previous solution shifted to the new grid t0 + k·dt (inputs of contact
//      points whose mode changed are reset: zero force on a new swing, the reference force on a
//      new stance); the first node is set to the measured state x̂;
//   2. linearise every node and project out its equalities, spread over `threads` cores, from
//      the last node down;
//   3. solve the LQ subproblem with a Riccati sweep (riccati_solver.hpp): its backward pass on
//      the calling thread, node by node as their projections are done (it needs only the
//      nodes after the one it takes), so that it overlaps step 2 instead of following it; the
//      arithmetic, and so the result, is the same whichever thread projected a node;
//   4. line search on cost and constraint violation (a filter as in OCS2's SQP): accept the
//      largest step 1, ½, ¼, … that lowers the violation, or the cost while the violation
//      stays small;
//   5. keep the result — or, on failure (rank-deficient constraints, indefinite Hessian, NaN,
//      no acceptable step from an infeasible iterate), keep the previous solution and report
//      why. A feasible iterate that no step improves is converged: kept, with step 0.
// The caller fills references() for the N+1 node times before each call.
//
// prepare(t0), between iterations (real-time iteration's preparation phase): most of steps 2
// and 3, done ahead while the caller waits for its next measurement. A node's matrices
// (dynamics, equality Jacobians, cost Hessians), their projection and the sweep's matrices
// depend on the nodes' points (x, u) and contact modes only; the rest of the references enters
// only the vectors (residuals, gradients). The caller fills references() with what it expects
// at t0: their contact modes, and the inputs step 1 gives a point whose mode changes
// (OptimalControlProblem::adaptInputToMode); their other values are not used. prepare takes
// the warm start step 1 would take, linearises nodes 1..N−1 there, projects their matrices
// and sweeps them. An iterate() at that t0 then computes only the vectors of each node whose
// warm start is that point to the bit in the mode prepared (all but node 0 where the
// expectation held), and sweeps only the vectors from the last node down to the first that
// changed: the same plan to the bit, sooner.
#pragma once

#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "mpc/optimal_control_problem.hpp"
#include "mpc/parallel_for.hpp"
#include "mpc/riccati_solver.hpp"
#include "mpc/solution.hpp"

namespace ballast::mpc {

/// The grid and threads come from the profile (planner.*); the line search's constants are ours.
struct SqpSettings {
  int nodes;            ///< N; horizon = N·dt
  double dt;            ///< s
  int threads;          ///< cores used for linearisation and projection
  double stepDecay = 0.5;
  double minStep = 1e-3;
  double constraintLarge = 1e-2;   ///< above: a step must reduce the violation (OCS2 g_max)
  double constraintSmall = 1e-6;   ///< below: a step must reduce the cost (OCS2 g_min)
  double armijo = 1e-4;
  double filterMargin = 1e-6;      ///< γ_c
  /// solve(): iterations at most; past the first, only while the violation (SqpStatistics) is
  /// over violationTolerance.
  int maxIterations = 1;
  double violationTolerance = 1.0;
};

struct SqpStatistics {
  /// Wall time of the parallel pass over the nodes, split between linearisation, the
  /// projection of the equalities and the backward Riccati sweep in proportion to the CPU time
  /// each took on the threads; riccatiMs adds the forward pass.
  double linearizeMs = 0.0;
  double projectionMs = 0.0;
  double riccatiMs = 0.0;
  double lineSearchMs = 0.0;
  double totalMs = 0.0;
  int preparedNodes = 0;       ///< nodes whose matrices and their projection were prepared
  int preparedSweeps = 0;      ///< of them, nodes whose part of the sweep was prepared too
  double cost = 0.0;           ///< after the step
  double violation = 0.0;      ///< sqrt(Σ‖defects‖² + Σ‖equalities‖²) after the step
  double step = 0.0;           ///< accepted step length, 0 if none
  int iterations = 0;          ///< in this solve() (iterate(): 1); the times above are their sums
  bool ok = false;
  std::string message;         ///< why an iteration failed
};

class SqpSolver {
 public:
  SqpSolver(const OptimalControlProblem& problem, const SqpSettings& settings);

  const SqpSettings& settings() const { return settings_; }
  /// Node references for t0 + k·dt, k = 0..N; filled by the caller before iterate().
  std::vector<NodeReference>& references() { return references_; }

  /// One SQP iteration from the measured state at time t0. Returns statistics().ok.
  bool iterate(double t0, const Eigen::VectorXd& xMeasured);
  /// iterate(t0, x̂), then again from the same t0 and x̂ while the plan is far from feasible
  /// (its violation over settings().violationTolerance, a step taken), up to
  /// settings().maxIterations in all. When the references jump (footholds moved by a push, a
  /// contact mode come early), one iteration leaves a plan still far from feasible, and the
  /// controller tracks it: its base accelerations jumped by tens of m/s² from one plan to the
  /// next. An extra iteration that fails leaves the one before it standing (the solution
  /// iterate() keeps), reported as it was. budget (s, wall time; 0: none): no iteration past the
  /// first starts once the solve has taken this long, so that a real-time plan is not late for
  /// its extra iterations (a busy host slows them). Returns statistics().ok.
  bool solve(double t0, const Eigen::VectorXd& xMeasured, double budget = 0.0);
  /// Ahead of iterate(t0, ·), on references() as the caller expects them at t0: see the header.
  /// Nothing before the first solution, nor for a
  /// problem that does not keep its nodes' matrices (OptimalControlProblem::keepsMatrices). An
  /// iterate() whose t0 is within kSameTime of this one takes its warm start on this t0's grid.
  void prepare(double t0);
  /// Start times this close count as one (they are sums of periods, with their rounding), s.
  static constexpr double kSameTime = 1e-6;
  /// Forgets the previous solution (next iterate starts from the references).
  void reset() {
    hasSolution_ = false;
    prepared_ = false;
  }

  const MpcSolution& solution() const { return solution_; }
  const SqpStatistics& statistics() const { return stats_; }

 private:
  struct Merit {
    double cost = 0.0;
    double violation = 0.0;
  };
  void warmStart(double t0, const Eigen::VectorXd& xMeasured);
  Merit evaluate(const std::vector<Eigen::VectorXd>& x, const std::vector<Eigen::VectorXd>& u);
  bool fail(const std::string& why);
  /// On the calling thread: the backward sweep over the nodes projected since it last ran (down
  /// to sweepLast_); matricesOnly: its matrices' part (prepare()).
  void sweepProjected(bool matricesOnly);

  const OptimalControlProblem& problem_;
  SqpSettings settings_;
  ParallelFor pool_;
  std::vector<std::unique_ptr<ProblemWorkspace>> workspaces_;  ///< one per thread: values
  /// One per node: its linearisations, and what prepare() did for the next one.
  std::vector<std::unique_ptr<ProblemWorkspace>> nodeWorkspaces_;
  bool prepared_ = false;  ///< prepare() ran since the last iterate(), for preparedT0_
  double preparedT0_ = 0.0;
  RiccatiSolver riccati_;
  std::vector<NodeReference> references_;
  std::vector<LqNode> lq_;
  std::vector<NodeValue> values_, trialValues_;  ///< at the iterate; at the line search's trial
  std::vector<Eigen::VectorXd> x_, u_, xTrial_, uTrial_, dx_, du_;
  Eigen::VectorXd xSample_, uSample_;  ///< warmStart's scratch: the last solution at a node's time
  Eigen::VectorXd zeroDx0_;  ///< the LQ step starts at the measured state: δx₀ = 0
  std::vector<double> nodeCost_, nodeViolation2_;
  std::vector<char> projected_;
  /// Per node, this iteration: its matrices are the ones projected before (and, where the sweep
  /// keeps them, swept).
  std::vector<char> sameMatrices_;
  /// Per node: its projection is done (set by the thread that projected it, read by the sweep).
  std::vector<std::atomic<bool>> projectionDone_;
  int sweepNext_ = -1;      ///< the next node the backward sweep takes
  int sweepLast_ = 0;       ///< the last node it takes
  bool sweepOk_ = true;     ///< no projection failed and every Hessian so far was definite
  double sweepCpuMs_ = 0.0;
  /// Per thread: CPU time (ms) of this iteration spent linearising and projecting nodes.
  std::vector<double> linearizeCpuMs_, projectionCpuMs_;
  MpcSolution solution_;
  bool hasSolution_ = false;
  SqpStatistics stats_;
};

}  // namespace ballast::mpc
