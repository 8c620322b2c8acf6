// The recording's column table (telemetry.hpp, TelemetryColumn): one row per column, or per
// family of columns (one per contact point, priority level or joint), in file order. Each row
// says where the value comes from and how much of it a recording keeps; the TSV and .blog
// writers, the .blog header (so `ballast log` and `ballast plot`, which read only files),
// ballastd(8)'s TELEMETRY table and the tests all take the columns from here.
//
// Resolutions: what is exact stays exact (the time, the mode, contact flags, the operator's
// commands); a measured or computed quantity is kept to a step below what the robot resolves,
// so rounding to it loses nothing anyone can use:
// - joint angles 1e-5 rad: a 19-bit absolute encoder's step is 1.2e-5 rad, the MIT motor
//   protocol's 16-bit position 3.8e-4 rad over +-12.5 rad;
// - joint velocities 1e-3 rad/s: a 19-bit encoder differentiated at 1 kHz resolves 0.012 rad/s,
//   the MIT protocol's 12-bit velocity 0.02 rad/s over +-45 rad/s;
// - joint torques 0.01 N·m: the MIT protocol's 12-bit torque is 0.009 N·m over +-18 N·m and
//   coarser for larger motors; current-sensed torque is no finer;
// - base position and orientation 1e-5 m and rad, velocities 1e-4 m/s and rad/s: 10-100 times
//   below an IMU's noise (0.01-0.1 deg, a 16-bit gyro's step 1e-3 rad/s at +-2000 deg/s) and
//   the estimator's millimetres;
// - contact forces 0.1 N, a foot force sensor's step;
// - times of work 1 µs (1e-3 ms), as cyclictest reports latencies; the RMS joint error 1e-6
//   rad, the priority levels' errors 1e-5 (in m/s^2, N or rad: up to 21 km/s^2 or kN).
// On a MuJoCo walk this took the .blog from 376 bytes per frame (f32) to 132, and 143 with the
// contact forces: 86 MB for 10 minutes at 1 kHz. Per column group (zstd of the group alone,
// bytes per frame): tau 32, tauff 28, dq 22, qref 15, base estimate 12 and truth 9, contact
// forces 9, q 7, err_p 5, the rest under 2.
#include <cmath>
#include <cstdio>
#include <string>

#include "control/telemetry.hpp"

namespace ballast::control {

namespace {

using blog::Type;

/// Base quantity q of b: position (0-2), linear velocity (3-5), roll pitch yaw (6-8), angular
/// velocity (9-11), then the velocity in the heading frame (yaw only): forward (12), left (13).
double baseValue(const BaseState& b, int q) {
  if (q < 12) {
    const double* groups[4] = {b.position, b.linear_velocity, b.rpy, b.angular_velocity};
    return groups[q / 3][q % 3];
  }
  const double c = std::cos(b.rpy[2]), s = std::sin(b.rpy[2]);
  return q == 12 ? c * b.linear_velocity[0] + s * b.linear_velocity[1]
                 : -s * b.linear_velocity[0] + c * b.linear_velocity[1];
}
template <int Q>
double estimate(const TelemetryFrame& f, int) {
  return baseValue(f.base, Q);
}
template <int Q>
double truth(const TelemetryFrame& f, int) {
  return f.has_truth ? baseValue(f.truth, Q) : kNaN;
}

double limbError(const TelemetryFrame& f, int) {
  double sum = 0.0;
  for (int j = 0; j < f.num_joints; ++j) sum += (f.q[j] - f.q_ref[j]) * (f.q[j] - f.q_ref[j]);
  return f.num_joints > 0 ? std::sqrt(sum / f.num_joints) : 0.0;
}

constexpr Repeat kOnce = Repeat::kOnce, kContacts = Repeat::kPerContact,
                 kLevels = Repeat::kPerLevel, kJoints = Repeat::kPerJoint;
constexpr Type kF64 = Type::kF64, kU8 = Type::kU8, kI32 = Type::kI32;

// clang-format off
const std::vector<TelemetryColumn> kTable = {
  {"t", kOnce, "s", kF64, 0, "controller time (simulated time in lockstep)", [](const TelemetryFrame& f, int) { return f.t; }},
  {"mode", kOnce, "-", kU8, 0, "0 passive, 1 stand-up, 2 stand, 3 walk, 4 damp, 5 recover", [](const TelemetryFrame& f, int) { return double(f.mode); }},

  {"x", kOnce, "m", kI32, 1e-5, "base position x, world frame, estimated", estimate<0>},
  {"y", kOnce, "m", kI32, 1e-5, "base position y, world frame, estimated", estimate<1>},
  {"z", kOnce, "m", kI32, 1e-5, "base position z (height), world frame, estimated", estimate<2>},
  {"vx", kOnce, "m/s", kI32, 1e-4, "base velocity x, world frame, estimated", estimate<3>},
  {"vy", kOnce, "m/s", kI32, 1e-4, "base velocity y, world frame, estimated", estimate<4>},
  {"vz", kOnce, "m/s", kI32, 1e-4, "base velocity z, world frame, estimated", estimate<5>},
  {"roll", kOnce, "rad", kI32, 1e-5, "base roll (ZYX angles), estimated", estimate<6>},
  {"pitch", kOnce, "rad", kI32, 1e-5, "base pitch (ZYX angles), estimated", estimate<7>},
  {"yaw", kOnce, "rad", kI32, 1e-5, "base yaw (ZYX angles), estimated", estimate<8>},
  {"wx", kOnce, "rad/s", kI32, 1e-4, "base angular velocity x, world frame, estimated", estimate<9>},
  {"wy", kOnce, "rad/s", kI32, 1e-4, "base angular velocity y, world frame, estimated", estimate<10>},
  {"wz", kOnce, "rad/s", kI32, 1e-4, "base angular velocity z, world frame, estimated", estimate<11>},
  {"v_fwd", kOnce, "m/s", kI32, 1e-4, "base velocity forward in the heading frame (yaw only), estimated", estimate<12>},
  {"v_lat", kOnce, "m/s", kI32, 1e-4, "base velocity to the left in the heading frame, estimated", estimate<13>},

  {"true_x", kOnce, "m", kI32, 1e-5, "base position x, world frame, ground truth (simulation; NaN on hardware)", truth<0>},
  {"true_y", kOnce, "m", kI32, 1e-5, "base position y, world frame, ground truth (simulation; NaN on hardware)", truth<1>},
  {"true_z", kOnce, "m", kI32, 1e-5, "base position z (height), world frame, ground truth (simulation; NaN on hardware)", truth<2>},
  {"true_vx", kOnce, "m/s", kI32, 1e-4, "base velocity x, world frame, ground truth (simulation; NaN on hardware)", truth<3>},
  {"true_vy", kOnce, "m/s", kI32, 1e-4, "base velocity y, world frame, ground truth (simulation; NaN on hardware)", truth<4>},
  {"true_vz", kOnce, "m/s", kI32, 1e-4, "base velocity z, world frame, ground truth (simulation; NaN on hardware)", truth<5>},
  {"true_roll", kOnce, "rad", kI32, 1e-5, "base roll (ZYX angles), ground truth (simulation; NaN on hardware)", truth<6>},
  {"true_pitch", kOnce, "rad", kI32, 1e-5, "base pitch (ZYX angles), ground truth (simulation; NaN on hardware)", truth<7>},
  {"true_yaw", kOnce, "rad", kI32, 1e-5, "base yaw (ZYX angles), ground truth (simulation; NaN on hardware)", truth<8>},
  {"true_wx", kOnce, "rad/s", kI32, 1e-4, "base angular velocity x, world frame, ground truth (simulation; NaN on hardware)", truth<9>},
  {"true_wy", kOnce, "rad/s", kI32, 1e-4, "base angular velocity y, world frame, ground truth (simulation; NaN on hardware)", truth<10>},
  {"true_wz", kOnce, "rad/s", kI32, 1e-4, "base angular velocity z, world frame, ground truth (simulation; NaN on hardware)", truth<11>},
  {"true_v_fwd", kOnce, "m/s", kI32, 1e-4, "base velocity forward in the heading frame (yaw only), ground truth (simulation; NaN on hardware)", truth<12>},
  {"true_v_lat", kOnce, "m/s", kI32, 1e-4, "base velocity to the left in the heading frame, ground truth (simulation; NaN on hardware)", truth<13>},

  {"cmd_vx", kOnce, "m/s", kF64, 0, "commanded velocity forward, heading frame", [](const TelemetryFrame& f, int) { return f.command.vx; }},
  {"cmd_vy", kOnce, "m/s", kF64, 0, "commanded velocity to the left", [](const TelemetryFrame& f, int) { return f.command.vy; }},
  {"cmd_yaw_rate", kOnce, "rad/s", kF64, 0, "commanded turning rate", [](const TelemetryFrame& f, int) { return f.command.yaw_rate; }},
  {"cmd_height", kOnce, "m", kF64, 0, "commanded base height (0: nominal)", [](const TelemetryFrame& f, int) { return f.command.height; }},
  {"cmd_roll", kOnce, "rad", kF64, 0, "commanded base roll", [](const TelemetryFrame& f, int) { return f.command.roll; }},
  {"cmd_pitch", kOnce, "rad", kF64, 0, "commanded base pitch", [](const TelemetryFrame& f, int) { return f.command.pitch; }},
  {"cmd_yaw", kOnce, "rad", kF64, 0, "commanded base yaw", [](const TelemetryFrame& f, int) { return f.command.yaw; }},

  {"contact_", kContacts, "-", kU8, 0, "1 where the contact point is in contact (estimator): 0 left toe, 1 left heel, 2 right toe, 3 right heel", [](const TelemetryFrame& f, int i) { return f.contact[i] ? 1.0 : 0.0; }},
  {"planned_", kContacts, "-", kU8, 0, "1 where the plan in force has the contact point in stance, 0 in swing (as contact_; standing and before a plan: 1)", [](const TelemetryFrame& f, int i) { return f.planned_contact[i] ? 1.0 : 0.0; }},
  {"fx_", kContacts, "N", kI32, 0.1, "the contact force the whole-body controller asks for at contact point 0..3 (as contact_), on the robot, world frame x; 0 in swing, NaN without the controller", [](const TelemetryFrame& f, int i) { return f.contact_force[i][0]; }},
  {"fy_", kContacts, "N", kI32, 0.1, "the same along y", [](const TelemetryFrame& f, int i) { return f.contact_force[i][1]; }},
  {"fz_", kContacts, "N", kI32, 0.1, "the same along z (the normal force on flat ground)", [](const TelemetryFrame& f, int i) { return f.contact_force[i][2]; }},
  {"pref_x_", kContacts, "m", kI32, 1e-5, "the position the whole-body controller tracks for contact point 0..3 (as contact_): its swing's reference, or where it stands; world frame x; NaN without the controller", [](const TelemetryFrame& f, int i) { return f.contact_ref[i][0]; }},
  {"pref_y_", kContacts, "m", kI32, 1e-5, "the same along y", [](const TelemetryFrame& f, int i) { return f.contact_ref[i][1]; }},
  {"pref_z_", kContacts, "m", kI32, 1e-5, "the same along z", [](const TelemetryFrame& f, int i) { return f.contact_ref[i][2]; }},
  {"p_x_", kContacts, "m", kI32, 1e-5, "contact point 0..3's position from the estimated state's kinematics, world frame x (beside pref_x_: a swing off its trajectory); NaN without the controller", [](const TelemetryFrame& f, int i) { return f.contact_position[i][0]; }},
  {"p_y_", kContacts, "m", kI32, 1e-5, "the same along y", [](const TelemetryFrame& f, int i) { return f.contact_position[i][1]; }},
  {"p_z_", kContacts, "m", kI32, 1e-5, "the same along z", [](const TelemetryFrame& f, int i) { return f.contact_position[i][2]; }},
  {"err_p", kLevels, "-", kI32, 1e-5, "tracking error of priority level 1..4 as the controller defines it (walking: the residual of the level's tasks in their units, m/s^2 and N; standing: 2 the RMS joint error, rad, 3 the base orientation error, rad); NaN where it has no such level", [](const TelemetryFrame& f, int i) { return f.task_error[i]; }},
  {"mpc_ms", kOnce, "ms", kI32, 1e-3, "the MPC's solve time of the plan in force", [](const TelemetryFrame& f, int) { return f.mpc_ms; }},
  {"wbc_ms", kOnce, "ms", kI32, 1e-3, "the whole-body controller's time this tick", [](const TelemetryFrame& f, int) { return f.wbc_ms; }},
  {"tick_ms", kOnce, "ms", kI32, 1e-3, "the tick's work until it was recorded (read through write)", [](const TelemetryFrame& f, int) { return f.tick_ms; }},
  {"lateness_ms", kOnce, "ms", kI32, 1e-3, "how late the tick began (real time; 0 in lockstep)", [](const TelemetryFrame& f, int) { return f.lateness_ms; }},
  {"limb_err", kOnce, "rad", kI32, 1e-6, "RMS over the joints of q - qref (the paper's Fig. 3 b)", limbError},

  {"q_", kJoints, "rad", kI32, 1e-5, "joint position, measured; one column per joint, named q_JOINT", [](const TelemetryFrame& f, int j) { return f.q[j]; }},
  {"dq_", kJoints, "rad/s", kI32, 1e-3, "joint velocity, measured", [](const TelemetryFrame& f, int j) { return f.dq[j]; }},
  {"tau_", kJoints, "N*m", kI32, 1e-2, "joint torque, measured", [](const TelemetryFrame& f, int j) { return f.tau[j]; }},
  {"qref_", kJoints, "rad", kI32, 1e-5, "joint position the controller tracks", [](const TelemetryFrame& f, int j) { return f.q_ref[j]; }},
  {"tauff_", kJoints, "N*m", kI32, 1e-2, "feed-forward torque sent to the motor", [](const TelemetryFrame& f, int j) { return f.tau_ff[j]; }},
};
// clang-format on

}  // namespace

const std::vector<TelemetryColumn>& telemetryTable() { return kTable; }

std::string telemetryColumnsMan() {
  std::string out = ".PD 0\n";  // one line after another, no blank line between
  for (const TelemetryColumn& row : kTable) {
    out += ".TP\n.B ";
    out += row.name;
    switch (row.repeat) {
      case Repeat::kOnce: break;
      case Repeat::kPerContact: out += "0..3"; break;
      case Repeat::kPerLevel: out += "1..4"; break;
      case Repeat::kPerJoint: out += "\\fIJOINT\\fR"; break;
    }
    out += "\n";
    out += row.unit;
    if (row.type == blog::Type::kI32) {
      char step[32];
      std::snprintf(step, sizeof step, ", to %g: ", row.resolution);
      out += step;
    } else {
      out += std::string(", exact (") + blog::typeName(row.type) + "): ";
    }
    out += row.doc;
    out += "\n";
  }
  return out + ".PD\n";
}

}  // namespace ballast::control
