// The single-rigid-body problem's stage-cost terms: the kino-dynamic problem's on the entries
// the two share, so that the paper's cH/cNH and its cI differ in their dynamics and nothing else:
// the quadratic tracking cost with the ZYX angles' error wrapped, the stance points' friction cone
// and normal-force bounds as relaxed barriers (eq. ic_friction_cone, ic_fz_max), the terminal
// cost, and the warm start's inputs across a contact-mode change.
//
// KinodynamicProblem takes stateError from here (a subtraction and a remainder: nothing to fuse)
// but computes the other terms in its own compute() and terminalCost(), and keeps them there:
// moved into these functions they changed cH's plans in the last bits (GCC fuses multiply-adds
// per translation unit, as its inlining goes, and even the headers that unit includes changed
// kinodynamic_problem.cpp's code), and a walk stopped at 1.2 m/s turns on such rounding (issue
// 13), so the refactor made cH stop differently from main. Including this header there left its
// plans bit for bit the same (ballast-push-map --trace, cmp). The unit test
// SingleRigidBody.CostTermsAreTheKinodynamicProblems holds the two copies to the same numbers.
//
// Layouts: both problems' states begin [h_com (6), p_b (3), zyx_b (3)] and their inputs
// [f_c1..f_c4 (12, world)]; the weights are the problem's diagonal Q and R (ProblemSettings).
#pragma once

#include <Eigen/Core>

#include "mpc/kinodynamic_problem.hpp"  // ProblemSettings
#include "mpc/lq_problem.hpp"
#include "mpc/optimal_control_problem.hpp"
#include "mpc/relaxed_barrier.hpp"

namespace ballast::mpc {

/// e = x − x_ref with the ZYX angles' difference wrapped to (−π, π]; e sized like x.
void stateError(const Eigen::VectorXd& x, const Eigen::VectorXd& xRef, Eigen::VectorXd& e);

/// Scratch for the tracking terms, sized by the problem (nx, nu) so that a node's costs do not
/// allocate on the planner's thread.
struct TrackingWorkspace : ProblemWorkspace {
  TrackingWorkspace(int nx, int nu) : xError(nx), uError(nu) {}
  Eigen::VectorXd xError;  ///< x − x_ref (ZYX wrapped)
  Eigen::VectorXd uError;  ///< u − u_ref
};

/// ½ dt (‖x − x_ref‖²_Q + ‖u − u_ref‖²_R); with a node, its Q, R, q, r (S zeroed).
double trackingCost(const ProblemSettings& s, TrackingWorkspace& ws, const NodeReference& ref,
                    const Eigen::VectorXd& x, const Eigen::VectorXd& u, double dt, LqNode* node);

/// dt Σ over stance points of the barriers of μ f_z ≥ sqrt(f_x² + f_y² + ε²),
/// f_z ≥ f_min and f_z ≤ f_max; with a node, their Gauss-Newton terms added to r and R.
double contactForceBarriers(const ProblemSettings& s, const NodeReference& ref,
                            const Eigen::VectorXd& u, double dt, LqNode* node);

/// ½‖x − x_ref‖² weighted by terminalWeights (the problem's terminalWeightScale · diag(Q), set
/// once with its settings); with a node, its Q and q (rest zeroed).
double terminalTrackingCost(const Eigen::VectorXd& terminalWeights, TrackingWorkspace& ws,
                            const NodeReference& ref, const Eigen::VectorXd& x, LqNode* node);

/// Zero force on a point that became a swing, the reference force on a new stance.
void adaptForcesToMode(const NodeReference& ref, const StanceFlags& before, Eigen::VectorXd& u);

}  // namespace ballast::mpc
