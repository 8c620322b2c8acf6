// The simbody backend's profile section: every key it accepts, declared once in a table
// (simSettingKeys(), sim_settings.cpp) with its type, default, bounds and one line of doc,
// parsed and validated by the schema engine ballastd's profile uses too
// (plugins/common/settings_schema.hpp):
// errors read `file:line:column: key: what is wrong`; unknown keys (with a "did you mean" for
// typos), keys given twice, wrong types and out-of-range values are errors.
//
// Example (every key is optional; values are the defaults unless marked):
//
//   friction: 0.8                     # Coulomb μ, robot vs terrain
//   contact_stiffness: 2.0e7          # Pa
//   integrator: semi_explicit_euler2
//   accuracy: 1.0e-3
//   fixed_step: 5.0e-4                # semi_explicit_euler's step
//   motor_latency_ticks: 1            # (default 0)
//   terrain_map: maps/lab-stage.bt    # (default "": Config::terrain_map, the planner's map)
//   initial_clearance: 0.05           # (default 0) drop the robot from 5 cm
//   initial_joints: {left_knee: 1.0}  # (default {}) overrides the initial posture
//   imu:
//     gyro_noise_density: 2.4e-4
//     gyro_bias: 0.002                # (default 0)
//   lidar:
//     rate: 10
//     horizontal_rays: 180
//
// Every key with its type, default, bounds and meaning: ballast-profile(5), section
// backend.simbody, generated from the table (`ballastd --dump-schema=man`).
#pragma once

#include <string>
#include <vector>

#include <array>

#include "settings_schema.hpp"
#include "rolling_lidar.hpp"     // plugins/common
#include "sensor_model.hpp"      // plugins/common

namespace ballast::simbody {

using schema::SettingsError;
using Vec3d = std::array<double, 3>;
using JointAngles = schema::NamedNumbers;

/// The parsed section. Field names are the keys with '.' replaced by '_'.
struct SimSettings : schema::Locations {
  double friction, friction_stiffness, friction_damping, contact_stiffness, contact_dissipation;
  double foot_sphere_radius, foot_width;
  bool body_contact;
  std::string terrain_map;
  bool floor;
  double floor_height;
  double overhang_height;

  std::string integrator;
  double accuracy;
  double fixed_step;
  Vec3d gravity;

  int motor_latency_ticks;
  double torque_limit_scale, joint_damping;
  bool joint_limits;
  double joint_limit_stiffness, joint_limit_damping;

  double encoder_resolution, joint_velocity_noise, torque_noise;
  schema::FrameRef imu_frame;
  double imu_gyro_noise_density, imu_gyro_bias, imu_accel_noise_density, imu_accel_bias;
  double imu_orientation_noise;

  bool lidar_enabled;
  schema::FrameRef lidar_frame;
  double lidar_rate;
  int lidar_horizontal_rays, lidar_vertical_rays;
  double lidar_horizontal_fov, lidar_vertical_min, lidar_vertical_max;
  double lidar_min_range, lidar_max_range, lidar_range_noise;

  double position_fix_rate, position_fix_noise;

  std::string initial_posture;
  JointAngles initial_joints;
  Vec3d initial_xy;  ///< [2] unused
  double initial_yaw, initial_clearance;

  double host_stall_at, host_stall, host_jitter_from, host_jitter_fraction, host_jitter;
};

using SettingKey = schema::Row<SimSettings>;

/// The table of keys, in documentation order.
const std::vector<SettingKey>& simSettingKeys();

/// Parses and validates the section; throws SettingsError "file:line:column: key: what is wrong".
SimSettings parseSimSettings(const std::string& yaml, const std::string& origin);

/// The key reference as text (the listing in this header's comment).
std::string simSettingsReference();
/// BackendEntry::section_doc: this section's keys as man page entries or commented YAML.
const char* simSettingsDoc(const char* format);

}  // namespace ballast::simbody
