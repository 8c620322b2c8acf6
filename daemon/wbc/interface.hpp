// What the control module hands the whole-body controller each tick and what it gets back.
// Plain structs, sized once by WholeBodyController::make*() and then reused: filling them and
// calling update() allocates nothing.
//
// Sizes: nq = 7 + nj, nv = 6 + nj (model.hpp), nj actuated joints in the model's order,
// nc contact points in WbcSettings::contactFrames order. Frames: "world" is the inertial frame,
// z up; the base velocity inside v is in the base frame (model.hpp), every other velocity or
// acceleration here is world-aligned.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "wbc/hierarchical_qp.hpp"

namespace ballast::wbc {

/// The measured (or estimated) robot state.
struct WbcState {
  Eigen::VectorXd q;  ///< nq: [base position (world), quaternion (x, y, z, w) world <- base, q_j]
  Eigen::VectorXd v;  ///< nv: [base linear velocity (base frame), ω (base frame), q̇_j]
};

/// References, typically from the planner and the gait.
struct WbcReference {
  /// Contact schedule: stance[i] = contact point i is on the ground (its acceleration is zero
  /// and its force inside the friction pyramid); otherwise it swings (zero force, tracked).
  std::vector<bool> stance;
  /// Swing references per contact point, world frame, 3 × nc (used for swing points only).
  Eigen::Matrix3Xd contactPosition, contactVelocity, contactAcceleration;
  /// Joint references, nj each; used for WbcSettings::jointSpaceJoints.
  Eigen::VectorXd jointPosition, jointVelocity, jointAcceleration;
  /// Base (the WbcSettings::baseFrame origin): pose in the world, twist and acceleration
  /// world-aligned.
  Eigen::Vector3d basePosition = Eigen::Vector3d::Zero();
  Eigen::Quaterniond baseOrientation = Eigen::Quaterniond::Identity();  ///< world <- base
  Eigen::Vector3d baseLinearVelocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d baseAngularVelocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d baseLinearAcceleration = Eigen::Vector3d::Zero();
  Eigen::Vector3d baseAngularAcceleration = Eigen::Vector3d::Zero();
  /// Contact force references, world frame, 3 × nc stacked (force on the robot).
  Eigen::VectorXd contactForce;
  /// The plan is stepping out a push (the capture point's footholds, walking or standing): with
  /// WbcSettings::pushBaseFirst the base task goes above the limb tasks.
  bool pushStep = false;
};

enum class WbcStatus : std::uint8_t {
  kOk,
  kRelaxed,       ///< torque limits or friction could not all be met: slack used, torques clamped
  kDegraded,      ///< a QP failed: lower-priority tasks were dropped (output meets those above)
  kInvalidInput,  ///< non-finite state or reference: zero torques, hold targets; go to damping
};
const char* toString(WbcStatus status);

/// Paper priority levels (Table I), for per-level figures.
enum WbcPriority : int { kPhysics = 0, kLimbs = 1, kBase = 2, kContactForces = 3 };

struct WbcOutput {
  WbcStatus status = WbcStatus::kInvalidInput;
  Eigen::VectorXd jointTorque;         ///< nj, τ = M_j v̇ + n_j − J_jᵀF_c (clamped to the limits)
  /// Targets for the motors' PD (kp, kd are the caller's): the mean over the coming control
  /// period T (settings.period) of the motion the controller predicts.
  Eigen::VectorXd jointPositionTarget; ///< nj, q_j + (T/2) q̇_j + (T²/6) v̇_j
  Eigen::VectorXd jointVelocityTarget; ///< nj, q̇_j + (T/2) v̇_j
  Eigen::VectorXd acceleration;        ///< nv, v̇ (base part in the base frame, like v)
  Eigen::VectorXd contactForce;        ///< 3·nc, world frame
  /// Per paper priority (WbcPriority): ‖A ξ − b‖ of that priority's equality tasks (physics:
  /// dynamics and contact rows; limbs: m/s² and rad/s²; base: m/s², rad/s²; forces: N).
  std::array<double, 4> taskError{};
  double slackNorm = 0.0;              ///< ‖slack‖ of the torque-limit and friction rows
  int iterations = 0;                  ///< QP iterations, all levels
  int qpSolves = 0;                    ///< levels that needed a QP (others: least squares)
};

}  // namespace ballast::wbc
