// What the SQP solver needs from a problem: node values and linearisations, and the terminal
// cost. KinodynamicProblem is the paper's, SingleRigidBodyProblem its cI's; tests use small
// linear ones.
#pragma once

#include <Eigen/Core>
#include <array>
#include <memory>

#include "model/contact_points.hpp"
#include "mpc/lq_problem.hpp"

namespace ballast::mpc {

using model::kNumContacts;
/// Closed (stance) or open (swing) per contact point: left toe, left heel, right toe, right heel.
using StanceFlags = std::array<bool, kNumContacts>;

/// What a node is asked to do: its contact mode and references.
struct NodeReference {
  StanceFlags stance{true, true, true, true};
  std::array<Eigen::Vector3d, kNumContacts> swingPosition{};  ///< p*(t), swing points only
  std::array<Eigen::Vector3d, kNumContacts> swingVelocity{};  ///< ṗ*(t)
  /// Where the gait puts every point at the node (world): its stance position, or on its swing
  /// trajectory. The single-rigid-body problem's lever arms; the kino-dynamic one has its own.
  std::array<Eigen::Vector3d, kNumContacts> contactPosition{};
  Eigen::VectorXd x, u;  ///< x_ref, u_ref
  /// A known external force on the robot at its centre of mass (world, N): a push the state
  /// estimator sees, taken to go on over the horizon. It adds to the rate of linear momentum.
  Eigen::Vector3d externalForce = Eigen::Vector3d::Zero();
};

/// A node's nonlinear value, for the line search.
struct NodeValue {
  Eigen::VectorXd xdot;        ///< f(x, u)
  double cost = 0.0;           ///< stage cost, integrated over the node's dt
  double equalityNorm2 = 0.0;  ///< ‖g(x, u)‖²
};

/// Scratch a problem needs to evaluate nodes: one per thread for values, one per node for
/// linearisations (where a problem may keep what it can use again: linearize()).
struct ProblemWorkspace {
  virtual ~ProblemWorkspace() = default;
  /// Set by linearize(): it kept the node's matrices as its last linearisation of that node
  /// made them (see there).
  bool keptMatrices = false;
};

class OptimalControlProblem {
 public:
  virtual ~OptimalControlProblem() = default;
  virtual int nx() const = 0;
  virtual int nu() const = 0;
  virtual int maxEqualities() const = 0;
  virtual std::unique_ptr<ProblemWorkspace> makeWorkspace() const = 0;

  /// Value of a stage node of duration dt; dynamics ẋ = f(x, u) (explicit Euler between nodes).
  virtual void evaluate(ProblemWorkspace& ws, const NodeReference& ref, const Eigen::VectorXd& x,
                        const Eigen::VectorXd& u, double dt, NodeValue& value) const = 0;
  /// Stage node linearised: A = I + dt ∂f/∂x, B = dt ∂f/∂u, equalities, quadratic cost model.
  /// node.b is left for the caller. Also returns the value. A problem may use what it computed
  /// last with the same workspace: where the node, x, u and dt are the same to the bit and so
  /// is ref.stance, the matrices (A, B, C, D, Q, R, S and neq) depend on nothing else and it
  /// may leave them as they are, computing only the vectors (e, q, r) and the value; it then
  /// sets ws.keptMatrices (the SQP's preparation, sqp_solver.hpp, relies on this). So a
  /// node's matrices must not be changed between its linearisations by anyone else.
  /// keepsMatrices(): whether it does.
  virtual void linearize(ProblemWorkspace& ws, const NodeReference& ref,
                         const Eigen::VectorXd& x, const Eigen::VectorXd& u, double dt,
                         LqNode& node, NodeValue& value) const = 0;
  virtual bool keepsMatrices() const { return false; }
  /// Terminal cost, and its quadratic model in node.Q, node.q if node is given.
  virtual double terminalCost(ProblemWorkspace& ws, const NodeReference& ref,
                              const Eigen::VectorXd& x, LqNode* node) const = 0;
  /// Warm start across a mode change: make u fit ref.stance where it differs from `before`.
  virtual void adaptInputToMode(const NodeReference& /*ref*/, const StanceFlags& /*before*/,
                                Eigen::VectorXd& /*u*/) const {}
};

}  // namespace ballast::mpc
