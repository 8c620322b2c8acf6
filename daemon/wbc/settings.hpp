// Settings of the whole-body controller: which model frames and joints the tasks use, the task
// gains, the friction coefficient and torque limits, and the variant (the paper's hierarchical
// cH or the weighted single QP cNH). Filled by the profile module from the profile's `wbc`
// section; validateSettings() is the one place that checks them.
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

namespace ballast::wbc {

enum class WbcVariant : std::uint8_t {
  kHierarchical,  ///< cH: Table I priorities, each level in the null space of those above
  kWeighted,      ///< cNH: priority 1 as constraints, tasks 2–4 in one weighted QP
};
const char* toString(WbcVariant variant);

struct WbcSettings {
  WbcVariant variant = WbcVariant::kHierarchical;

  // The robot (names as in the URDF).
  std::string baseFrame = "pelvis";
  std::vector<std::string> contactFrames{"left_toe", "left_heel", "right_toe", "right_heel"};
  /// Joints tracked in joint space at priority 2 (the arms); the legs follow their feet.
  std::vector<std::string> jointSpaceJoints{
      "left_shoulder_pitch",  "left_shoulder_roll",  "left_shoulder_yaw",  "left_elbow",
      "left_wrist_yaw",       "left_wrist_pitch",    "right_shoulder_pitch", "right_shoulder_roll",
      "right_shoulder_yaw",   "right_elbow",         "right_wrist_yaw",    "right_wrist_pitch"};

  // Priority 2: limb motion tracking.
  double swingKp = 400.0;  ///< 1/s², swing contact points, world frame
  double swingKd = 40.0;   ///< 1/s
  double jointKp = 400.0;  ///< 1/s², joint-space joints
  double jointKd = 40.0;   ///< 1/s
  // Priority 3: base motion tracking, [position (world x, y, z); orientation (world axes)].
  std::array<double, 6> baseKp{400.0, 400.0, 400.0, 400.0, 400.0, 400.0};
  std::array<double, 6> baseKd{40.0, 40.0, 40.0, 40.0, 40.0, 40.0};

  // Priority 1: friction pyramid (C_fr of the paper, normal = world z) and torque limits.
  double frictionCoefficient = 0.6;
  /// |τ_j| ≤ torqueLimit[j], in the model's joint order; empty: the URDF effort limits.
  std::vector<double> torqueLimit;

  // The weighted variant: weights of the squared task errors (limb, base, contact force).
  double limbWeight = 100.0;
  double baseWeight = 10.0;
  double contactForceWeight = 1e-3;

  /// Regularisation λ of every QP, in the scaled decision units (accelerations in m/s², rad/s²;
  /// contact forces in units of m·g / number of contact points).
  double regularization = 1e-8;
  int maxQpIterations = 200;
  /// Control period (s): the joint targets for the motors' PD are the mean over one period.
  double period = 0.001;
};

/// "" if the settings fit the model, otherwise one message naming the field (the profile key,
/// e.g. "wbc.friction_coefficient") and what is wrong.
std::string validateSettings(const WbcSettings& settings, const model::Model& model);

}  // namespace ballast::wbc
