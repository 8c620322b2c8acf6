#include "sim_settings.hpp"

#include "format.hpp"

namespace ballast::simbody {
namespace {

constexpr double kTwoPi = 6.283185307179586;
constexpr double kHalfPi = 1.5707963267948966;

using S = SimSettings;
using R = schema::Rule<SimSettings>;
using namespace schema;  // the row declarations

// Documentation groups.
constexpr const char* kContact = "Contact and terrain";
constexpr const char* kSimulation = "Simulation";
constexpr const char* kMotors = "Motors";
constexpr const char* kSensors = "Sensors";
constexpr const char* kLidar = "Lidar";
constexpr const char* kLocalisation = "Localisation";
constexpr const char* kInitial = "Initial state (start())";
constexpr const char* kHost = "Host delays (real time; to test the daemon's deadline policy)";

// clang-format off
const Schema<SimSettings> kSchema({
  number("friction", "0.8", 0, 3, "", "Coulomb friction coefficient μ between the robot and the terrain").inGroup(kContact).into<&S::friction>(),
  number("friction_stiffness", "5.0e4", 1e2, 1e7, "", "tangential stiffness (N/m per contact sphere) of the stick phase: a foot gives μ f_n / k_t before it slides").inGroup(kContact).into<&S::friction_stiffness>(),
  number("friction_damping", "200", 0, 1e5, "", "tangential damping (N·s/m per contact sphere) of the stick phase").inGroup(kContact).into<&S::friction_damping>(),
  number("contact_stiffness", "2.0e7", 1e4, 1e10, "", "Hertz contact modulus E* (Pa) of robot vs terrain; 2e7 gives about 1 mm of sink standing").inGroup(kContact).into<&S::contact_stiffness>(),
  number("contact_dissipation", "1.0", 0, 50, "", "Hunt-Crossley dissipation c (s/m): normal force k δ^1.5 (1 + 1.5 c dδ/dt)").inGroup(kContact).into<&S::contact_dissipation>(),
  number("foot_sphere_radius", "0.01", 1e-3, 0.05, "", "radius (m) of the contact spheres on the soles (two per contact point: the foot has area)").inGroup(kContact).into<&S::foot_sphere_radius>(),
  number("foot_width", "0", 0, 0.5, "", "distance (m) between the outer edges of a contact point's two spheres; 0: the width of the foot's collision box").inGroup(kContact).into<&S::foot_width>(),
  flag("body_contact", "true", "bodies other than the feet collide with the terrain too (points on their collision shapes), for falls").inGroup(kContact).into<&S::body_contact>(),
  text("terrain_map", "\"\"", "OctoMap file (.bt/.ot) simulated instead of Config::terrain_map (to test mapping); relative: to the working directory, else to the profile's").inGroup(kContact).into<&S::terrain_map>(),
  flag("floor", "true", "an infinite floor plane under the map (or alone, without a map)").inGroup(kContact).into<&S::floor>(),
  number("floor_height", "0", -100, 100, "", "height (m) of that floor").inGroup(kContact).into<&S::floor_height>(),
  number("overhang_height", "0.5", 0.05, 100, "", "the map's cells stand on the ground in runs joined from the bottom up; a run that starts more than this (m) above floor_height hangs over it (a ceiling, a table top seen without its legs) and is not simulated").inGroup(kContact).into<&S::overhang_height>(),
  choice("integrator", "semi_explicit_euler2", "semi_explicit_euler2|semi_explicit_euler|rkm|rk3|rkf|verlet", "Simbody integrator; semi_explicit_euler takes fixed steps of fixed_step without error control (one evaluation of the dynamics per step), the others are error-controlled: semi_explicit_euler2 takes one step per tick standing (rkm: Runge-Kutta-Merson, 2.5x the cost)").inGroup(kSimulation).into<&S::integrator>(),
  number("accuracy", "1.0e-3", 1e-8, 0.1, "", "relative accuracy of the error-controlled integrators").inGroup(kSimulation).into<&S::accuracy>(),
  number("fixed_step", "5.0e-4", 1e-5, 0.01, "", "step (s) of semi_explicit_euler; at 1e-3 the humanoid's stance feet slip where the friction holds them (the contact tests, test/integration/simbody)").inGroup(kSimulation).into<&S::fixed_step>(),
  numbers("gravity", "[0, 0, -9.81]", -100, 100, "", "gravity (m/s², world frame)").ofLength(3).inGroup(kSimulation).into<&S::gravity>(),
  integer("motor_latency_ticks", "0", 0, 64, "", "commands written at tick k act from tick k + N (before the first one arrives, motors are off)").inGroup(kMotors).into<&S::motor_latency_ticks>(),
  number("torque_limit_scale", "1", 0, 10, "", "multiplies every URDF <limit effort> (the motor torque limit)").inGroup(kMotors).into<&S::torque_limit_scale>(),
  number("joint_damping", "0", 0, 100, "", "viscous friction (N·m·s/rad) in every joint").inGroup(kMotors).into<&S::joint_damping>(),
  flag("joint_limits", "true", "spring-damper stops at the URDF position limits").inGroup(kMotors).into<&S::joint_limits>(),
  number("joint_limit_stiffness", "1000", 0, 1e6, "", "stop stiffness (N·m/rad)").inGroup(kMotors).into<&S::joint_limit_stiffness>(),
  number("joint_limit_damping", "2", 0, 1e4, "", "stop damping (N·m·s/rad), only past the limit and moving further into it").inGroup(kMotors).into<&S::joint_limit_damping>(),
  number("encoder_resolution", "0", 0, 0.1, "", "joint position quantisation (rad); 0: exact").inGroup(kSensors).into<&S::encoder_resolution>(),
  number("joint_velocity_noise", "0", 0, 10, "", "white noise σ (rad/s) on joint velocities").inGroup(kSensors).into<&S::joint_velocity_noise>(),
  number("torque_noise", "0", 0, 100, "", "white noise σ (N·m) on measured joint torques").inGroup(kSensors).into<&S::torque_noise>(),
  frame("imu.frame", "imu", true, "the IMU: a URDF link, or {link: NAME, offset: [x, y, z], rpy: [r, p, y]} in that link's frame; not given: where robot.imu_frame puts the controller's (the default where ballastd gives none); given: there whatever the controller assumes, a mounting error to simulate").inGroup(kSensors).into<&S::imu_frame>(),
  number("imu.gyro_noise_density", "2.4e-4", 0, 1, "", "gyro white noise (rad/s/√Hz); σ per sample = density / √period").inGroup(kSensors).into<&S::imu_gyro_noise_density>(),
  number("imu.gyro_bias", "0", 0, 1, "", "σ (rad/s) of the per-axis gyro bias, drawn once at start").inGroup(kSensors).into<&S::imu_gyro_bias>(),
  number("imu.accel_noise_density", "1.5e-3", 0, 10, "", "accelerometer white noise (m/s²/√Hz)").inGroup(kSensors).into<&S::imu_accel_noise_density>(),
  number("imu.accel_bias", "0", 0, 5, "", "σ (m/s²) of the per-axis accelerometer bias, drawn once at start").inGroup(kSensors).into<&S::imu_accel_bias>(),
  number("imu.orientation_noise", "0", 0, 0.5, "", "σ (rad) of a random small rotation applied to the reported orientation").inGroup(kSensors).into<&S::imu_orientation_noise>(),
  flag("lidar.enabled", "true", "simulate the lidar (Capabilities::lidar)").inGroup(kLidar).into<&S::lidar_enabled>(),
  frame("lidar.frame", "lidar", true, "the sensor: a URDF link, or {link: NAME, offset: [x, y, z], rpy: [r, p, y]} in that link's frame; rays in its x-forward, z-up frame").inGroup(kLidar).into<&S::lidar_frame>(),
  number("lidar.rate", "10", 0.1, 100, "", "scans per second (Hz)").inGroup(kLidar).into<&S::lidar_rate>(),
  integer("lidar.horizontal_rays", "180", 1, 4096, "", "rays per scan line").inGroup(kLidar).into<&S::lidar_horizontal_rays>(),
  integer("lidar.vertical_rays", "16", 1, 256, "", "scan lines").inGroup(kLidar).into<&S::lidar_vertical_rays>(),
  number("lidar.horizontal_fov", "6.283185307179586", 1e-3, kTwoPi, "", "horizontal field of view (rad), centred on x").inGroup(kLidar).into<&S::lidar_horizontal_fov>(),
  number("lidar.vertical_min", "-1.0", -kHalfPi, kHalfPi, "", "elevation (rad) of the lowest scan line").inGroup(kLidar).into<&S::lidar_vertical_min>(),
  number("lidar.vertical_max", "0.25", -kHalfPi, kHalfPi, "", "elevation (rad) of the highest scan line (>= vertical_min)").inGroup(kLidar).into<&S::lidar_vertical_max>(),
  number("lidar.min_range", "0.1", 0, 100, "", "nearer hits are dropped (m)").inGroup(kLidar).into<&S::lidar_min_range>(),
  number("lidar.max_range", "10", 0.1, 200, "", "farther hits are dropped (m; > min_range)").inGroup(kLidar).into<&S::lidar_max_range>(),
  number("lidar.range_noise", "0", 0, 1, "", "white noise σ (m) along each ray").inGroup(kLidar).into<&S::lidar_range_noise>(),
  number("position_fix.rate", "0", 0, 100, "", "fixes per second (Hz) of the base position, as lidar scans matched against the map give them (Capabilities::position_fix); 0: none").inGroup(kLocalisation).into<&S::position_fix_rate>(),
  number("position_fix.noise", "0.01", 1e-5, 1, "", "white noise σ (m) per axis on each fix").inGroup(kLocalisation).into<&S::position_fix_noise>(),
  choice("initial_posture", "stand", "stand|zero", "stand: *hip_pitch -0.4, *knee 0.8, *ankle_pitch -(hip_pitch + knee) so the soles are level, others 0; zero: all 0").inGroup(kInitial).into<&S::initial_posture>(),
  numberMap("initial_joints", "{}", -kTwoPi, kTwoPi, "", "joint name -> angle (rad) overriding the posture; within the URDF limits").inGroup(kInitial).into<&S::initial_joints>(),
  numbers("initial_xy", "[0, 0]", -1e4, 1e4, "", "base position (m) over the terrain").ofLength(2).inGroup(kInitial).into<&S::initial_xy>(),
  number("initial_yaw", "0", -kTwoPi, kTwoPi, "", "base heading (rad)").inGroup(kInitial).into<&S::initial_yaw>(),
  number("initial_clearance", "0", 0, 1000, "", "gap (m) between the lowest contact sphere and the terrain under it (0: touching)").inGroup(kInitial).into<&S::initial_clearance>(),
  number("host.stall_at", "-1", -1, 1e6, "", "simulated time (s) at which the control host stalls once, for host.stall; -1: never").inGroup(kHost).into<&S::host_stall_at>(),
  number("host.stall", "0.05", 0, 10, "", "length (s, wall time) of that stall").inGroup(kHost).into<&S::host_stall>(),
  number("host.jitter_from", "0", 0, 1e6, "", "simulated time (s) from which ticks are delayed at random").inGroup(kHost).into<&S::host_jitter_from>(),
  number("host.jitter_fraction", "0", 0, 1, "", "fraction of ticks delayed by host.jitter; 0: none").inGroup(kHost).into<&S::host_jitter_fraction>(),
  number("host.jitter", "0.002", 0, 1, "", "delay (s, wall time) of a jittered tick").inGroup(kHost).into<&S::host_jitter>(),

  R{"lidar.vertical_max", [](const S& s) {
      return s.lidar_vertical_min > s.lidar_vertical_max
                 ? "is below lidar.vertical_min (" + formatNumber(s.lidar_vertical_min) + ")"
                 : std::string();
    }},
  R{"lidar.max_range", [](const S& s) {
      return s.lidar_min_range >= s.lidar_max_range
                 ? "must be above lidar.min_range (" + formatNumber(s.lidar_min_range) + ")"
                 : std::string();
    }},
});
// clang-format on

}  // namespace

const std::vector<SettingKey>& simSettingKeys() { return kSchema.rows(); }

SimSettings parseSimSettings(const std::string& yaml, const std::string& origin) {
  return schema::parseSection(kSchema, yaml, origin, "the simbody backend section");
}

std::string simSettingsReference() { return schema::textReference(kSchema.keys()); }
const char* simSettingsDoc(const char* format) {
  return schema::backendSectionDoc(kSchema.keys(), "simbody", format);
}

}  // namespace ballast::simbody
