// The mujoco backend's profile section: every key it accepts, declared once in a table
// (mujocoSettingKeys(), mujoco_settings.cpp) with its type, default, bounds and one line of doc,
// parsed and validated by the plugins' schema engine (plugins/common/settings_schema.hpp):
// errors read `file:line:column: key: what is wrong`; unknown keys (with a "did you mean" for
// typos), keys given twice, wrong types and out-of-range values are errors.
//
// A key that means what a simbody backend key means has its name, default and bounds (sensors,
// lidar, position fixes, motors, initial state, host delays, friction, foot spheres, terrain),
// so a profile's robot is the same robot on either simulator; the contact softness and the
// stepping are MuJoCo's own (contact_*, cone, substeps, integrator, solver*).
//
// Example (every key is optional; values are the defaults unless marked):
//
//   friction: 0.8                     # Coulomb μ, robot vs terrain
//   contact_timeconst: 0.02           # s: MuJoCo solref[0]
//   substeps: 1                       # MuJoCo steps per control tick
//   motor_latency_ticks: 1            # (default 0)
//   terrain_map: maps/lab-stage.bt    # (default "": Config::terrain_map, the planner's map)
//   initial_clearance: 0.05           # (default 0) drop the robot from 5 cm
//   imu:
//     gyro_bias: 0.002                # (default 0)
//   lidar:
//     rate: 10
//
// Keys (name, type, default, bounds or choices, meaning):
//   Contact and terrain
//   friction                      number  0.8            [0, 3]         Coulomb friction coefficient μ between the robot and the terrain
//   contact_timeconst             number  0.02           [0.0001, 1]    time constant (s) of MuJoCo's soft contact (solref[0], MuJoCo's default): smaller is stiffer; at least 2 timesteps; 0.02 sinks the standing robot 0.7 mm
//   contact_dampratio             number  1              [0.01, 100]    damping ratio of the soft contact (solref[1]); 1: critically damped
//   contact_impedance             vec3    [0.9, 0.95, 0.001] [0.0001, 1]    MuJoCo solimp [dmin, dmax, width (m)]: constraint impedance from dmin at the surface to dmax at width deep
//   cone                          choice  elliptic       elliptic|pyramidal friction cone: elliptic (exact Coulomb) or pyramidal (MuJoCo's default, 4 edges)
//   foot_sphere_radius            number  0.01           [0.001, 0.05]  radius (m) of the contact spheres on the soles (two per contact point: the foot has area)
//   foot_width                    number  0              [0, 0.5]       distance (m) between the outer edges of a contact point's two spheres; 0: the width of the foot's collision box
//   body_contact                  bool    true                          bodies other than the feet collide with the terrain too (their URDF collision shapes), for falls
//   terrain_map                   string  ""                            OctoMap file (.bt/.ot) simulated instead of Config::terrain_map (to test mapping); relative: to the working directory, else to the profile's
//   floor                         bool    true                          an infinite floor plane under the map (or alone, without a map)
//   floor_height                  number  0              [-100, 100]    height (m) of that floor
//
//   Simulation
//   substeps                      integer 1              [1, 100]       MuJoCo steps per control tick: timestep = period / substeps; the motor model acts in every one
//   integrator                    choice  euler          euler|implicit MuJoCo integrator: euler (semi-implicit, joint damping and the motors' kd implicit) or implicit (in velocity)
//   solver                        choice  newton         newton|cg|pgs  MuJoCo constraint solver
//   solver_iterations             integer 100            [1, 10000]     constraint solver iterations at most
//   solver_tolerance              number  1.0e-8         [0, 1]         constraint solver tolerance
//   gravity                       vec3    [0, 0, -9.81]  [-100, 100]    gravity (m/s², world frame)
//
//   Motors
//   motor_latency_ticks           integer 0              [0, 64]        commands written at tick k act from tick k + N (before the first one arrives, motors are off)
//   torque_limit_scale            number  1              [0, 10]        multiplies every URDF <limit effort> (the motor torque limit)
//   joint_damping                 number  0              [0, 100]       viscous friction (N·m·s/rad) in every joint (MuJoCo joint damping, implicit)
//   joint_limits                  bool    true                          MuJoCo limit constraints at the URDF position limits
//   joint_limit_timeconst         number  0.02           [0.0001, 1]    MuJoCo limit constraint time constant (s) at the URDF position limits (solreflimit, critically damped); at least 2 timesteps
//
//   Sensors
//   encoder_resolution            number  0              [0, 0.1]       joint position quantisation (rad); 0: exact
//   joint_velocity_noise          number  0              [0, 10]        white noise σ (rad/s) on joint velocities
//   torque_noise                  number  0              [0, 100]       white noise σ (N·m) on measured joint torques
//   imu.frame                     string  imu                           URDF link of the IMU
//   imu.gyro_noise_density        number  2.4e-4         [0, 1]         gyro white noise (rad/s/√Hz); σ per sample = density / √period
//   imu.gyro_bias                 number  0              [0, 1]         σ (rad/s) of the per-axis gyro bias, drawn once at start
//   imu.accel_noise_density       number  1.5e-3         [0, 10]        accelerometer white noise (m/s²/√Hz)
//   imu.accel_bias                number  0              [0, 5]         σ (m/s²) of the per-axis accelerometer bias, drawn once at start
//   imu.orientation_noise         number  0              [0, 0.5]       σ (rad) of a random small rotation applied to the reported orientation
//
//   Lidar
//   lidar.enabled                 bool    true                          simulate the lidar (Capabilities::lidar)
//   lidar.frame                   string  lidar                         URDF link of the sensor; rays in its x-forward, z-up frame
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
// test/integration/mujoco/settings_test.cpp checks that this comment lists every key of the
// table with its default.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "rolling_lidar.hpp"    // plugins/common
#include "sensor_model.hpp"     // plugins/common
#include "settings_schema.hpp"  // plugins/common

namespace ballast::mujoco {

using schema::SettingsError;
using Vec3d = std::array<double, 3>;
using JointAngles = schema::NamedNumbers;

/// The parsed section. Field names are the keys with '.' replaced by '_'.
struct MujocoSettings : schema::Locations {
  double friction, contact_timeconst, contact_dampratio;
  Vec3d contact_impedance;
  std::string cone;
  double foot_sphere_radius, foot_width;
  bool body_contact;
  std::string terrain_map;
  bool floor;
  double floor_height;

  int substeps;
  std::string integrator, solver;
  int solver_iterations;
  double solver_tolerance;
  Vec3d gravity;

  int motor_latency_ticks;
  double torque_limit_scale, joint_damping;
  bool joint_limits;
  double joint_limit_timeconst;

  double encoder_resolution, joint_velocity_noise, torque_noise;
  std::string imu_frame;
  double imu_gyro_noise_density, imu_gyro_bias, imu_accel_noise_density, imu_accel_bias;
  double imu_orientation_noise;

  bool lidar_enabled;
  std::string lidar_frame;
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

using SettingKey = schema::Row<MujocoSettings>;

/// The table of keys, in documentation order.
const std::vector<SettingKey>& mujocoSettingKeys();

/// Parses and validates the section; throws SettingsError "file:line:column: key: what is wrong".
MujocoSettings parseMujocoSettings(const std::string& yaml, const std::string& origin);

/// The key reference as text (the listing in this header's comment).
std::string mujocoSettingsReference();
/// BackendEntry::section_doc: this section's keys as man page entries or commented YAML.
const char* mujocoSettingsDoc(const char* format);

/// The sensor keys, for the shared sensor model.
plugin::SensorNoise sensorNoise(const MujocoSettings& settings);
/// The lidar.* keys, for the shared rolling lidar.
plugin::LidarSettings lidarSettings(const MujocoSettings& settings);

}  // namespace ballast::mujoco
