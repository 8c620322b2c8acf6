// The schema table. One row per key; the helpers below keep a row on one line or two.
#include "profile/schema.hpp"

#include "common/closest_name.hpp"  // plugins/common

#include <algorithm>
#include <deque>
#include <sstream>

#include "estimation/settings.hpp"

namespace ballast::profile {

namespace {

constexpr double kInf = kUnbounded;
constexpr double kPi = 3.14159265358979323846;

constexpr Key flag(const char* n, const char* def, const char* doc) {
  return {n, KeyType::kBool, def, -kInf, kInf, "", doc};
}
constexpr Key integer(const char* n, const char* def, double lo, double hi, const char* unit,
                      const char* doc) {
  return {n, KeyType::kInt, def, lo, hi, unit, doc};
}
constexpr Key number(const char* n, const char* def, double lo, double hi, const char* unit,
                     const char* doc) {
  return {n, KeyType::kNumber, def, lo, hi, unit, doc};
}
constexpr Key text(const char* n, const char* def, const char* doc) {
  return {n, KeyType::kString, def, -kInf, kInf, "", doc};
}
constexpr Key path(const char* n, const char* def, const char* doc) {
  return {n, KeyType::kPath, def, -kInf, kInf, "", doc};
}
constexpr Key choice(const char* n, const char* def, const char* choices, const char* doc) {
  return {n, KeyType::kEnum, def, -kInf, kInf, choices, doc};
}
constexpr Key numbers(const char* n, const char* def, double lo, double hi, const char* unit,
                      const char* doc) {
  return {n, KeyType::kNumberList, def, lo, hi, unit, doc};
}
constexpr Key integers(const char* n, const char* def, double lo, double hi, const char* doc) {
  return {n, KeyType::kIntList, def, lo, hi, "", doc};
}
constexpr Key strings(const char* n, const char* def, const char* doc) {
  return {n, KeyType::kStringList, def, -kInf, kInf, "", doc};
}
constexpr Key paths(const char* n, const char* def, const char* doc) {
  return {n, KeyType::kPathList, def, -kInf, kInf, "", doc};
}
constexpr Key numberMap(const char* n, const char* def, double lo, double hi, const char* unit,
                        const char* doc) {
  return {n, KeyType::kNumberMap, def, lo, hi, unit, doc};
}
constexpr Key groupMap(const char* n, const char* def, const char* doc) {
  return {n, KeyType::kGroupMap, def, -kInf, kInf, "", doc};
}

// clang-format off
const std::vector<Key> kTable = {
  // ---- the profile itself
  text("extends", "", "base profile: a file (relative to this one) or a profile name; maps merge, scalars and lists replace"),
  text("description", "", "one line about the profile, shown by `ballast profile list`"),

  // ---- robot: the model and its standing posture
  path("robot.urdf", "", "robot model (URDF); required").needsRestart(),
  strings("robot.contact_frames", "[left_toe, left_heel, right_toe, right_heel]", "the four contact points (URDF links): left toe, left heel, right toe, right heel").ofLength(4).needsRestart(),
  text("robot.imu_frame", "imu", "URDF link of the IMU; it must be fixed to the floating base").needsRestart(),
  groupMap("robot.joint_groups", "{}", "joint groups, name: [URDF joints]; every actuated joint belongs to exactly one").needsRestart(),
  numberMap("robot.armature", "{}", 0, 10, "kg·m²", "reflected rotor inertia (rotor inertia times the gear ratio squared) per joint group or joint (a joint's entry wins over its group's), in the controller's model and the simulation; joints not listed: 0").needsRestart(),
  numberMap("robot.nominal_posture", "{}", -2 * kPi, 2 * kPi, "rad", "standing posture, joint: angle; joints not listed stand at 0"),

  // ---- control: the loop and the standing controller
  number("control.rate", "1000", 100, 5000, "Hz", "control loop rate").needsRestart(),
  choice("control.initial_mode", "passive", "passive|stand-up", "mode at start: passive, or stand-up at once (a simulated robot that starts on its feet)").needsRestart(),
  number("control.stand_up_duration", "2", 0.1, 30, "s", "stand-up: from the posture at its start to the standing posture"),
  numberMap("control.joint_kp", "{}", 0, 5000, "N·m/rad", "joint stiffness per joint group (motor PD)"),
  numberMap("control.joint_kd", "{}", 0, 500, "N·m·s/rad", "joint damping per joint group (motor PD)"),
  flag("control.gravity_compensation", "true", "add the model's gravity torques (least-norm contact forces) to the joint PD"),
  number("control.gain_blend_time", "0.5", 0, 10, "s", "profile switch: gains blend from the old to the new over this time"),
  number("control.pose_speed", "0.1", 0.01, 1, "m/s", "standing height changes at most this fast"),
  number("control.pose_angular_speed", "0.3", 0.01, 3, "rad/s", "standing orientation changes at most this fast"),

  // ---- backend: the plugin and its own section
  text("backend.name", "simbody", "backend plugin: libballast_backend_<name>.so").needsRestart(),
  paths("backend.plugin_dirs", "[]", "directories searched first for the plugin; then $BALLAST_PLUGIN_PATH, the build tree, the install tree").needsRestart(),
  integer("backend.seed", "0", 0, 9007199254740992.0, "", "seed for sensor noise and anything random in the backend").needsRestart(),

  // ---- gait (daemon/gait; locomotion/locomotion_planner.hpp LocomotionSettings)
  number("gait.period", "0.8", 0.2, 2, "s", "gait cycle: one step of each leg"),
  number("gait.double_support", "0.2", 0, 0.8, "", "fraction of the cycle with both feet on the ground"),
  number("gait.toe_off_lead", "0", 0, 0.5, "s", "toe-off and heel-strike: a heel lifts and lands this much before its toe (0: together)"),
  number("gait.swing_apex", "0.08", 0.01, 0.3, "m", "swing-foot clearance at mid-swing, above the terrain"),
  number("gait.foothold_gain", "0.15", 0, 1, "", "k of the foothold rule hip + T/2 v_des + k (v - v_des)"),
  number("gait.step_height", "0.03", 0, 1, "m", "a swing over terrain that rises or falls more than this is a step: the foot lifts before it moves and moves before it lands"),
  number("gait.step_lift", "0.2", 0, 0.45, "", "stepping: fraction of the swing at each end spent lifting (lowering) without moving horizontally"),
  number("gait.replan_until", "0.7", 0, 1, "", "fraction of a swing after which its touch-down point is held"),
  number("gait.min_foot_distance", "0.12", 0, 1, "m", "closest the left and right contact points may come (swing planning and the MPC's collision constraint)"),
  number("gait.walk_start_delay", "0.3", 0, 2, "s", "walking from standing starts this much after the command: the weight shifts onto the first stance foot meanwhile"),
  number("gait.stop_delay", "0.4", 0, 2, "s", "stepping goes on this long after the commanded velocity reached zero"),
  number("gait.foothold_lead", "0.05", 0, 0.5, "m", "footholds are planned from the measured base moved toward the commanded one by at most this"),

  // ---- planner: the kino-dynamic MPC (daemon/mpc, daemon/locomotion)
  number("planner.rate", "100", 10, 1000, "Hz", "planner rate, controller time").needsRestart(),
  number("planner.latency", "0.005", 0, 0.1, "s", "lockstep: a plan is used this long (controller time) after the state it starts from, as a real-time solve's delay (at most 1 / planner.rate); real time uses each plan when it arrives").needsRestart(),
  number("planner.horizon", "1", 0.1, 5, "s", "MPC horizon (at most 100 nodes)"),
  number("planner.dt", "0.02", 0.002, 0.2, "s", "MPC node spacing"),
  integer("planner.threads", "2", 1, 16, "", "threads that linearise the MPC's nodes"),
  number("planner.max_acceleration", "1", 0.05, 10, "m/s^2", "the commanded velocity slews toward the operator's at this rate"),
  number("planner.max_yaw_acceleration", "1.5", 0.05, 20, "rad/s^2", "the commanded yaw rate slews toward the operator's at this rate"),
  number("planner.max_position_lead", "0.15", 0.01, 1, "m", "walking: the commanded base position is kept this close to the measured one"),
  number("planner.q_linear_velocity", "40", 0, 1e6, "(m/s)^-2", "Q: centroidal linear momentum / mass against the commanded velocity"),
  number("planner.q_angular_momentum", "1", 0, 1e6, "(m^2/s)^-2", "Q: centroidal angular momentum / mass"),
  numbers("planner.q_base_position", "[200, 200, 800]", 0, 1e6, "m^-2", "Q: base position, [x y z]").ofLength(3),
  numbers("planner.q_base_orientation", "[300, 800, 800]", 0, 1e6, "rad^-2", "Q: base orientation, [yaw pitch roll]").ofLength(3),
  number("planner.q_leg_joints", "5", 0, 1e6, "rad^-2", "Q: joint positions against the nominal posture, joints other than wbc.joint_space_joints"),
  number("planner.q_arm_joints", "5", 0, 1e6, "rad^-2", "Q: joint positions against the nominal posture, wbc.joint_space_joints (the arms)"),
  number("planner.r_forces", "0.001", 0, 1e6, "N^-2", "R: contact forces against the weight shared by the stance points"),
  number("planner.r_leg_joint_velocities", "0.5", 0, 1e6, "(rad/s)^-2", "R: joint velocities, joints other than wbc.joint_space_joints (small values let the plan chatter)"),
  number("planner.r_arm_joint_velocities", "1", 0, 1e6, "(rad/s)^-2", "R: joint velocities, wbc.joint_space_joints (larger values freeze the arm swing)"),
  number("planner.terminal_weight_scale", "5", 0, 1e6, "", "Q at the last node = this times Q"),
  numbers("planner.friction_barrier", "[0.1, 5]", 1e-9, 1e6, "", "relaxed log barrier of the friction cone and normal force bounds, [weight (paper: xi), delta in N]").ofLength(2),
  numbers("planner.limit_barrier", "[0.1, 0.02]", 1e-9, 1e6, "", "relaxed log barrier of the joint position and velocity limits, [weight, delta in rad or rad/s]").ofLength(2),
  number("planner.friction_coefficient", "0.6", 0.05, 2, "", "friction cone coefficient"),
  number("planner.min_normal_force", "0", 0, 1e4, "N", "lower bound of a stance contact's normal force"),
  number("planner.max_normal_force", "1000", 1, 1e5, "N", "upper bound of a contact's normal force"),
  number("planner.joint_limit_margin", "0.05", 0, 0.5, "rad", "kept from each URDF joint limit"),
  number("planner.swing_position_gain", "20", 0, 1e3, "1/s", "swing contact points: velocity = reference velocity + this gain times the position error"),

  // ---- wbc: the whole-body controller (daemon/wbc; wbc/settings.hpp)
  choice("wbc.variant", "hierarchical", "hierarchical|weighted", "strict priorities (the paper's cH) or one weighted QP (cNH)"),
  text("wbc.base_frame", "pelvis", "URDF link whose pose and twist the base task tracks; on the floating base"),
  strings("wbc.joint_space_joints", "[arms]", "joints tracked in joint space at priority 2 (the legs follow their feet): URDF joints or joint group names"),
  number("wbc.swing_kp", "400", 0, 1e5, "1/s^2", "priority 2: swing contact point tracking stiffness (world frame)"),
  number("wbc.swing_kd", "40", 0, 1e4, "1/s", "priority 2: swing contact point tracking damping"),
  number("wbc.joint_kp", "400", 0, 1e5, "1/s^2", "priority 2: joint-space tracking stiffness"),
  number("wbc.joint_kd", "40", 0, 1e4, "1/s", "priority 2: joint-space tracking damping"),
  numbers("wbc.base_kp", "[400, 400, 400, 400, 400, 400]", 0, 1e5, "1/s^2", "priority 3: base tracking stiffness, [x y z position; x y z orientation] (world)").ofLength(6),
  numbers("wbc.base_kd", "[40, 40, 40, 40, 40, 40]", 0, 1e4, "1/s", "priority 3: base tracking damping, [x y z linear; x y z angular] (world)").ofLength(6),
  number("wbc.friction_coefficient", "0.6", 0.01, 10, "", "priority 1: friction pyramid coefficient"),
  number("wbc.torque_limit_scale", "1", 0.1, 1, "", "priority 1: fraction of the URDF effort limits the controller may command"),
  number("wbc.limb_weight", "100", 0, 1e9, "", "weighted variant: weight of the limb tasks"),
  number("wbc.base_weight", "10", 0, 1e9, "", "weighted variant: weight of the base task"),
  number("wbc.contact_force_weight", "0.001", 0, 1e9, "", "weighted variant: weight of the contact-force task"),
  number("wbc.regularization", "1e-8", 1e-15, 0.01, "", "added to the diagonal of every level's Hessian (scaled units)"),
  integer("wbc.max_qp_iterations", "200", 1, 100000, "", "active-set iterations per QP before it gives up"),
  number("wbc.motor_kp", "20", 0, 5000, "N·m/rad", "stand and walk under the whole-body controller: the motors' PD stiffness around its joint targets (its torques do the work)"),
  number("wbc.motor_kd", "2", 0, 500, "N·m·s/rad", "the motors' PD damping under the whole-body controller"),

  // ---- estimator (daemon/estimation)
  choice("estimator.source", "estimate", "estimate|truth", "what the controllers run on: the estimate, or the simulator's ground truth (diagnostics)").needsRestart(),
  flag("estimator.position_fix", "true", "fuse the backend's position fixes (a localisation source: lidar against the map, motion capture) into the base position, when it has them"),
  flag("estimator.contact_force_check", "true", "a scheduled contact counts only once the estimated normal force confirms it (estimator.contact_force_threshold)"),
  // The filter's number keys follow, generated from estimation::estimatorNumberKeys().

  // ---- terrain
  path("terrain.map", "", "OctoMap file (.bt or .ot) of the terrain for the planner; the simulation builds its world from it at start (a profile switch changes the planner's map only); empty: a flat floor"),
  number("terrain.ground_height", "0", -100, 100, "m", "height of the floor under the robot at start"),

  // ---- safety
  number("safety.max_tilt", "0.8", 0.05, 3.14, "rad", "fall: the base tilts beyond this"),
  number("safety.min_base_height", "0.45", 0, 5, "m", "fall: the base is lower than this above terrain.ground_height"),
  flag("safety.fall_on_non_foot_contact", "true", "fall: a body other than the feet touches the ground (simulation ground truth)"),
  number("safety.damping", "4", 0, 500, "N·m·s/rad", "joint damping in damp mode"),
  number("safety.command_ttl", "10", 0.01, 3600, "s", "a walk command without a ttl lasts this long (controller time)"),
  number("safety.max_command_ttl", "600", 0.01, 86400, "s", "longest ttl a walk command may ask for"),
  number("safety.max_vx", "1.5", 0, 5, "m/s", "largest forward/backward velocity command"),
  number("safety.max_vy", "0.5", 0, 5, "m/s", "largest sideways velocity command"),
  number("safety.max_yaw_rate", "1", 0, 10, "rad/s", "largest turning rate command"),
  number("safety.min_pose_height", "0.7", 0, 5, "m", "lowest standing height `pose` may ask for"),
  number("safety.max_pose_height", "0.95", 0, 5, "m", "highest standing height `pose` may ask for"),
  number("safety.max_pose_tilt", "0.35", 0, 1.5, "rad", "largest standing roll or pitch `pose` may ask for"),
  number("safety.max_pose_yaw", "0.35", 0, 1.5, "rad", "largest standing yaw `pose` may ask for"),
  number("safety.max_plan_age", "0.1", 0.01, 1, "s", "a failed planner solve keeps the last plan; stand or walk on a plan older than this is a fault (damp)"),
  number("safety.max_command_gap", "0.01", 0.002, 1, "s", "real time: the motors going longer than this without a command (on the backend clock: the wall for hardware, the world for a simulation) is a fault (damp); a late tick alone is not"),
  number("safety.max_late_fraction", "0.2", 0, 1, "", "real time: more than this fraction of the last second's ticks late (their predecessor ran past the deadline) is a fault (damp)"),
  number("safety.max_push_force", "300", 0, 1e4, "N", "largest push (simulation)"),
  number("safety.max_push_duration", "5", 0, 60, "s", "longest push (simulation)"),

  // ---- telemetry
  integer("telemetry.decimation", "1", 1, 1000, "", "record every Nth control tick"),
  integer("telemetry.ring_frames", "4096", 64, 1048576, "", "frames buffered between the loop and the writer thread").needsRestart(),
  path("telemetry.record_on_start", "", "record from the start into this file (empty: only on `ballast record start`)").needsRestart(),

  // ---- server: socket, clients, lease
  path("server.socket", "", "socket path; empty: $XDG_RUNTIME_DIR/ballast/ballastd.sock").needsRestart(),
  integers("server.allowed_uids", "[]", 0, 4294967295.0, "uids allowed to connect besides the daemon's own"),
  number("server.lease_timeout", "300", 0, 86400, "s", "a lease unused this long (wall time) lapses; 0: never"),
  integer("server.max_message_bytes", "65536", 256, 16777216, "bytes", "longest request line"),
  integer("server.max_clients", "32", 1, 1024, "", "most clients connected at once"),
  number("server.max_watch_rate", "100", 1, 1000, "Hz", "fastest status stream `watch` may ask for"),
  number("server.reply_timeout", "2", 0.1, 60, "s", "wall time a request waits for the control loop before a timeout error"),
};
// clang-format on

/// The table with the estimator's number keys (declared once, in estimation/settings.cpp, with
/// their bounds; the defaults are EstimatorSettings' initialisers) after estimator.source.
std::vector<Key> withEstimatorKeys(std::vector<Key> table) {
  static std::deque<std::string> text;  // names and defaults the rows point into
  const estimation::EstimatorSettings defaults;
  std::vector<Key> rows;
  for (const estimation::EstimatorNumberKey& k : estimation::estimatorNumberKeys()) {
    text.push_back(std::string("estimator.") + k.key);
    const char* name = text.back().c_str();
    std::ostringstream value;
    value << defaults.*k.field;
    text.push_back(value.str());
    rows.push_back({name, KeyType::kNumber, text.back().c_str(), k.min, k.max, k.unit, k.doc});
  }
  auto at = std::find_if(table.begin(), table.end(),
                         [](const Key& k) { return std::string(k.name) == "estimator.source"; });
  table.insert(at + 1, rows.begin(), rows.end());
  return table;
}

const std::vector<Key> kSchema = withEstimatorKeys(kTable);


}  // namespace

const char* typeName(KeyType type) {
  switch (type) {
    case KeyType::kBool:
      return "bool";
    case KeyType::kInt:
      return "integer";
    case KeyType::kNumber:
      return "number";
    case KeyType::kString:
      return "string";
    case KeyType::kEnum:
      return "choice";
    case KeyType::kPath:
      return "path";
    case KeyType::kNumberList:
      return "list of numbers";
    case KeyType::kIntList:
      return "list of integers";
    case KeyType::kStringList:
      return "list of strings";
    case KeyType::kPathList:
      return "list of paths";
    case KeyType::kNumberMap:
      return "map of numbers";
    case KeyType::kGroupMap:
      return "map of lists of names";
    case KeyType::kSection:
      return "section";
  }
  return "?";
}

const std::vector<Key>& schema() {
  return kSchema;
}

const Key* findKey(const std::string& name) {
  for (const Key& k : kSchema)
    if (name == k.name) return &k;
  return nullptr;
}

bool isSection(const std::string& name) {
  const std::string prefix = name + ".";
  for (const Key& k : kSchema)
    if (std::string(k.name).rfind(prefix, 0) == 0) return true;
  return false;
}

bool isBackendSection(const std::string& name) {
  const std::string prefix = "backend.";
  if (name.rfind(prefix, 0) != 0 || findKey(name)) return false;
  const std::string rest = name.substr(prefix.size());
  return !rest.empty() && rest.find('.') == std::string::npos;
}

std::string closestKey(const std::string& name) {
  return closestName(name, kSchema, [](const Key& k) { return std::string(k.name); });
}

namespace {

std::string bounds(const Key& k) {
  if (k.type == KeyType::kEnum) return std::string("one of ") + k.unit;
  const bool numeric = k.type == KeyType::kInt || k.type == KeyType::kNumber ||
                       k.type == KeyType::kNumberList || k.type == KeyType::kIntList ||
                       k.type == KeyType::kNumberMap;
  if (!numeric) return "";
  std::ostringstream out;
  out << "[" << k.min << ", " << k.max << "]";
  if (k.unit && *k.unit) out << " " << k.unit;
  if (std::string(k.unit) == "rad") out << " (or deg with a \"deg\" suffix)";
  return out.str();
}

/// Escapes text for troff: backslashes and leading dots or quotes.
std::string troff(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '\\')
      out += "\\e";
    else if (c == '-')
      out += "\\-";
    else
      out += c;
  }
  if (!out.empty() && (out[0] == '.' || out[0] == '\'')) out = "\\&" + out;
  return out;
}

}  // namespace

std::string schemaManPage() {
  std::ostringstream m;
  m << R"(.\" Generated by `ballastd --dump-schema=man` from daemon/profile/schema.cpp: edit the
.\" schema, then regenerate this file (a test compares them).
.TH BALLAST-PROFILE 5 "" "ballast" "File formats"
.SH NAME
ballast-profile \- ballastd profiles: robot, backend, gait, planner, controller, estimator, safety
.SH SYNOPSIS
.B ballastd \-\-profile
.I FILE.yaml
.SH DESCRIPTION
A profile is a YAML map of sections. Every key is declared in one schema (listed below with
its type, default, bounds and meaning). A key that is not in the schema, a value of the wrong
type and a value out of bounds are errors reported as
.IP
.I file:line:column: key: what is wrong
.PP
and
.BR ballastd (8)
refuses to start; at run time
.RB ( "ballast profile use" ,
SIGHUP) the running profile stays in force.
.PP
.B extends:
names a base profile, a file relative to this one or a profile name looked up beside it and
in the profile directories. The base is loaded first, then this file on top of it: maps merge
key by key, scalars and lists replace. Paths are relative to the file that sets them. Angles
(unit rad) also take degrees with a
.B deg
suffix, e.g.
.BR "left_knee: 35deg" .
.PP
The backend's own keys live in a map named after the backend,
.BR backend.simbody ,
.BR backend.socketcan ;
ballastd passes that map, as YAML text with its file and line, to the plugin, which checks
it. A backend section other than the one of
.B backend.name
is an error in the file that names the backend, and ignored when inherited.
.PP
Keys marked
.I restart
cannot change on a running daemon: a profile switch that changes one is refused.
.SH KEYS
)";
  std::string section;
  for (const Key& k : kSchema) {
    const std::string name = k.name;
    const auto dot = name.find('.');
    const std::string sec = dot == std::string::npos ? "" : name.substr(0, dot);
    if (sec != section || (sec.empty() && &k == &kSchema.front())) {
      section = sec;
      m << ".SS " << (section.empty() ? "top level" : section) << "\n";
    }
    m << ".TP\n.B " << troff(name) << "\n";
    m << "(" << typeName(k.type);
    if (k.length) m << ", " << k.length << " elements";
    const std::string b = bounds(k);
    if (!b.empty()) m << ", " << troff(b);
    m << "; default: " << troff(*k.fallback ? k.fallback : "\"\"");
    if (k.restart) m << "; restart";
    m << ")\n" << troff(k.doc) << "\n";
  }
  m << ".TP\n.B backend.<name>\n(section; restart)\nthe backend's own keys; see the backend's "
       "documentation\n";
  m << R"(.SH FILES
.TP
.I profiles/sim\-flat.yaml
the default: Simbody simulation, flat floor
.TP
.I profiles/sim\-stage.yaml, profiles/sim\-rough.yaml
simulation with a stage to step onto, and on rough ground
.TP
.I profiles/hardware\-example.yaml
a SocketCAN robot: a template to adapt
.PP
Installed profiles are in
.IR <prefix>/share/ballast/profiles .
.SH EXAMPLE
.nf
extends: sim\-flat
description: softer arms
control:
  joint_kp: {arms: 60}
robot:
  nominal_posture: {left_elbow: \-20deg, right_elbow: \-20deg}
.fi
.SH SEE ALSO
.BR ballastd (8),
.BR ballast (1)
)";
  return m.str();
}

std::string schemaYaml() {
  std::ostringstream y;
  y << "# Every profile key with its default (ballastd --dump-schema=yaml).\n";
  std::string section;
  for (const Key& k : kSchema) {
    const std::string name = k.name;
    const auto dot = name.find('.');
    const std::string sec = dot == std::string::npos ? "" : name.substr(0, dot);
    const std::string leaf = dot == std::string::npos ? name : name.substr(dot + 1);
    if (sec != section) {
      section = sec;
      if (!sec.empty()) y << "\n" << section << ":\n";
    }
    const std::string indent = sec.empty() ? "" : "  ";
    y << indent << "# " << k.doc;
    const std::string b = bounds(k);
    if (!b.empty()) y << " " << b;
    if (k.restart) y << " (restart)";
    y << "\n" << indent << leaf << ": " << (*k.fallback ? k.fallback : "\"\"") << "\n";
  }
  return y.str();
}

}  // namespace ballast::profile
