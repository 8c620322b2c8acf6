#include "mpc/sqp_solver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>


namespace ballast::mpc {
namespace {

using Clock = std::chrono::steady_clock;
bool finite(const std::vector<Eigen::VectorXd>& v) {
  for (const auto& x : v)
    if (!x.allFinite()) return false;
  return true;
}

}  // namespace

SqpSolver::SqpSolver(const OptimalControlProblem& problem, const SqpSettings& settings)
    : problem_(problem),
      settings_(settings),
      pool_(std::max(1, settings.threads)),
      riccati_(settings.nodes, problem.nx(), problem.nu()),
      references_(settings.nodes + 1),
      lq_(settings.nodes + 1, LqNode(problem.nx(), problem.nu(), problem.maxEqualities())),
      values_(settings.nodes),
      trialValues_(settings.nodes),
      x_(settings.nodes + 1, Eigen::VectorXd::Zero(problem.nx())),
      u_(settings.nodes, Eigen::VectorXd::Zero(problem.nu())),
      xTrial_(x_),
      uTrial_(u_),
      xSample_(problem.nx()),
      uSample_(problem.nu()),
      zeroDx0_(Eigen::VectorXd::Zero(problem.nx())),
      nodeCost_(settings.nodes + 1),
      nodeViolation2_(settings.nodes + 1),
      projected_(settings.nodes),
      sameMatrices_(settings.nodes),
      projectionDone_(settings.nodes),
      linearizeCpuMs_(pool_.threads()),
      projectionCpuMs_(pool_.threads()) {
  for (int t = 0; t < pool_.threads(); ++t)
    workspaces_.push_back(problem.makeWorkspace());
  for (int k = 0; k < settings.nodes; ++k) nodeWorkspaces_.push_back(problem.makeWorkspace());
  for (auto& r : references_) {
    r.x = Eigen::VectorXd::Zero(problem.nx());
    r.u = Eigen::VectorXd::Zero(problem.nu());
  }
}

bool SqpSolver::fail(const std::string& why) {
  stats_.ok = false;
  stats_.step = 0.0;
  stats_.message = why;
  return false;
}

void SqpSolver::warmStart(double t0, const Eigen::VectorXd& xMeasured) {
  const int N = settings_.nodes;
  if (!hasSolution_) {
    for (int k = 0; k <= N; ++k) x_[k] = xMeasured;
    for (int k = 0; k < N; ++k) u_[k] = references_[k].u;
    return;
  }
  const MpcSolution& prev = solution_;
  for (int k = 0; k <= N; ++k) {
    StanceFlags prevMode;
    prev.sample(t0 + k * settings_.dt, xSample_, uSample_, &prevMode);
    x_[k] = xSample_;
    if (k == N) break;
    u_[k] = uSample_;
    problem_.adaptInputToMode(references_[k], prevMode, u_[k]);
  }
  x_[0] = xMeasured;
}

void SqpSolver::prepare(double t0) {
  if (!hasSolution_ || !problem_.keepsMatrices()) return;
  const int N = settings_.nodes;
  // x_ and u_ are free between iterations (solution_ holds their copies). Node 0 will be the
  // measured state. Each node is linearised in its expected mode (the references' vectors do
  // not matter: only its matrices are kept), its matrices projected, and the sweep's matrices
  // follow, as iterate() does it.
  warmStart(t0, solution_.x[0]);
  riccati_.beginMatrixSweep(lq_[N]);  // Q_N is the same at every iteration
  sweepNext_ = N - 1;
  sweepLast_ = 1;
  sweepOk_ = true;
  for (auto& done : projectionDone_) done.store(false, std::memory_order_relaxed);
  auto prepareNode = [&](int i, int thread) {
    const int k = N - 1 - i;
    problem_.linearize(*nodeWorkspaces_[k], references_[k], x_[k], u_[k], settings_.dt, lq_[k],
                       values_[k]);
    riccati_.projectMatrices(k, lq_[k]);
    projectionDone_[k].store(true, std::memory_order_release);
    if (thread == 0) sweepProjected(true);
  };
  pool_.run(N - 1, prepareNode);
  sweepProjected(true);
  prepared_ = true;
  preparedT0_ = t0;
}

SqpSolver::Merit SqpSolver::evaluate(const std::vector<Eigen::VectorXd>& x,
                                     const std::vector<Eigen::VectorXd>& u) {
  const int N = settings_.nodes;
  const double dt = settings_.dt;
  auto body = [&](int k, int thread) {
    if (k == N) {
      nodeCost_[N] = problem_.terminalCost(*workspaces_[thread], references_[N], x[N], nullptr);
      nodeViolation2_[N] = 0.0;
      return;
    }
    NodeValue& v = trialValues_[k];
    problem_.evaluate(*workspaces_[thread], references_[k], x[k], u[k], dt, v);
    nodeCost_[k] = v.cost;
    nodeViolation2_[k] = v.equalityNorm2 + (x[k] + dt * v.xdot - x[k + 1]).squaredNorm();
  };
  pool_.run(N + 1, body);
  Merit m;
  for (int k = 0; k <= N; ++k) {
    m.cost += nodeCost_[k];
    m.violation += nodeViolation2_[k];
  }
  m.violation = std::sqrt(m.violation);
  return m;
}

void SqpSolver::sweepProjected(bool matricesOnly) {
  const auto begin = Clock::now();
  while (sweepOk_ && sweepNext_ >= sweepLast_ &&
         projectionDone_[sweepNext_].load(std::memory_order_acquire)) {
    const int k = sweepNext_--;
    sweepOk_ = matricesOnly ? riccati_.matricesProjected(k) && riccati_.sweepMatrices(k)
                            : projected_[k] && riccati_.sweepNode(k, sameMatrices_[k]);
  }
  sweepCpuMs_ += msSince(begin);
}

bool SqpSolver::solve(double t0, const Eigen::VectorXd& xMeasured, double budget) {
  const auto start = Clock::now();
  const bool ok = iterate(t0, xMeasured);
  double linearizeMs = stats_.linearizeMs, projectionMs = stats_.projectionMs,
         riccatiMs = stats_.riccatiMs, lineSearchMs = stats_.lineSearchMs, totalMs = stats_.totalMs;
  const int preparedNodes = stats_.preparedNodes, preparedSweeps = stats_.preparedSweeps;
  int iterations = 1;
  while (ok && iterations < settings_.maxIterations &&
         stats_.violation > settings_.violationTolerance && stats_.step > 0.0 &&
         (budget <= 0.0 || msSince(start) < 1e3 * budget)) {
    const double cost = stats_.cost, violation = stats_.violation, step = stats_.step;
    const bool again = iterate(t0, xMeasured);
    ++iterations;
    linearizeMs += stats_.linearizeMs;
    projectionMs += stats_.projectionMs;
    riccatiMs += stats_.riccatiMs;
    lineSearchMs += stats_.lineSearchMs;
    totalMs += stats_.totalMs;
    if (!again) {  // the solution before it stands
      stats_.ok = true;
      stats_.cost = cost;
      stats_.violation = violation;
      stats_.step = step;
      stats_.message.clear();
      break;
    }
  }
  stats_.linearizeMs = linearizeMs;
  stats_.projectionMs = projectionMs;
  stats_.riccatiMs = riccatiMs;
  stats_.lineSearchMs = lineSearchMs;
  stats_.totalMs = totalMs;
  stats_.preparedNodes = preparedNodes;
  stats_.preparedSweeps = preparedSweeps;
  stats_.iterations = iterations;
  return ok;
}

bool SqpSolver::iterate(double t0, const Eigen::VectorXd& xMeasured) {
  const auto start = Clock::now();
  const int N = settings_.nodes;
  const double dt = settings_.dt;
  stats_ = SqpStatistics{};
  stats_.iterations = 1;
  if (!xMeasured.allFinite()) return fail("the measured state has a NaN or infinite entry");
  // Prepared for (about) this time: the warm start is taken on the prepared grid, so that it
  // is the point prepared.
  const bool onPrepared = prepared_ && std::abs(t0 - preparedT0_) < kSameTime;
  prepared_ = false;
  warmStart(onPrepared ? preparedT0_ : t0, xMeasured);

  // Linearise and project every node in parallel, from the last one down, while the calling
  // thread takes the backward Riccati sweep over those done (sweepProjected): the sweep, serial,
  // runs behind the projections instead of after them all.
  auto t = Clock::now();
  const double terminal = problem_.terminalCost(*workspaces_[0], references_[N], x_[N], &lq_[N]);
  riccati_.beginSweep(lq_[N]);
  sweepNext_ = N - 1;
  sweepLast_ = 0;
  sweepOk_ = true;
  sweepCpuMs_ = 0.0;
  for (auto& done : projectionDone_) done.store(false, std::memory_order_relaxed);
  std::fill(linearizeCpuMs_.begin(), linearizeCpuMs_.end(), 0.0);
  std::fill(projectionCpuMs_.begin(), projectionCpuMs_.end(), 0.0);
  auto linearize = [&](int i, int thread) {
    const int k = N - 1 - i;
    const auto begin = Clock::now();
    ProblemWorkspace& ws = *nodeWorkspaces_[k];
    problem_.linearize(ws, references_[k], x_[k], u_[k], dt, lq_[k], values_[k]);
    lq_[k].b = x_[k] + dt * values_[k].xdot - x_[k + 1];
    const auto linearized = Clock::now();
    sameMatrices_[k] = ws.keptMatrices && riccati_.matricesProjected(k);
    if (sameMatrices_[k]) {  // the matrices projected before
      riccati_.projectVectors(k, lq_[k]);
      projected_[k] = true;
    } else {
      projected_[k] = riccati_.project(k, lq_[k]);
    }
    linearizeCpuMs_[thread] += std::chrono::duration<double, std::milli>(linearized - begin).count();
    projectionCpuMs_[thread] += msSince(linearized);
    projectionDone_[k].store(true, std::memory_order_release);
    if (thread == 0) sweepProjected(false);
  };
  pool_.run(N, linearize);
  sweepProjected(false);  // the nodes the other threads finished last
  const double wall = msSince(t);
  double linearizeCpu = 0.0, projectionCpu = 0.0;
  for (int k = 0; k < N; ++k) stats_.preparedNodes += sameMatrices_[k];
  stats_.preparedSweeps = riccati_.keptSweeps();
  for (int i = 0; i < pool_.threads(); ++i) {
    linearizeCpu += linearizeCpuMs_[i];
    projectionCpu += projectionCpuMs_[i];
  }
  const double cpu = linearizeCpu + projectionCpu + sweepCpuMs_;
  stats_.projectionMs = cpu > 0.0 ? wall * projectionCpu / cpu : 0.0;
  stats_.riccatiMs = cpu > 0.0 ? wall * sweepCpuMs_ / cpu : 0.0;
  stats_.linearizeMs = wall - stats_.projectionMs - stats_.riccatiMs;
  Merit current{terminal, 0.0};
  for (int k = 0; k < N; ++k) {
    if (!projected_[k])
      return fail("rank-deficient contact constraints at node " + std::to_string(k) +
                  " (a leg at a singular posture?)");
    current.cost += values_[k].cost;
    current.violation += values_[k].equalityNorm2 + lq_[k].b.squaredNorm();
  }
  current.violation = std::sqrt(current.violation);

  // LQ subproblem: the sweep's forward pass.
  if (!sweepOk_) return fail("the projected cost Hessian is not positive definite");
  t = Clock::now();
  riccati_.forwardPass(lq_, zeroDx0_, dx_, du_);
  stats_.riccatiMs += msSince(t);
  if (!finite(dx_) || !finite(du_)) return fail("the LQ step has NaN or infinite entries");

  // Filter line search.
  t = Clock::now();
  double slope = 0.0;  // first-order cost change along the step
  for (int k = 0; k < N; ++k) slope += lq_[k].q.dot(dx_[k]) + lq_[k].r.dot(du_[k]);
  slope += lq_[N].q.dot(dx_[N]);
  const SqpSettings& s = settings_;
  double alpha = 1.0;
  Merit trial;
  bool accepted = false;
  for (; alpha >= s.minStep; alpha *= s.stepDecay) {
    for (int k = 0; k <= N; ++k) xTrial_[k] = x_[k] + alpha * dx_[k];
    for (int k = 0; k < N; ++k) uTrial_[k] = u_[k] + alpha * du_[k];
    trial = evaluate(xTrial_, uTrial_);
    if (!std::isfinite(trial.cost) || !std::isfinite(trial.violation)) continue;
    if (current.violation > s.constraintLarge) {
      accepted = trial.violation < (1.0 - s.filterMargin) * current.violation;
    } else if (std::max(trial.violation, current.violation) < s.constraintSmall) {
      accepted = trial.cost < current.cost + s.armijo * alpha * std::min(slope, 0.0);
    } else {
      accepted = trial.cost < current.cost - s.filterMargin * current.violation ||
                 trial.violation < (1.0 - s.filterMargin) * current.violation;
    }
    if (accepted) break;
  }
  stats_.lineSearchMs = msSince(t);
  if (!accepted) {
    stats_.totalMs = msSince(start);
    // Feasible and no step lowers the cost: converged, the iterate itself is the answer.
    if (current.violation >= s.constraintSmall)
      return fail("no step along the SQP direction reduced cost or constraint violation");
    alpha = 0.0;
    trial = current;
  } else {
    std::swap(x_, xTrial_);
    std::swap(u_, uTrial_);
  }
  solution_.t0 = t0;
  solution_.dt = dt;
  solution_.x = x_;
  solution_.u = u_;
  solution_.stance.resize(N + 1);
  for (int k = 0; k <= N; ++k) solution_.stance[k] = references_[k].stance;
  hasSolution_ = true;
  stats_.cost = trial.cost;
  stats_.violation = trial.violation;
  stats_.step = alpha;
  stats_.ok = true;
  stats_.totalMs = msSince(start);
  return true;
}

}  // namespace ballast::mpc
