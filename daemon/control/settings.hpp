// What the control loop takes from a profile (daemon/profile builds it and checks it against
// the model). Per-joint arrays are in the model's joint order. A profile switch hands the loop
// a new ControlSettings; the keys marked "restart" in the profile schema (robot, backend, rate)
// never change under a running loop.
#pragma once

#include <array>
#include <memory>
#include <string>

#include "control/types.hpp"
#include "estimation/settings.hpp"
#include "locomotion/locomotion_planner.hpp"
#include "wbc/whole_body_controller.hpp"

namespace ballast::control {

struct ControlSettings {
  std::string profile_name;  ///< for messages only

  // control
  double rate = 1000.0;  ///< Hz
  Mode initial_mode = Mode::kPassive;
  double stand_up_duration = 2.0;  ///< s
  double gain_blend_time = 0.5;    ///< s, profile switch
  bool gravity_compensation = true;
  double pose_speed = 0.1;          ///< m/s, standing height changes
  double pose_angular_speed = 0.3;  ///< rad/s, standing orientation changes
  int num_joints = 0;
  std::array<double, kMaxJoints> kp{}, kd{};   ///< joint PD gains
  std::array<double, kMaxJoints> nominal_q{};  ///< nominal standing posture

  // robot
  std::array<std::string, kNumContacts> contact_frames;
  std::string imu_frame = "imu";

  // estimator
  bool use_truth = false;      ///< control on the simulator's ground truth (diagnostics)
  double ground_height = 0.0;  ///< m, terrain under the robot at start
  estimation::EstimatorSettings estimator;
  bool use_position_fix = true;  ///< fuse Sensors::position_fix when the backend sends them

  // safety
  double damping = 4.0;           ///< N·m·s/rad in damp
  double max_tilt = 0.8;          ///< rad
  double min_base_height = 0.45;  ///< m
  bool fall_on_non_foot_contact = true;
  double command_ttl = 10.0, max_command_ttl = 600.0;  ///< s
  double max_vx = 1.5, max_vy = 0.5, max_yaw_rate = 1.0;
  double min_pose_height = 0.6, max_pose_height = 1.0;  ///< m
  double max_pose_tilt = 0.35, max_pose_yaw = 0.35;     ///< rad
  double max_push_force = 300.0, max_push_duration = 5.0;
  double max_plan_age = 0.1;  ///< s: older plans are a planner fault
  double max_command_gap = 0.01;   ///< s of wall time between command writes (real time)
  double max_late_fraction = 0.2;  ///< of the last second's ticks (real time)

  // whole-body controller (stand and walk once a plan exists). Built with the settings on the
  // IO side, so a profile switch hands the loop a ready controller and nothing is allocated on
  // the loop's thread; freed with the settings when they are retired. nullptr: none (the
  // standing controller alone).
  std::shared_ptr<wbc::WholeBodyController> wbc;
  double wbc_motor_kp = 20.0, wbc_motor_kd = 2.0;  ///< motor PD around the WBC's targets

  // planner, telemetry
  double planner_rate = 100.0;  ///< Hz
  double planner_latency = 0.005;  ///< s: lockstep takes a plan this long after its input
  locomotion::LocomotionSettings locomotion;  ///< the planner thread copies it (MpcPlanner)
  int telemetry_decimation = 1;
};

}  // namespace ballast::control
