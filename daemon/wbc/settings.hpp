// Settings of the whole-body controller: which model frames and joints the tasks use, the task
// gains, the friction coefficient and torque limits, and the variant (the paper's hierarchical
// cH, the weighted single QP cNH, or cI's inverse dynamics). Filled by the profile schema (daemon/profile/schema.cpp:
// every key's bounds and default); validateSettings() checks them against the model.
//
// Units: SI. Gains act on errors in the world frame (task space) or in joint space:
//   commanded acceleration = reference acceleration + kp·(reference − actual) + kd·(reference rate − actual rate)
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "model/model.hpp"
#include "model/settings_problem.hpp"

namespace ballast::wbc {

enum class WbcVariant : std::uint8_t {
  kHierarchical,  ///< cH: Table I priorities, each level in the null space of those above
  kWeighted,      ///< cNH: priority 1 as constraints, tasks 2–4 in one weighted QP
  /// cI (the paper's inverse-dynamics tracking of a single-rigid-body plan): one weighted QP as
  /// kWeighted, with the joint-space joints held at their reference positions (zero reference
  /// velocity and acceleration: the plan's limbs do not move).
  kInverseDynamics,
};
const char* toString(WbcVariant variant);

struct WbcSettings {
  WbcVariant variant;

  // The robot (names as in the URDF).
  std::string baseFrame;
  std::vector<std::string> contactFrames;
  /// Joints tracked in joint space at priority 2 (the arms); the legs follow their feet.
  std::vector<std::string> jointSpaceJoints;

  // Priority 2: limb motion tracking.
  double swingKp;  ///< 1/s², swing contact points, world frame
  double swingKd;  ///< 1/s
  /// A swinging foot (both its contact points in swing) is held level about the line through
  /// its points, with swingKp and swingKd: the points' paths leave that roll free.
  bool levelSwingFeet = true;
  /// No leg turns its foot about the vertical relative to the base (no hip yaw, or locked; the
  /// profile finds it from the URDF): a foot's yaw is then the base's, and the base's is the
  /// stance foot's. Standing on both feet, the second foot's yaw is left to the first; a
  /// swinging foot tracks the middle of its contact points and its pitch (the toe's height over
  /// the heel's) instead of each point; the base task has no yaw row (whole_body_controller.hpp).
  bool feetFollowBaseYaw = false;
  double jointKp;  ///< 1/s², joint-space joints
  double jointKd;  ///< 1/s
  // Priority 3: base motion tracking, [position (world x, y, z); orientation (world axes)].
  std::array<double, 6> baseKp;
  std::array<double, 6> baseKd;
  /// While the plan steps out a push (WbcReference::pushStep), the base task goes above the limb
  /// tasks (hierarchical variant): see whole_body_controller.hpp. False: the paper's order always.
  bool pushBaseFirst = true;

  // Priority 1: friction pyramid (C_fr of the paper, normal = world z) and torque limits.
  double frictionCoefficient;
  /// Every joint's acceleration keeps it within its URDF position limits: jointKp·(limit − q) −
  /// jointKd·q̇ bounds q̈ on each side. The limb tasks then fall short of a target beyond a
  /// joint's range instead of driving the joint into its stop, which jolts the base.
  bool jointLimits = false;
  /// |τ_j| ≤ torqueLimit[j], in the model's joint order; empty: the URDF effort limits.
  std::vector<double> torqueLimit;

  // The weighted and inverse-dynamics variants: weights of the squared task errors (limb, base,
  // contact force).
  double limbWeight;
  double baseWeight;
  double contactForceWeight;

  /// Regularisation λ of every QP, in the scaled decision units (accelerations in m/s², rad/s²;
  /// contact forces in units of m·g / number of contact points).
  double regularization;
  int maxQpIterations;
  /// Control period (s): the joint targets for the motors' PD are the mean over one period.
  double period;
};

/// No problem if the settings fit the model; otherwise the field at fault and what is wrong.
model::SettingsProblem validateSettings(const WbcSettings& settings, const model::Model& model);

}  // namespace ballast::wbc
