#include "sim_settings.hpp"

namespace ballast::simbody {
namespace {

constexpr double kTwoPi = 6.283185307179586;
constexpr double kHalfPi = 1.5707963267948966;
constexpr double kNone = 0.0;  // bounds of keys that have none

using S = SimSettings;
using K = plugin::KeyType;

// clang-format off
const std::vector<SettingKey> kKeys = {
  // name, type, default, min, max, choices, group, doc, field
  {"friction", K::kNumber, "0.8", 0, 3, "", "Contact and terrain",
   "Coulomb friction coefficient μ between the robot and the terrain", &S::friction},
  {"friction_stiffness", K::kNumber, "5.0e4", 1e2, 1e7, "", "Contact and terrain",
   "tangential stiffness (N/m per contact sphere) of the stick phase: a foot gives μ f_n / k_t before it slides",
   &S::friction_stiffness},
  {"friction_damping", K::kNumber, "200", 0, 1e5, "", "Contact and terrain",
   "tangential damping (N·s/m per contact sphere) of the stick phase", &S::friction_damping},
  {"contact_stiffness", K::kNumber, "2.0e7", 1e4, 1e10, "", "Contact and terrain",
   "Hertz contact modulus E* (Pa) of robot vs terrain; 2e7 gives about 1 mm of sink standing",
   &S::contact_stiffness},
  {"contact_dissipation", K::kNumber, "1.0", 0, 50, "", "Contact and terrain",
   "Hunt-Crossley dissipation c (s/m): normal force k δ^1.5 (1 + 1.5 c dδ/dt)", &S::contact_dissipation},
  {"foot_sphere_radius", K::kNumber, "0.01", 1e-3, 0.05, "", "Contact and terrain",
   "radius (m) of the contact spheres on the soles (two per contact point: the foot has area)",
   &S::foot_sphere_radius},
  {"foot_width", K::kNumber, "0", 0, 0.5, "", "Contact and terrain",
   "distance (m) between the outer edges of a contact point's two spheres; 0: the width of the foot's collision box",
   &S::foot_width},
  {"body_contact", K::kBool, "true", kNone, kNone, "", "Contact and terrain",
   "bodies other than the feet collide with the terrain too (points on their collision shapes), for falls",
   &S::body_contact},
  {"terrain_map", K::kString, "\"\"", kNone, kNone, "", "Contact and terrain",
   "OctoMap file (.bt/.ot) simulated instead of Config::terrain_map (to test mapping); relative: to the working directory, else to the profile's",
   &S::terrain_map},
  {"floor", K::kBool, "true", kNone, kNone, "", "Contact and terrain",
   "an infinite floor plane under the map (or alone, without a map)", &S::floor},
  {"floor_height", K::kNumber, "0", -100, 100, "", "Contact and terrain",
   "height (m) of that floor", &S::floor_height},

  {"integrator", K::kChoice, "semi_explicit_euler2", kNone, kNone,
   "semi_explicit_euler2|rkm|rk3|rkf|verlet", "Simulation",
   "Simbody integrator, error-controlled; semi_explicit_euler2 takes one step per tick standing (rkm: Runge-Kutta-Merson, 2.5x the cost)",
   &S::integrator},
  {"accuracy", K::kNumber, "1.0e-3", 1e-8, 0.1, "", "Simulation",
   "integrator relative accuracy", &S::accuracy},
  {"gravity", K::kVec3, "[0, 0, -9.81]", -100, 100, "", "Simulation",
   "gravity (m/s², world frame)", &S::gravity},

  {"motor_latency_ticks", K::kInteger, "0", 0, 64, "", "Motors",
   "commands written at tick k act from tick k + N (before the first one arrives, motors are off)",
   &S::motor_latency_ticks},
  {"torque_limit_scale", K::kNumber, "1", 0, 10, "", "Motors",
   "multiplies every URDF <limit effort> (the motor torque limit)", &S::torque_limit_scale},
  {"joint_damping", K::kNumber, "0", 0, 100, "", "Motors",
   "viscous friction (N·m·s/rad) in every joint", &S::joint_damping},
  {"joint_limits", K::kBool, "true", kNone, kNone, "", "Motors",
   "spring-damper stops at the URDF position limits", &S::joint_limits},
  {"joint_limit_stiffness", K::kNumber, "1000", 0, 1e6, "", "Motors",
   "stop stiffness (N·m/rad)", &S::joint_limit_stiffness},
  {"joint_limit_damping", K::kNumber, "2", 0, 1e4, "", "Motors",
   "stop damping (N·m·s/rad), only past the limit and moving further into it", &S::joint_limit_damping},

  {"encoder_resolution", K::kNumber, "0", 0, 0.1, "", "Sensors",
   "joint position quantisation (rad); 0: exact", &S::encoder_resolution},
  {"joint_velocity_noise", K::kNumber, "0", 0, 10, "", "Sensors",
   "white noise σ (rad/s) on joint velocities", &S::joint_velocity_noise},
  {"torque_noise", K::kNumber, "0", 0, 100, "", "Sensors",
   "white noise σ (N·m) on measured joint torques", &S::torque_noise},
  {"imu.frame", K::kString, "imu", kNone, kNone, "", "Sensors",
   "URDF link of the IMU", &S::imu_frame},
  {"imu.gyro_noise_density", K::kNumber, "2.4e-4", 0, 1, "", "Sensors",
   "gyro white noise (rad/s/√Hz); σ per sample = density / √period", &S::imu_gyro_noise_density},
  {"imu.gyro_bias", K::kNumber, "0", 0, 1, "", "Sensors",
   "σ (rad/s) of the per-axis gyro bias, drawn once at start", &S::imu_gyro_bias},
  {"imu.accel_noise_density", K::kNumber, "1.5e-3", 0, 10, "", "Sensors",
   "accelerometer white noise (m/s²/√Hz)", &S::imu_accel_noise_density},
  {"imu.accel_bias", K::kNumber, "0", 0, 5, "", "Sensors",
   "σ (m/s²) of the per-axis accelerometer bias, drawn once at start", &S::imu_accel_bias},
  {"imu.orientation_noise", K::kNumber, "0", 0, 0.5, "", "Sensors",
   "σ (rad) of a random small rotation applied to the reported orientation", &S::imu_orientation_noise},

  {"lidar.enabled", K::kBool, "true", kNone, kNone, "", "Lidar",
   "simulate the lidar (Capabilities::lidar)", &S::lidar_enabled},
  {"lidar.frame", K::kString, "lidar", kNone, kNone, "", "Lidar",
   "URDF link of the sensor; rays in its x-forward, z-up frame", &S::lidar_frame},
  {"lidar.rate", K::kNumber, "10", 0.1, 100, "", "Lidar",
   "scans per second (Hz)", &S::lidar_rate},
  {"lidar.horizontal_rays", K::kInteger, "180", 1, 4096, "", "Lidar",
   "rays per scan line", &S::lidar_horizontal_rays},
  {"lidar.vertical_rays", K::kInteger, "16", 1, 256, "", "Lidar",
   "scan lines", &S::lidar_vertical_rays},
  {"lidar.horizontal_fov", K::kNumber, "6.283185307179586", 1e-3, kTwoPi, "", "Lidar",
   "horizontal field of view (rad), centred on x", &S::lidar_horizontal_fov},
  {"lidar.vertical_min", K::kNumber, "-1.0", -kHalfPi, kHalfPi, "", "Lidar",
   "elevation (rad) of the lowest scan line", &S::lidar_vertical_min},
  {"lidar.vertical_max", K::kNumber, "0.25", -kHalfPi, kHalfPi, "", "Lidar",
   "elevation (rad) of the highest scan line (>= vertical_min)", &S::lidar_vertical_max},
  {"lidar.min_range", K::kNumber, "0.1", 0, 100, "", "Lidar",
   "nearer hits are dropped (m)", &S::lidar_min_range},
  {"lidar.max_range", K::kNumber, "10", 0.1, 200, "", "Lidar",
   "farther hits are dropped (m; > min_range)", &S::lidar_max_range},
  {"lidar.range_noise", K::kNumber, "0", 0, 1, "", "Lidar",
   "white noise σ (m) along each ray", &S::lidar_range_noise},

  {"position_fix.rate", K::kNumber, "0", 0, 100, "", "Localisation",
   "fixes per second (Hz) of the base position, as lidar scans matched against the map give "
   "them (Capabilities::position_fix); 0: none",
   &S::position_fix_rate},
  {"position_fix.noise", K::kNumber, "0.01", 1e-5, 1, "", "Localisation",
   "white noise σ (m) per axis on each fix", &S::position_fix_noise},

  {"initial_posture", K::kChoice, "stand", kNone, kNone, "stand|zero", "Initial state (start())",
   "stand: *hip_pitch -0.4, *knee 0.8, *ankle_pitch -(hip_pitch + knee) so the soles are level, others 0; zero: all 0",
   &S::initial_posture},
  {"initial_joints", K::kNamedNumbers, "{}", -kTwoPi, kTwoPi, "", "Initial state (start())",
   "joint name -> angle (rad) overriding the posture; within the URDF limits", &S::initial_joints},
  {"initial_xy", K::kVec2, "[0, 0]", -1e4, 1e4, "", "Initial state (start())",
   "base position (m) over the terrain", &S::initial_xy},
  {"initial_yaw", K::kNumber, "0", -kTwoPi, kTwoPi, "", "Initial state (start())",
   "base heading (rad)", &S::initial_yaw},
  {"initial_clearance", K::kNumber, "0", 0, 1000, "", "Initial state (start())",
   "gap (m) between the lowest contact sphere and the terrain under it (0: touching)",
   &S::initial_clearance},

  {"host.stall_at", K::kNumber, "-1", -1, 1e6, "", "Host delays (real time; to test the daemon's deadline policy)",
   "simulated time (s) at which the control host stalls once, for host.stall; -1: never", &S::host_stall_at},
  {"host.stall", K::kNumber, "0.05", 0, 10, "", "Host delays (real time; to test the daemon's deadline policy)",
   "length (s, wall time) of that stall", &S::host_stall},
  {"host.jitter_from", K::kNumber, "0", 0, 1e6, "", "Host delays (real time; to test the daemon's deadline policy)",
   "simulated time (s) from which ticks are delayed at random", &S::host_jitter_from},
  {"host.jitter_fraction", K::kNumber, "0", 0, 1, "", "Host delays (real time; to test the daemon's deadline policy)",
   "fraction of ticks delayed by host.jitter; 0: none", &S::host_jitter_fraction},
  {"host.jitter", K::kNumber, "0.002", 0, 1, "", "Host delays (real time; to test the daemon's deadline policy)",
   "delay (s, wall time) of a jittered tick", &S::host_jitter},
};
// clang-format on

void checkAcrossKeys(const SimSettings& s) {
  using plugin::SectionCursor;
  if (s.lidar_vertical_min > s.lidar_vertical_max)
    throw SettingsError(s.where("lidar.vertical_max") + "is below lidar.vertical_min (" +
                        SectionCursor::formatNumber(s.lidar_vertical_min) + ")");
  if (s.lidar_min_range >= s.lidar_max_range)
    throw SettingsError(s.where("lidar.max_range") + "must be above lidar.min_range (" +
                        SectionCursor::formatNumber(s.lidar_min_range) + ")");
}

}  // namespace

const std::vector<SettingKey>& simSettingKeys() { return kKeys; }

SimSettings parseSimSettings(const std::string& yaml, const std::string& origin) {
  SimSettings s = plugin::parseSection(kKeys, yaml, origin, "the simbody backend section");
  checkAcrossKeys(s);
  return s;
}

std::string simSettingsReference() { return plugin::sectionReference(kKeys); }

}  // namespace ballast::simbody
