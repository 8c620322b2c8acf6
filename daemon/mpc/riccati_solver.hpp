// Solves the equality-constrained LQ problem of lq_problem.hpp over a horizon by projection and a
// Riccati sweep:
//  1. per node, the equalities are projected out: every feasible δu = Kc δx + kc + Z w with w
//     spanning D's null space. Inputs fall in three kinds, so the work goes only where it must:
//     fixed ones (a row of D with a single entry and no C part, e.g. a swing point's force:
//     δu_j = −e/d), constrained ones (in the other rows: the QR D_Kᵀ = [Y Z_K][R; 0] gives
//     Kc_K = Y·Ct with Ct = −R⁻ᵀ C, kc_K = −Y R⁻ᵀ e'), and free ones (in no row: w passes
//     through). Kc_K is kept in that factored form: it has rank mg (the general rows, ≤ 10 of
//     the 24 joint velocities it touches), so the products that carry it into the dynamics and
//     the cost cost O(n²·mg) instead of O(n³);
//  2. a backward Riccati recursion on (δx, w) gives the feedback w = K δx + k per node. With
//     H_uu = L Lᵀ and G = L⁻¹ H_ux, the update P ← Q + AᵀPA − GᵀG is a symmetric rank-nw update,
//     computed on one triangle; AᵀPA, BᵀPA and BᵀPB are the lower triangle of one product
//     [A B]ᵀ (P [A B]), and K is kept as L and G (the forward pass solves with L);
//  3. a forward pass from δx_0 (the initial-state defect) rolls out δx and δu.
// Step 2 can also be taken one node at a time (beginSweep, sweepNode from N−1 down, then
// forwardPass), so that a caller may run it behind the projections of the nodes before them
// (sqp_solver.cpp): each step reads only its own node and what the step after it left.
// The result is the exact minimiser of the LQ problem (checked against a direct KKT solve in
// test/unit/mpc). Work arrays are allocated with the solver and reused; a node whose contact
// mode changes keeps its matrices of earlier modes (useSizes), so that once each of its modes
// has been seen a solve allocates nothing.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <array>
#include <chrono>
#include <vector>

#include "mpc/lq_problem.hpp"

namespace ballast::mpc {

/// Wall time since t0, ms: the unit of the solvers' timings.
inline double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

struct RiccatiTimings {
  double riccatiMs = 0.0;  ///< sweep(): backward sweep and forward pass
};

class RiccatiSolver {
 public:
  RiccatiSolver(int horizonNodes, int nx, int nu);

  /// nodes[0..N-1] carry dynamics, constraints and stage cost; nodes[N] the terminal cost.
  /// dx0 is the initial-state deviation. Writes dx (N+1) and du (N). Returns false if the
  /// equalities are rank deficient or a projected Hessian is not positive definite (the
  /// caller keeps its previous solution). Same as project() on every node, then sweep().
  bool solve(const std::vector<LqNode>& nodes, const Eigen::VectorXd& dx0,
             std::vector<Eigen::VectorXd>& dx, std::vector<Eigen::VectorXd>& du);

  /// Step 1 for node k alone (nodes are independent: callers may run these in parallel).
  /// Returns false if the node's equality rows are (numerically) rank deficient. The same as
  /// projectMatrices() then projectVectors().
  bool project(int k, const LqNode& node);
  /// Step 1's part that reads the node's matrices only (A, B, C, D, Q, R, S): the kinds of
  /// inputs, the QR and the projected matrices, most of its work. False as project().
  bool projectMatrices(int k, const LqNode& node);
  /// The last projectMatrices(k) (or project(k)) got through the matrices: what it returned,
  /// or would have.
  bool matricesProjected(int k) const { return proj_[k].matricesProjected; }
  /// The rest, on the node's vectors (b, e, q, r), after a projectMatrices(k) that returned true
  /// on a node with the same matrices to the bit (the SQP's preparation: sqp_solver.hpp).
  void projectVectors(int k, const LqNode& node);
  /// Steps 2 and 3, after project() ran on nodes 0..N-1: beginSweep, sweepNode(N−1..0),
  /// forwardPass. Same result as taking them one by one.
  bool sweep(const std::vector<LqNode>& nodes, const Eigen::VectorXd& dx0,
             std::vector<Eigen::VectorXd>& dx, std::vector<Eigen::VectorXd>& du);

  /// Step 2, one node at a time: beginSweep with the terminal node (nodes[N]), then
  /// sweepNode(k) for k = N−1 down to 0, each after project(k). sweepNode returns false if
  /// node k's projected Hessian is not positive definite (the sweep cannot go on).
  /// The recursion's matrices (P, and the factors of K) depend on the projected matrices only.
  /// sameMatrices: node k's projected matrices are those of its last sweep (only its vectors
  /// were projected since, projectVectors()). Such a node on the same P after it as then (the
  /// same terminal Q to the bit, and every node between kept too) keeps the matrices of that
  /// sweep, and only its vectors are swept (the SQP's preparation: sqp_solver.hpp), with the
  /// same result.
  void beginSweep(const LqNode& terminal);
  bool sweepNode(int k, bool sameMatrices = false);
  /// The matrices' part of step 2 alone, for nodes N−1 down to some node, each after its
  /// projectMatrices(): beginMatrixSweep, then sweepMatrices(k) from N−1 down; false as
  /// sweepNode. A sweep after it keeps them where sameMatrices holds.
  void beginMatrixSweep(const LqNode& terminal);
  bool sweepMatrices(int k);
  /// Nodes whose matrices the last sweep kept.
  int keptSweeps() const { return keptSweeps_; }
  /// Step 3, after sweepNode(0).
  void forwardPass(const std::vector<LqNode>& nodes, const Eigen::VectorXd& dx0,
                   std::vector<Eigen::VectorXd>& dx, std::vector<Eigen::VectorXd>& du);

  const RiccatiTimings& timings() const { return timings_; }

 private:
  /// What sets the sizes of a node's projection: the numbers of its constrained inputs, of its
  /// general rows (before any is dropped) and of its free inputs.
  struct Sizes {
    int constrained = -1, general = -1, free = -1;
    bool operator==(const Sizes& o) const {
      return constrained == o.constrained && general == o.general && free == o.free;
    }
  };
  /// The matrices of a node's projection whose sizes follow its contact mode, and their scratch.
  struct SizedMatrices {
    Sizes sizes;
    long lastUsed = 0;
    Eigen::MatrixXd Y, Ct, ZK;  ///< Kc_K = Y·Ct (nK × mg, mg × nx); null basis of D_K (nK × nz)
    /// The LQ problem in (δx, w): AB = [A B] side by side, so that the sweep carries both
    /// through P in one product; R holds its lower triangle only (all the sweep reads).
    Eigen::MatrixXd AB, R, S;
    Eigen::VectorXd r;
    // Scratch of this node's projection (kept to reuse the memory).
    Eigen::MatrixXd DKt, Qfull, BK, BQ, RKK, RQ, T, SK, QtSK, RFK, RFY, CW, WC;
    Eigen::VectorXd ePrime, rK, ct, kcK, qWork;
    Eigen::HouseholderQR<Eigen::MatrixXd> qr;
  };
  /// A node's contact mode changes the sizes of its matrices, and a resize allocates. So each node
  /// keeps the matrices of the last few sizes it had (walking cycles through a handful of modes):
  /// the projection takes those of its sizes, the least recently used when it has none.
  static constexpr int kSizeSets = 5;
  struct Projected {
    std::vector<int> free, constrained, fixed, general;  ///< inputs by kind; general D rows
    std::vector<char> kind;                              ///< per input (scratch)
    std::vector<int> fixedBy;                            ///< per fixed input: its row of D
    Eigen::VectorXd kc;         ///< nu
    /// Q holds its lower triangle only (all the sweep reads).
    Eigen::MatrixXd Q;
    Eigen::VectorXd b, q, Rkc;
    int nw = 0;
    std::array<SizedMatrices, kSizeSets> sets;
    int current = 0;  ///< the set of the node's present sizes
    unsigned long generation = 0;  ///< counts projectMatrices() calls
    bool matricesProjected = false;  ///< the last projectMatrices() returned true
    long clock = 0;   ///< counts useSizes calls, for lastUsed
    SizedMatrices& sized() { return sets[current]; }
    const SizedMatrices& sized() const { return sets[current]; }
  };
  void useSizes(Projected& p, const Sizes& sizes);
  /// sweepNode's part on the vectors, after node k's matrices are swept.
  void sweepVectors(int k);
  /// δu for a state deviation and w (step 1 undone).
  void inputStep(const Projected& p, const Eigen::VectorXd& dx, const Eigen::VectorXd& w,
                 Eigen::VectorXd& du);

  int N_, nx_, nu_;
  std::vector<Projected> proj_;
  // Per node, what the forward pass needs: H_uu = L Lᵀ (lower triangle), G = L⁻¹ H_ux and
  // g = L⁻¹ h_u, so that w = −L⁻ᵀ (g + G δx) without forming K = −L⁻ᵀ G.
  std::vector<Eigen::MatrixXd> L_, G_;
  std::vector<Eigen::VectorXd> g_;
  /// P_k per node, k = 0..N (P_N: the terminal Q), kept from sweep to sweep.
  std::vector<Eigen::MatrixXd> P_;
  /// Per node: the generation of the projection L_, G_ and P_[k] were swept from, on P_[k + 1]
  /// as it is; 0: none (the sweep's thread alone reads and writes these).
  std::vector<unsigned long> swept_;
  int keptSweeps_ = 0;
  Eigen::MatrixXd M_, H_;
  Eigen::VectorXd p_, Pb_, y_, w_;
  Eigen::VectorXd CtDx_, KcDx_, ZKw_;  ///< inputStep's scratch (nu each)
  RiccatiTimings timings_;
};

}  // namespace ballast::mpc
