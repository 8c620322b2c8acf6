// The control loop: one thread, one tick per control period, read top to bottom in tick().
//
//   read sensors -> estimate -> operator commands -> modes, safety -> planner post
//   -> controller -> NaN guard -> write commands -> publish status, telemetry -> advance
//
// Controllers: passive (free joints), damp, stand-up (StandController's joint PD to the
// posture), stand and walk (WalkingController: the plan through the whole-body controller, once
// a plan exists; the StandController until then). The planner is fed in stand and walk only.
//
// It talks to the other threads only through lock-free structures sized at construction:
// commands arrive in an SPSC ring from the IO thread, replies and log events leave in two
// more (a tick's replies leave after its status is published, so a client that has its reply
// never reads a status from before its command), the status is published through a seqlock, telemetry frames through a ring the writer
// thread drains, and a profile switch arrives as a handle to settings the IO side keeps
// (settings_keeper.hpp): the loop shares them and never frees any. tick() allocates nothing and
// takes no lock (test/unit/control/control_loop_test.cpp interposes malloc to check).
//
// Faults (backend kFault/kStale, repeated sensor sequence, NaN in sensors or commands, a fall, a
// plan older than safety.max_plan_age, an exception in the control or planner thread) put the
// robot in damp until `reset`. A planner answer without a valid plan (solver failure, NaN) never
// reaches the motors: the loop keeps the last valid plan, logs the first failure of a streak
// and counts them.
//
// Real time: advance() paces the loop on absolute deadlines and reports each tick's lateness;
// the deadline policy is that of robot stacks (ros2_control warns on an overrun and carries on;
// the motors' own watchdogs catch a host that really stalls): a late tick is counted and shown
// (status `timing`), never a fault by itself. The fault is the danger itself: the motors going
// longer than safety.max_command_gap without a command, or more than safety.max_late_fraction of
// the last second's ticks late. Lockstep: advance() steps the simulation, so the loop runs as
// fast as the backend, simulation time is controller time and nothing is ever late; held
// (LoopOptions::hold), only as far as a client asks.
#pragma once

#include <array>
#include <atomic>
#include <memory>

#include "control/loop_estimator.hpp"
#include "control/mode_machine.hpp"
#include "control/planner_slot.hpp"
#include "control/seqlock.hpp"
#include "control/settings.hpp"
#include "control/settings_keeper.hpp"
#include "control/spsc_ring.hpp"
#include "control/stand_controller.hpp"
#include "control/telemetry.hpp"
#include "control/terrain_mapper.hpp"
#include "control/walking_controller.hpp"
#include "model/model.hpp"

namespace ballast::control {

/// CLOCK_MONOTONIC in ns: the loop's wall clock unless LoopOptions::clock says otherwise.
std::uint64_t monotonicNs();

/// Writes to `bytes` of the calling thread's stack below the caller's frame, one byte a page:
/// a real-time thread started after ballastd locked its memory on fault has that much of its
/// stack resident (and locked) before its first deadline, not a page fault at its first deep
/// call. The control loop calls it as it starts, in real time; the planner's thread, started
/// with the daemon before the memory is locked, has its whole stack made resident then.
void touchStack(std::size_t bytes = 512 * 1024);

struct LoopOptions {
  bool lockstep = false;
  /// Lockstep only: the loop ticks only up to the controller time a client asks for (command
  /// kAdvance), and one tick for each command that arrives while it waits there, so a client
  /// that drives it lands every command at the controller time it chooses: a scripted run is
  /// deterministic (ballastd --hold; ballast-study).
  bool hold = false;
  /// Wall clock (ns) for the tick's work; nullptr: monotonicNs. Tests substitute a clock they
  /// advance themselves.
  std::uint64_t (*clock)() = nullptr;
  std::size_t command_capacity = 64;
  std::size_t telemetry_capacity = 4096;
  int shutdown_ticks = 50;  ///< damped ticks before backend stop() at shutdown
  /// Real time: SCHED_FIFO priority of the planner thread and its workers (0: normal).
  int planner_priority = 0;
};

class ControlLoop {
 public:
  /// The backend must be configured and started. Throws std::runtime_error when its joints do
  /// not match the model (names listed), model::ModelError for missing frames.
  ControlLoop(const model::Model& model, backend::Backend& backend, SettingsPtr settings,
              const LoopOptions& options);
  ~ControlLoop();
  ControlLoop(const ControlLoop&) = delete;
  ControlLoop& operator=(const ControlLoop&) = delete;

  /// Before run(): seat a planner (its thread starts here). nullptr leaves the slot empty. The
  /// planner must outlive the loop, or be detached first.
  void attachPlanner(Planner* planner);
  /// Not while run() runs: stops the planner's thread and empties the slot.
  void detachPlanner();
  /// Before run(): the live map the loop hands the backend's lidar scans to (nullptr: none;
  /// terrain_mapper.hpp). It must outlive the loop's run.
  void attachMapper(TerrainMapper* mapper) {
    mapper_ = mapper;
    // Lockstep: the planner sees a scan's map only once it is due (handOffScan).
    planner_input_.map_scan = mapper && options_.lockstep ? 0 : ~std::uint64_t{0};
  }

  // ---- IO thread (single producer of commands, single consumer of replies and events) ----
  /// False if the command ring is full.
  bool submit(const OperatorCommand& command);
  bool popReply(CommandReply& reply) { return replies_.tryPop(reply); }
  bool popEvent(LoopEvent& event) { return events_.tryPop(event); }
  /// An eventfd that becomes readable when replies or events wait (read it to rearm).
  int wakeFd() const { return wake_fd_; }

  // ---- any thread ----
  LoopStatus status() const { return status_.load(); }
  TelemetryRing& telemetryRing() { return telemetry_; }
  /// The writer whose recording state the loop follows (nullptr: no telemetry).
  void setTelemetryWriter(const TelemetryWriter* writer) { writer_ = writer; }
  const std::vector<std::string>& jointNames() const { return joint_names_; }
  double nominalHeight() const { return stand_.nominalHeight(); }

  // ---- control thread, between ticks (lockstep tests and tools) ----
  /// The state estimator's seat: its filter's output of the last tick.
  const LoopEstimator& estimator() const { return estimator_; }
  /// The plan in force (the last valid one; PlannerOutput::valid false before the first).
  const PlannerOutput& plan() const { return plan_; }

  // ---- control thread ----
  /// Ticks until stop is set, then damps for shutdown_ticks and stops the backend. An exception
  /// in a tick is a fault: the motors are damped and the loop goes on.
  void run(const std::atomic<bool>& stop);
  /// One control period.
  void tick();
  /// tick(), with any exception turned into a fault (what run() calls).
  void guardedTick();

 private:
  void readSensors();
  /// A new lidar scan copied into the mapper's slot (mapping.rate); lockstep: the maps due.
  void handOffScan();
  void handleCommands();
  void applySettings(const SettingsPtr& next, CommandReply& reply);
  void detectFall();
  void planPost();
  void computeCommands();
  void guardCommands();
  void writeCommands();
  void publish();
  void sendReplies();
  void updateTruth();
  void record();
  void raise(FaultKind kind, const char* message);
  void event(bool warning, const char* message);
  void backendStatus(backend::Status status, const char* call);
  /// The deadline policy, after advance(): timing recorded, too many late ticks a fault.
  void keepSchedule(double work);
  void notifyIo();
  double secondsSince(std::uint64_t start_ns) const;
  /// How far ahead of its input the next plan starts (PlannerInput::lead).
  double planLead() const;
  /// A plan whose map agreement changed: the event, warning when it stops agreeing.
  void mapAgreement();

  const model::Model& model_;
  backend::Backend& backend_;
  SettingsPtr settings_;  // shared with the IO side, which frees it (never the loop)
  LoopOptions options_;
  int nj_;
  std::vector<std::string> joint_names_;
  std::array<int, kMaxJoints> backend_index_{};  // model joint -> backend joint

  LoopEstimator estimator_;
  StandController stand_;
  WalkingController walking_;
  ModeMachine modes_;
  PlannerSlot planner_;
  TerrainMapper* mapper_ = nullptr;
  std::uint64_t scans_handed_ = 0;
  double next_scan_ = -1.0;         // controller time before which a scan is not inserted
  std::uint64_t scan_pending_ = 0;  // lockstep: the scan whose map is due at scan_due_
  double scan_due_ = 0.0;
  /// The last valid plan, the loop's own copy (the planner's buffers turn over underneath).
  PlannerOutput plan_;
  bool have_plan_ = false;
  bool map_agrees_ = true;  // the last plan's PlannerOutput::map_agrees
  /// This tick's contact schedule from the plan in force (standing, no plan: every point).
  std::array<bool, kNumContacts> scheduled_{true, true, true, true};
  bool planning_ = false;  // inputs are being posted (stand, walk)
  std::uint64_t first_sequence_ = 0;  // of the input that restarted planning
  double restart_t_ = 0.0;            // controller time of that input
  int warm_plans_ = 0;                // valid plans since then (the first ones are cold solves)
  std::uint64_t failed_sequence_ = 0;  // of the last answer without a valid plan
  std::uint64_t planner_failures_ = 0, position_fixes_ = 0;
  int planner_streak_ = 0;  // failed answers since the last valid plan
  bool plan_age_said_ = false;  // the plan in force's age was said (half safety.max_plan_age)
  char planner_message_[kMessageLength] = {};
  std::uint64_t wbc_degraded_ = 0;
  double solve_time_ = 0.0;  // s, recent planner solve time (real time: the plans' lead)

  SpscRing<OperatorCommand> commands_;
  SpscRing<CommandReply> replies_;
  static constexpr int kCommandsPerTick = 8;  // a flood of requests never stretches one tick
  std::array<CommandReply, kCommandsPerTick> tick_replies_{};
  int num_tick_replies_ = 0;
  SpscRing<LoopEvent> events_;
  SeqLock<LoopStatus> status_;
  TelemetryRing telemetry_;
  const TelemetryWriter* writer_ = nullptr;
  int wake_fd_ = -1;

  // Per-tick state (all preallocated).
  backend::Sensors sensors_;
  backend::Commands commands_out_;
  ControllerInput input_;
  ControllerOutput output_;
  PlannerInput planner_input_;
  LoopStatus published_;
  TelemetryFrame frame_;
  BaseState truth_;
  double q_[kMaxJoints] = {}, dq_[kMaxJoints] = {}, tau_[kMaxJoints] = {};
  std::array<double, kMaxJoints> kp_{}, kd_{}, blend_kp_{}, blend_kd_{};
  double blend_start_ = -1.0;
  bool sensors_ok_ = false;
  bool started_ = false;
  bool shutting_down_ = false;
  bool fallen_ = false;
  Mode last_mode_ = Mode::kPassive;
  std::uint64_t ticks_ = 0, last_sequence_ = 0, dropped_ = 0, recorded_ = 0;
  std::uint64_t (*clock_)();
  backend::TickTiming timing_;  // what the last advance() reported
  TickTimingStats timing_stats_;
  double last_write_time_ = 0.0;     // backend time of the last command write
  bool have_written_ = false;
  std::uint64_t tick_start_ = 0;     // wall clock at the start of this tick
  LoopProfile profile_;
  LoopProfile tick_profile_;         // the last tick's share of each part
  double next_stall_warning_ = 0.0;  // controller time
  double next_host_stall_warning_ = 0.0;
  double late_work_ = 0.0;           // work of the last late tick, s
  double next_late_warning_ = 0.0;   // controller time
  std::uint64_t settings_generation_ = 0;
  std::uint64_t last_command_ = 0;
  double t_ = 0.0, period_ = 0.001;
  double run_until_ = 0.0;  // hold: controller time the loop runs to
  double wbc_ms_ = 0.0, wbc_ms_max_ = 0.0;
  char message_[kMessageLength] = {};
};

}  // namespace ballast::control
