// The single-rigid-body convex MPC of the MIT Cheetah lineage (Di Carlo et al. 2018; for bipeds
// Li & Nguyen 2021, "Force-and-moment-based MPC", the paper's cI planner), on the kino-dynamic
// problem's grid, gait, references, friction cone and cost terms (tracking_cost.hpp).
//
// State and input: the kino-dynamic problem's (centroidal_dynamics.hpp) with the joints left out
// (they stay at the nominal posture, their velocities zero):
//   x = [h_com (6), p_b (3), zyx_b (3)],   u = [f_c1..f_c4 (12, world)]     nx = nu = 12
// The robot is one rigid body: its whole mass m, and its composite inertia I_0 about its centre
// of mass c_0 (base frame, both constant) at the nominal posture.
//
// Dynamics, linearised about the node's reference (the commanded yaw, and the pose's pitch and
// roll) as the convex MPC is:
//   ḣ_lin = Σ f_i + m g (+ the estimated push)
//   ḣ_ang = Σ (p_i − c*) × f_i                 c* = p_b* + R* c_0, the reference centre of mass
//   ω     = I*⁻¹ h_ang                          I* = R* I_0 R*ᵀ
//   ṗ_b   = h_lin / m + (R* c_0) × ω
//   d(zyx)/dt = E(zyx*)⁻¹ ω
// with p_i where the gait puts contact point i at the node (NodeReference::contactPosition: its
// stance position, or the planned foothold of a swing). Linear in (x, u): each real-time
// iteration solves the convex QP, up to the barriers' Gauss-Newton step. Lever arms about the
// iterate's centre of mass instead (from the measured one on, as the MIT controller takes them
// from the measured state) were tried: bilinear, slower to converge, and in ballast-study the
// robot fell sooner (3.4 s against 4.2 s into the 1.0 m/s walk).
// At R = R*, c = c*, with the limbs at the nominal posture and not moving, this is the
// kino-dynamic problem's ẋ exactly (test/unit/mpc): what cI leaves out is the limbs' motion and
// the rotation's effect on the inertia and the lever arms.
//
// Equalities: swing points' force = 0 (projected out: fixed inputs). Inequalities: the stance
// points' friction cone and normal-force bounds as relaxed barriers, as the kino-dynamic
// problem's. Cost: ½‖x − x_ref‖²_Q + ½‖u − u_ref‖²_R + barriers.
#pragma once

#include <Eigen/Core>

#include "mpc/optimal_control_problem.hpp"
#include "mpc/tracking_cost.hpp"

namespace ballast::mpc {

/// The rigid body: the robot at its nominal posture.
struct RigidBody {
  double mass = 0.0;                                     ///< kg
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Identity();  ///< about the CoM, base frame, kg·m²
  Eigen::Vector3d com = Eigen::Vector3d::Zero();          ///< CoM in the base frame, m
  Eigen::Vector3d gravity{0.0, 0.0, -9.81};               ///< world, m/s²
};

class SingleRigidBodyProblem final : public OptimalControlProblem {
 public:
  static constexpr int kStateSize = 12;
  static constexpr int kInputSize = 3 * kNumContacts;

  /// settings: stateWeights and inputWeights of size 12; the joint limits, the feet distance and
  /// the swing gain are not used (the body has no limbs).
  SingleRigidBodyProblem(const RigidBody& body, const ProblemSettings& settings);

  int nx() const override { return kStateSize; }
  int nu() const override { return kInputSize; }
  int maxEqualities() const override { return 3 * kNumContacts; }
  std::unique_ptr<ProblemWorkspace> makeWorkspace() const override {
    return std::make_unique<TrackingWorkspace>(kStateSize, kInputSize);
  }
  const RigidBody& body() const { return body_; }
  const ProblemSettings& settings() const { return settings_; }

  void evaluate(ProblemWorkspace& ws, const NodeReference& ref, const Eigen::VectorXd& x,
                const Eigen::VectorXd& u, double dt, NodeValue& value) const override;
  void linearize(ProblemWorkspace& ws, const NodeReference& ref, const Eigen::VectorXd& x,
                 const Eigen::VectorXd& u, double dt, LqNode& node, NodeValue& value) const override;
  double terminalCost(ProblemWorkspace& ws, const NodeReference& ref, const Eigen::VectorXd& x,
                      LqNode* node) const override;
  void adaptInputToMode(const NodeReference& ref, const StanceFlags& before,
                        Eigen::VectorXd& u) const override;

  /// ẋ = F x + G u + g and its Jacobians F, G (12 × 12) for the node's reference.
  void dynamics(const NodeReference& ref, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                Eigen::Matrix<double, 12, 1>& xdot, Eigen::Matrix<double, 12, 12>& F,
                Eigen::Matrix<double, 12, 12>& G) const;

 private:
  void compute(TrackingWorkspace& ws, const NodeReference& ref, const Eigen::VectorXd& x,
               const Eigen::VectorXd& u, double dt, LqNode* node, NodeValue& value) const;

  RigidBody body_;
  Eigen::Matrix3d inertiaInverse_;  ///< body_.inertia⁻¹, base frame
  ProblemSettings settings_;
  Eigen::VectorXd terminalWeights_;  ///< diag(Q_N) = terminalWeightScale · stateWeights
};

}  // namespace ballast::mpc
