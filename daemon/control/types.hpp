// The plain structs the control loop passes between its parts and to the threads around it.
//
// Everything here is fixed-size and trivially copyable: it crosses threads through the rings
// and seqlocks of this directory, and the 1 kHz path copies it without allocating. Joint
// arrays are in the model's joint order (model.hpp), not the backend's. Frames: world z up;
// base velocities in the world frame; rpy = [roll, pitch, yaw] with R = Rz·Ry·Rx.
//
// The parts that plug into the loop see only these structs:
//   estimator  : backend::Sensors          -> EstimatedState
//   planner    : PlannerInput              -> PlannerOutput     (own thread, >= 100 Hz)
//   controller : ControllerInput           -> ControllerOutput  (every tick)
#pragma once

#include <cstdint>
#include <limits>
#include <memory>

#include "backend_abi.hpp"
#include "control/tick_timing.hpp"
#include "locomotion/plan.hpp"

namespace ballast::control {

inline constexpr int kMaxJoints = backend::kMaxJoints;
using model::kNumContacts;
/// Priority levels of the whole-body controller (paper, Table I).
inline constexpr int kNumPriorityLevels = 4;
inline constexpr int kMessageLength = 200;
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// kRecover: standing, the planner steps to recover from a push (last, so telemetry's numbers of
/// the others stay).
enum class Mode : std::uint8_t { kPassive, kStandUp, kStand, kWalk, kDamp, kRecover };

/// "passive", "stand-up", "stand", "walk", "damp", "recover": the names status reports.
const char* modeName(Mode mode);

/// The modes the planner plans for and the walking controller drives: standing, walking, and
/// the steps that recover from a push while standing.
inline constexpr bool plannedMode(Mode m) {
  return m == Mode::kStand || m == Mode::kWalk || m == Mode::kRecover;
}

struct BaseState {
  double position[3] = {};               ///< world, m
  double orientation[4] = {0, 0, 0, 1};  ///< world <- base, quaternion (x, y, z, w)
  double linear_velocity[3] = {};        ///< world, m/s
  double angular_velocity[3] = {};       ///< world, rad/s
  double rpy[3] = {};                    ///< roll, pitch, yaw of orientation, rad
};

struct EstimatedState {
  double t = 0.0;  ///< controller time, s
  BaseState base;
  int num_joints = 0;
  double q[kMaxJoints] = {};    ///< rad
  double dq[kMaxJoints] = {};   ///< rad/s
  double tau[kMaxJoints] = {};  ///< measured, N·m
  bool contact[kNumContacts] = {};
  double contact_position[kNumContacts][3] = {};  ///< world
  /// Estimated external force on the robot (a push): horizontal, world, N, zero under
  /// estimator.external_force_deadband times the robot's mass
  /// (estimation/external_force_observer.hpp).
  double external_force[3] = {};
};

/// What the operator asks of the base: a velocity (walking) and a standing pose.
struct BaseCommand {
  double vx = 0.0, vy = 0.0;  ///< m/s, heading frame (x forward, y left)
  double yaw_rate = 0.0;      ///< rad/s
  bool velocity_active = false;
  double expires_at = 0.0;  ///< controller time at which the velocity drops to zero
  double height = 0.0;      ///< base height above the ground, m
  double roll = 0.0, pitch = 0.0, yaw = 0.0;  ///< base orientation relative to the feet, rad
};

/// Planner slot: the kino-dynamic MPC (control/mpc_planner.hpp) fills PlannerOutput. Without a
/// planner the slot is empty and `walk` is refused.
struct PlannerInput {
  std::uint64_t sequence = 0;
  double t = 0.0;
  Mode mode = Mode::kPassive;
  /// First input after a time without planning (start, or back from damp/passive): the planner
  /// forgets its previous solution and gait phase.
  bool restart = false;
  /// s: the plan will be used from t + lead on (the solve's latency), so the planner starts it
  /// there, from the state the plan in force predicts for then (see MpcPlanner).
  double lead = 0.0;
  /// s of wall time after which the planner's SQP starts no further iteration (past the
  /// first; mpc::SqpSolver::solve). Real time: half a planner period, so that a plan is not late
  /// for its extra iterations; lockstep: 0, none (the plans do not depend on the host's speed).
  double iteration_budget = 0.0;
  /// The planner plans on the newest terrain map made of lidar scans up to this one (scans
  /// count from 1 as the loop hands them off). Real time: all of them; lockstep: those whose
  /// insertion was due by t (mapping.latency), so plans do not depend on the mapping thread's
  /// speed.
  std::uint64_t map_scan = ~std::uint64_t{0};
  EstimatedState state;
  BaseCommand command;
};
struct PlannerOutput {
  std::uint64_t sequence = 0;  ///< of the PlannerInput it answers
  double t = 0.0;              ///< controller time the plan starts at
  bool valid = false;          ///< false: solver failure or NaN; the loop keeps the last valid plan
  bool exception = false;      ///< the planner threw (a bug, not a hard problem): a fault
  double solve_ms = 0.0;
  char message[kMessageLength] = {};  ///< why it is not valid
  /// Whether the terrain map agrees with the stance feet (MapTerrain::checkUnderFeet; while it
  /// does not, the plan is made on the plane the feet stood on), and its largest error, m (NaN:
  /// nothing to compare).
  bool map_agrees = true;
  double map_disagreement = kNaN;
  /// The MPC's optimal state and input trajectories x*(t), u*(t), the contact schedule and the
  /// swing trajectories.
  locomotion::Plan plan;
};

struct ControllerInput {
  Mode mode = Mode::kPassive;
  double t = 0.0;
  double stand_up_progress = 0.0;  ///< 0..1 during stand-up
  EstimatedState state;
  BaseCommand command;
  const PlannerOutput* plan = nullptr;  ///< latest valid plan, nullptr if none
};
struct ControllerOutput {
  backend::JointCommand joint[kMaxJoints];
  /// Tracking error of each priority level (1: dynamics/contacts ... 4: contact forces), as
  /// the controller defines it; NaN where the controller has no such level.
  double task_error[kNumPriorityLevels] = {kNaN, kNaN, kNaN, kNaN};
  double q_ref[kMaxJoints] = {};  ///< joint reference the controller tracks (telemetry)
  /// The contact forces the whole-body controller asks for (on the robot, world frame, N; zero
  /// in swing), per contact point; NaN from a controller without contact forces (telemetry).
  double contact_force[kNumContacts][3] = {{kNaN, kNaN, kNaN}, {kNaN, kNaN, kNaN},
                                           {kNaN, kNaN, kNaN}, {kNaN, kNaN, kNaN}};
  /// Per contact point, the position the whole-body controller tracks (a swing's reference, a
  /// stance point's held position) and where the kinematics of the estimated state put the
  /// point (world, m); NaN from a controller without contact tasks (telemetry: a swing foot
  /// that does not follow its trajectory shows as the two apart).
  double contact_ref[kNumContacts][3] = {{kNaN, kNaN, kNaN}, {kNaN, kNaN, kNaN},
                                         {kNaN, kNaN, kNaN}, {kNaN, kNaN, kNaN}};
  double contact_position[kNumContacts][3] = {{kNaN, kNaN, kNaN}, {kNaN, kNaN, kNaN},
                                              {kNaN, kNaN, kNaN}, {kNaN, kNaN, kNaN}};
};

enum class FaultKind : std::uint8_t {
  kBackendFault,
  kBackendStale,
  kNotANumber,
  kFall,
  kEstop,
  kPlanner,
  kCommandGap,  ///< the motors went longer than safety.max_command_gap without a command
  kLateTicks,   ///< more than safety.max_late_fraction of the last second's ticks were late
  kException,   ///< the control or planner thread caught an exception
};
/// "backend_fault", "backend_stale", "nan", "fall", "estop", "planner", "command_gap",
/// "late_ticks", "exception".
const char* faultName(FaultKind kind);

struct Fault {
  FaultKind kind = FaultKind::kBackendFault;
  double t = 0.0;           ///< first occurrence
  std::uint32_t count = 0;  ///< occurrences since the last reset
  char message[kMessageLength] = {};
};

/// Faults since the last reset, one entry per kind (the first message kept, occurrences counted).
struct FaultList {
  static constexpr int kCapacity = 12;
  Fault fault[kCapacity];
  int size = 0;
  /// Returns true when this kind is new since the last clear().
  bool add(FaultKind kind, double t, const char* message);
  void clear() { size = 0; }
  bool has(FaultKind kind) const;
};

/// Where the control thread's wall time went since start, s (benchmarks: BM_LockstepWalk).
struct LoopProfile {
  double estimator = 0.0;   ///< the state estimator
  double planner = 0.0;     ///< posting to the planner and taking its plans (lockstep: waiting)
  double mapping = 0.0;     ///< handing lidar scans to the mapping thread (lockstep: waiting for maps)
  double controller = 0.0;  ///< standing controller or plan sampling + whole-body controller
  double backend = 0.0;     ///< advance(): lockstep, the simulation's step; real time, its work
  double total = 0.0;       ///< whole ticks (real time: without the sleep)
};

/// What the loop publishes every tick (seqlock); status requests are answered from it.
struct LoopStatus {
  double t = 0.0;
  std::uint64_t ticks = 0;
  Mode mode = Mode::kPassive;
  bool estop = false;  ///< estop latched
  bool fallen = false;
  bool lockstep = false;
  /// Lockstep held (LoopOptions::hold): the controller time the loop runs to (`advance`); it
  /// stands still there, answering commands with a tick each.
  bool held = false;
  double run_until = 0.0;
  bool planner_available = false;
  double stand_up_progress = 0.0;
  BaseState base;  ///< estimated
  bool has_truth = false;
  BaseState truth;  ///< simulator ground truth (has_truth)
  bool truth_non_foot_contact = false;
  BaseCommand command;
  bool contacts[kNumContacts] = {};
  double external_force[3] = {};  ///< estimated push, world, N (EstimatedState::external_force)
  double mpc_ms = 0.0;      ///< last planner solve
  /// The terrain map agrees with the stance feet (PlannerOutput::map_agrees) and its largest
  /// error under them, m (NaN: nothing compared).
  bool map_agrees = true;
  double map_disagreement = kNaN;
  double wbc_ms = 0.0;      ///< last controller computation (plan sampling + WBC, or standing)
  double wbc_ms_max = 0.0;  ///< since start
  std::uint64_t tick_overruns = 0;       ///< late ticks since start (timing.late_ticks)
  TimingSummary timing;                  ///< real-time schedule (zero in lockstep)
  LoopProfile profile;
  std::uint64_t wbc_degraded_ticks = 0;  ///< ticks the WBC dropped lower priorities (QP failed)
  std::uint64_t planner_failures = 0;    ///< planner answers without a valid plan (kept the last)
  std::uint64_t position_fixes = 0;      ///< backend position fixes the estimator fused
  FaultList faults;
  std::uint64_t telemetry_frames = 0;
  std::uint64_t telemetry_dropped = 0;
  std::uint64_t settings_generation = 0;  ///< bumps when a profile switch takes effect
  std::uint64_t last_command = 0;  ///< sequence of the last command the loop took
  int num_joints = 0;
  double q[kMaxJoints] = {};
  double tau[kMaxJoints] = {};
};

/// Operator commands, IO thread -> loop (ring).
enum class CommandKind : std::uint8_t {
  kStand,
  kWalk,
  kPose,
  kStop,
  kEstop,
  kReset,
  kPassive,
  kPush,
  kSwitchSettings,
  kAdvance,  ///< lockstep held (LoopOptions::hold): run to controller time `until`
};

struct ControlSettings;

struct OperatorCommand {
  std::uint64_t sequence = 0;
  CommandKind kind = CommandKind::kStop;
  double vx = 0.0, vy = 0.0, yaw_rate = 0.0, ttl = 0.0;      ///< walk (ttl <= 0: the profile's)
  double height = kNaN, roll = 0.0, pitch = 0.0, yaw = 0.0;  ///< pose (height NaN: nominal)
  backend::Push push;                                        ///< push
  double until = 0.0;                                        ///< advance: controller time, s
  /// Switch: a handle the IO side keeps (SettingsKeeper) until the loop has taken it.
  const std::shared_ptr<const ControlSettings>* settings = nullptr;
};

/// Why the loop refused a command.
enum class Refusal : std::uint8_t {
  kNone,
  kRefused,      ///< not in this mode (the message says what to do)
  kUnavailable,  ///< the capability does not exist (no planner, no disturbance input)
  kOutOfRange,   ///< beyond the profile's safety limits
  kBackend,      ///< the backend said no
};

/// Loop -> IO thread (ring): the answer to one OperatorCommand.
struct CommandReply {
  std::uint64_t sequence = 0;
  Refusal refusal = Refusal::kNone;
  Mode mode = Mode::kPassive;  ///< after the command
  char message[kMessageLength] = {};
};

/// Loop -> IO thread (ring): something worth a log line (mode changes, faults).
struct LoopEvent {
  double t = 0.0;
  bool warning = false;
  char message[kMessageLength] = {};
};

/// Copies text into a fixed buffer, truncating (the loop's way of keeping a message).
template <int N>
void copyText(char (&out)[N], const char* text) {
  int i = 0;
  for (; text && text[i] && i + 1 < N; ++i) out[i] = text[i];
  out[i] = '\0';
}

}  // namespace ballast::control
