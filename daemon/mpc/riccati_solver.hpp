// Solves the equality-constrained LQ problem of lq_problem.hpp over a horizon by projection and a
// Riccati sweep:
//  1. per node, the equalities are projected out: with Dᵀ = [Y Z][R; 0] (QR), every feasible
//     δu = Kc δx + kc + Z w, Kc = −Y R⁻ᵀ C, kc = −Y R⁻ᵀ e, and w spans D's null space;
//  2. a backward Riccati recursion on (δx, w) gives the feedback w = K δx + k per node;
//  3. a forward pass from δx_0 (the initial-state defect) rolls out δx and δu.
// The result is the exact minimiser of the LQ problem (checked against a direct KKT solve in
// test/unit/mpc). Work arrays are allocated once per horizon length.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <vector>

#include "mpc/lq_problem.hpp"

namespace ballast::mpc {

struct RiccatiTimings {
  double riccatiMs = 0.0;  ///< backward sweep and forward pass
};

class RiccatiSolver {
 public:
  RiccatiSolver(int horizonNodes, int nx, int nu, int maxEq);

  /// nodes[0..N-1] carry dynamics, constraints and stage cost; nodes[N] the terminal cost.
  /// dx0 is the initial-state deviation. Writes dx (N+1) and du (N). Returns false if the
  /// equalities are rank deficient or a projected Hessian is not positive definite (the
  /// caller keeps its previous solution). Same as project() on every node, then sweep().
  bool solve(const std::vector<LqNode>& nodes, const Eigen::VectorXd& dx0,
             std::vector<Eigen::VectorXd>& dx, std::vector<Eigen::VectorXd>& du);

  /// Step 1 for node k alone (nodes are independent: callers may run these in parallel).
  /// Returns false if the node's equality rows are (numerically) rank deficient.
  bool project(int k, const LqNode& node);
  /// Steps 2 and 3, after project() ran on nodes 0..N-1.
  bool sweep(const std::vector<LqNode>& nodes, const Eigen::VectorXd& dx0,
             std::vector<Eigen::VectorXd>& dx, std::vector<Eigen::VectorXd>& du);

  /// Feedback gains δu = Ku δx + ku of the last solve, per node (for interpolating policies).
  const Eigen::MatrixXd& feedback(int k) const { return fullK_[k]; }
  const RiccatiTimings& timings() const { return timings_; }

 private:
  struct Projected {
    Eigen::MatrixXd A, B, Q, R, S, Kc, Z;
    Eigen::VectorXd b, q, r, kc;
    int nw = 0;
  };

  int N_, nx_, nu_;
  std::vector<Projected> proj_;
  std::vector<Eigen::MatrixXd> K_, fullK_;
  std::vector<Eigen::VectorXd> k_;
  Eigen::MatrixXd P_, PA_, PB_, Huu_, Hux_, Dt_;
  Eigen::VectorXd p_, Pb_, hu_;
  RiccatiTimings timings_;
};

}  // namespace ballast::mpc
