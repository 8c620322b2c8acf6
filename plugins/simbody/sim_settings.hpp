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
// Keys (name, type, default, bounds or choices, meaning):
//   Contact and terrain
//   friction                      number  0.8            [0, 3]         Coulomb friction coefficient μ between the robot and the terrain
//   friction_stiffness            number  5.0e4          [100, 1e+07]   tangential stiffness (N/m per contact sphere) of the stick phase: a foot gives μ f_n / k_t before it slides
//   friction_damping              number  200            [0, 100000]    tangential damping (N·s/m per contact sphere) of the stick phase
//   contact_stiffness             number  2.0e7          [10000, 1e+10] Hertz contact modulus E* (Pa) of robot vs terrain; 2e7 gives about 1 mm of sink standing
//   contact_dissipation           number  1.0            [0, 50]        Hunt-Crossley dissipation c (s/m): normal force k δ^1.5 (1 + 1.5 c dδ/dt)
//   foot_sphere_radius            number  0.01           [0.001, 0.05]  radius (m) of the contact spheres on the soles (two per contact point: the foot has area)
//   foot_width                    number  0              [0, 0.5]       distance (m) between the outer edges of a contact point's two spheres; 0: the width of the foot's collision box
//   body_contact                  bool    true                          bodies other than the feet collide with the terrain too (points on their collision shapes), for falls
//   terrain_map                   string  ""                            OctoMap file (.bt/.ot) simulated instead of Config::terrain_map (to test mapping); relative: to the working directory, else to the profile's
//   floor                         bool    true                          an infinite floor plane under the map (or alone, without a map)
//   floor_height                  number  0              [-100, 100]    height (m) of that floor
//
//   Simulation
//   integrator                    choice  semi_explicit_euler2 semi_explicit_euler2|rkm|rk3|rkf|verlet Simbody integrator, error-controlled; semi_explicit_euler2 takes one step per tick standing (rkm: Runge-Kutta-Merson, 2.5x the cost)
//   accuracy                      number  1.0e-3         [1e-08, 0.1]   integrator relative accuracy
//   gravity                       vec3    [0, 0, -9.81]  [-100, 100]    gravity (m/s², world frame)
//
//   Motors
//   motor_latency_ticks           integer 0              [0, 64]        commands written at tick k act from tick k + N (before the first one arrives, motors are off)
//   torque_limit_scale            number  1              [0, 10]        multiplies every URDF <limit effort> (the motor torque limit)
//   joint_damping                 number  0              [0, 100]       viscous friction (N·m·s/rad) in every joint
//   joint_limits                  bool    true                          spring-damper stops at the URDF position limits
//   joint_limit_stiffness         number  1000           [0, 1e+06]     stop stiffness (N·m/rad)
//   joint_limit_damping           number  2              [0, 10000]     stop damping (N·m·s/rad), only past the limit and moving further into it
//
//   Sensors
//   encoder_resolution            number  0              [0, 0.1]       joint position quantisation (rad); 0: exact
//   joint_velocity_noise          number  0              [0, 10]        white noise σ (rad/s) on joint velocities
//   torque_noise                  number  0              [0, 100]       white noise σ (N·m) on measured joint torques
//   imu.frame                     frame   imu                           the IMU: a URDF link, or {link: NAME, offset: [x, y, z], rpy: [r, p, y]} in that link's frame
//   imu.gyro_noise_density        number  2.4e-4         [0, 1]         gyro white noise (rad/s/√Hz); σ per sample = density / √period
//   imu.gyro_bias                 number  0              [0, 1]         σ (rad/s) of the per-axis gyro bias, drawn once at start
//   imu.accel_noise_density       number  1.5e-3         [0, 10]        accelerometer white noise (m/s²/√Hz)
//   imu.accel_bias                number  0              [0, 5]         σ (m/s²) of the per-axis accelerometer bias, drawn once at start
//   imu.orientation_noise         number  0              [0, 0.5]       σ (rad) of a random small rotation applied to the reported orientation
//
//   Lidar
//   lidar.enabled                 bool    true                          simulate the lidar (Capabilities::lidar)
//   lidar.frame                   frame   lidar                         the sensor: a URDF link, or {link: NAME, offset: [x, y, z], rpy: [r, p, y]} in that link's frame; rays in its x-forward, z-up frame
//   lidar.rate                    number  10             [0.1, 100]     scans per second (Hz)
//   lidar.horizontal_rays         integer 180            [1, 4096]      rays per scan line
//   lidar.vertical_rays           integer 16             [1, 256]       scan lines
//   lidar.horizontal_fov          number  6.283185307179586 [0.001, 6.28319] horizontal field of view (rad), centred on x
//   lidar.vertical_min            number  -1.0           [-1.5708, 1.5708] elevation (rad) of the lowest scan line
//   lidar.vertical_max            number  0.25           [-1.5708, 1.5708] elevation (rad) of the highest scan line (>= vertical_min)
//   lidar.min_range               number  0.1            [0, 100]       nearer hits are dropped (m)
//   lidar.max_range               number  10             [0.1, 200]     farther hits are dropped (m; > min_range)
//   lidar.range_noise             number  0              [0, 1]         white noise σ (m) along each ray
//
//   Localisation
//   position_fix.rate             number  0              [0, 100]       fixes per second (Hz) of the base position, as lidar scans matched against the map give them (Capabilities::position_fix); 0: none
//   position_fix.noise            number  0.01           [1e-05, 1]     white noise σ (m) per axis on each fix
//
//   Initial state (start())
//   initial_posture               choice  stand          stand|zero     stand: *hip_pitch -0.4, *knee 0.8, *ankle_pitch -(hip_pitch + knee) so the soles are level, others 0; zero: all 0
//   initial_joints                map     {}             [-6.28319, 6.28319] joint name -> angle (rad) overriding the posture; within the URDF limits
//   initial_xy                    vec2    [0, 0]         [-10000, 10000] base position (m) over the terrain
//   initial_yaw                   number  0              [-6.28319, 6.28319] base heading (rad)
//   initial_clearance             number  0              [0, 1000]      gap (m) between the lowest contact sphere and the terrain under it (0: touching)
//
//   Host delays (real time; to test the daemon's deadline policy)
//   host.stall_at                 number  -1             [-1, 1e+06]    simulated time (s) at which the control host stalls once, for host.stall; -1: never
//   host.stall                    number  0.05           [0, 10]        length (s, wall time) of that stall
//   host.jitter_from              number  0              [0, 1e+06]     simulated time (s) from which ticks are delayed at random
//   host.jitter_fraction          number  0              [0, 1]         fraction of ticks delayed by host.jitter; 0: none
//   host.jitter                   number  0.002          [0, 1]         delay (s, wall time) of a jittered tick
//
// test/integration/simbody/settings_test.cpp checks that this comment lists every key of the
// table with its default.
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

  std::string integrator;
  double accuracy;
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

/// The sensor keys, for the shared sensor model.
plugin::SensorNoise sensorNoise(const SimSettings& settings);
/// The lidar.* keys, for the shared rolling lidar.
plugin::LidarSettings lidarSettings(const SimSettings& settings);

}  // namespace ballast::simbody
