// The locomotion plan: what the planner thread hands the 1 kHz loop. Fixed-size and copyable
// without allocation, so it can sit in a triple buffer: the MPC's state and input trajectories
// on its node grid, the contact schedule and the swing trajectories that shaped them.
//
// PlanSample is the plan at one instant, as the whole-body controller consumes it: the base pose
// and twist, joint positions and velocities, contact forces (world), and for each contact point
// its reference (swing trajectory, or the held stance position).
#pragma once

#include <Eigen/Core>
#include <array>

#include "gait/contact_schedule.hpp"
#include "gait/swing_planner.hpp"

namespace ballast::locomotion {

using model::kNumContacts;
inline constexpr int kMaxJoints = 32;
inline constexpr int kMaxNodes = 100;
inline constexpr int kMaxState = 12 + kMaxJoints;
inline constexpr int kMaxInput = 3 * kNumContacts + kMaxJoints;

struct Plan {
  bool valid = false;
  double t0 = 0.0;  ///< time of node 0
  double dt = 0.02;
  int nodes = 0;    ///< N
  int nx = 0, nu = 0;
  double x[kMaxNodes + 1][kMaxState] = {};  ///< x_k = [h, p, zyx, q_j] (mpc)
  double u[kMaxNodes][kMaxInput] = {};      ///< u_k = [f_c (12), v_j]
  gait::ContactSchedule schedule{gait::Gait{}, 0.0};
  gait::SwingPlanner swings{gait::SwingPlannerParameters{}, {}};
  bool walking = false;
  /// Standing, the planner steps to recover from a push (gait/recovery.hpp).
  bool recovering = false;
  /// Walking, a push has the footholds on the capture point's (gait::RecoveryParameters::
  /// walkingPushForcePerKg).
  bool pushStepping = false;
  /// Per contact point, the terrain height (world z) it stands on at t0, or, in a swing, the one
  /// it lands on: what the state estimator measures stance points against.
  std::array<double, kNumContacts> supportHeight{};
};

struct PlanSample {
  std::array<bool, kNumContacts> stance{true, true, true, true};
  Eigen::Vector3d basePosition = Eigen::Vector3d::Zero();         ///< world
  Eigen::Vector3d baseZyx = Eigen::Vector3d::Zero();              ///< [yaw, pitch, roll]
  Eigen::Vector3d baseLinearVelocity = Eigen::Vector3d::Zero();   ///< world
  Eigen::Vector3d baseAngularVelocity = Eigen::Vector3d::Zero();  ///< world
  Eigen::Matrix<double, 6, 1> momentum = Eigen::Matrix<double, 6, 1>::Zero();  ///< h_com
  std::array<double, kMaxJoints> jointPositions{};
  std::array<double, kMaxJoints> jointVelocities{};
  std::array<Eigen::Vector3d, kNumContacts> contactForce{};       ///< world, N
  std::array<gait::PointReference, kNumContacts> contact{};       ///< swing or held stance
};

}  // namespace ballast::locomotion
