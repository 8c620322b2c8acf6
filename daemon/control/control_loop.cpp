#include "control/control_loop.hpp"

#include <alloca.h>
#include <pthread.h>
#include <sys/eventfd.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <thread>

#include "model/base_conventions.hpp"

namespace ballast::control {

std::uint64_t monotonicNs() {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::uint64_t>(ts.tv_sec) * 1000000000ull + ts.tv_nsec;
}

__attribute__((noinline)) void touchStack(std::size_t bytes) {
  // Not inlined: the region is this call's frame, below the caller's, where its callees go.
  volatile unsigned char* region = static_cast<volatile unsigned char*>(alloca(bytes));
  const std::size_t page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  for (std::size_t i = 0; i < bytes; i += page) region[i] = 0;
}

namespace {

static_assert(PlannerSlot::kLockstepTimeout == 10.0, "kPlannerStuck names the timeout");
// How old the plan in force may be while the planner's first solves after a restart come in
// (ControlLoop::planPost).
constexpr double kColdStartAge = 0.5;  // s
constexpr const char* kPlannerStuck = "the planner did not answer within 10 s of wall time (lockstep)";

bool finite3(const double* x) {
  return std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]);
}

const char* statusName(backend::Status s) {
  switch (s) {
    case backend::Status::kOk:
      return "ok";
    case backend::Status::kStale:
      return "stale data";
    case backend::Status::kFault:
      return "fault";
  }
  return "unknown status";
}
}  // namespace

ControlLoop::ControlLoop(const model::Model& model, backend::Backend& backend,
                         SettingsPtr settings, const LoopOptions& options)
    : model_(model),
      backend_(backend),
      settings_(std::move(settings)),
      options_(options),
      nj_(model.nj()),
      estimator_(model, *settings_),
      stand_(model, *settings_),
      walking_(model, *settings_),
      commands_(options.command_capacity),
      replies_(options.command_capacity),
      events_(256),
      telemetry_(options.telemetry_capacity),
      clock_(options.clock ? options.clock : &monotonicNs),
      timing_stats_(settings_->rate) {
  if (nj_ > kMaxJoints)
    throw std::runtime_error(model.sourceFile + ": " + std::to_string(nj_) +
                             " joints; ballastd handles at most " + std::to_string(kMaxJoints));
  const backend::Capabilities& caps = backend.capabilities();
  std::string missing;
  for (int j = 0; j < nj_; ++j) {
    const std::string& name = model.jointName[j + 1];
    joint_names_.push_back(name);
    backend_index_[j] = -1;
    for (int b = 0; b < caps.num_joints; ++b)
      if (name == caps.joint_names[b]) backend_index_[j] = b;
    if (backend_index_[j] < 0) missing += (missing.empty() ? "" : ", ") + name;
  }
  if (!missing.empty())
    throw std::runtime_error(std::string("backend '") + caps.name + "' has no joint named " +
                             missing + " (the model " + model.sourceFile +
                             " has them): use the same URDF for both");
  period_ = 1.0 / settings_->rate;
  modes_.configure(*settings_, stand_.nominalHeight());
  for (int j = 0; j < nj_; ++j) {
    kp_[j] = settings_->kp[j];
    kd_[j] = settings_->kd[j];
  }
  commands_out_.num_joints = caps.num_joints;
  wake_fd_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
}

ControlLoop::~ControlLoop() {
  planner_.stop();
  if (wake_fd_ >= 0) close(wake_fd_);
}

void ControlLoop::attachPlanner(Planner* planner) {
  if (!options_.lockstep)
    planner_.injectStall(settings_->planner_injected_stall_at, settings_->planner_injected_stall);
  planner_.start(planner, settings_->planner_rate, options_.lockstep, settings_->planner_latency,
                 options_.lockstep ? 0 : options_.planner_priority);
}

void ControlLoop::detachPlanner() {
  planner_.detach();
  have_plan_ = planning_ = false;
}

bool ControlLoop::submit(const OperatorCommand& command) {
  return commands_.tryPush(command);
}

void ControlLoop::notifyIo() {
  const std::uint64_t one = 1;
  [[maybe_unused]] const ssize_t n = write(wake_fd_, &one, sizeof(one));
}

void ControlLoop::event(bool warning, const char* message) {
  LoopEvent e;
  e.t = t_;
  e.warning = warning;
  copyText(e.message, message);
  events_.tryPush(e);  // a full ring loses a log line, never a tick
  notifyIo();
}

void ControlLoop::raise(FaultKind kind, const char* message) {
  if (modes_.fault(kind, t_, message)) {
    char line[kMessageLength];
    std::snprintf(line, sizeof(line), "fault %s: %s", faultName(kind), message);
    event(true, line);
  }
}

void ControlLoop::backendStatus(backend::Status status, const char* call) {
  if (status == backend::Status::kOk) return;
  const backend::Error& e = backend_.lastError();
  std::snprintf(message_, sizeof(message_), "backend %s(): %s%s%.150s", call, statusName(status),
                e.empty() ? "" : ": ", e.message);
  switch (status) {
    case backend::Status::kStale:
      raise(FaultKind::kBackendStale, message_);
      break;
    default:
      raise(FaultKind::kBackendFault, message_);
      break;
  }
}

void ControlLoop::run(const std::atomic<bool>& stop) {
  pthread_setname_np(pthread_self(), "ballast-loop");
  if (!options_.lockstep) touchStack();
  while (!stop.load(std::memory_order_relaxed)) {
    // Held: wait at run_until_ (the last tick's time within half a period of it) unless a
    // command waits; it gets one tick, at the same controller time whenever it arrives.
    if (options_.lockstep && options_.hold && t_ >= run_until_ - 0.5 * period_ &&
        commands_.size() == 0) {
      std::this_thread::sleep_for(std::chrono::microseconds(200));
      continue;
    }
    guardedTick();
  }
  shutting_down_ = true;
  modes_.damp();
  for (int i = 0; i < options_.shutdown_ticks; ++i) guardedTick();
  try {
    backend_.stop();
  } catch (...) {
  }
  publish();
}

void ControlLoop::guardedTick() {
  try {
    tick();
    return;
  } catch (const std::exception& e) {
    std::snprintf(message_, sizeof(message_), "control thread: exception: %.160s", e.what());
  } catch (...) {
    std::snprintf(message_, sizeof(message_), "control thread: an exception of unknown type");
  }
  // The tick did not finish: damp the motors, answer what was asked, keep the schedule. Each
  // step on its own, since any of them may be what threw.
  raise(FaultKind::kException, message_);
  try {
    dampOutput(nj_, sensors_ok_ ? q_ : input_.state.q, settings_->damping, output_);
    writeCommands();
  } catch (...) {
  }
  try {
    publish();
    sendReplies();
  } catch (...) {
  }
  try {
    ++ticks_;
    backendStatus(backend_.advance(timing_), "advance");
  } catch (...) {
    // A backend that throws from advance() would spin: keep the period by sleeping it.
    timespec ts{0, static_cast<long>(period_ * 1e9)};
    nanosleep(&ts, nullptr);
  }
}

void ControlLoop::tick() {
  const std::uint64_t start = tick_start_ = clock_();
  readSensors();
  if (mapper_) {
    const std::uint64_t mapping_start = clock_();
    handOffScan();
    tick_profile_.mapping = secondsSince(mapping_start);
    profile_.mapping += tick_profile_.mapping;
  }
  if (!started_ && sensors_ok_) {
    modes_.start(settings_->initial_mode, t_);
    if (settings_->initial_mode == Mode::kStandUp) stand_.beginStandUp(input_.state);
    last_mode_ = modes_.mode();
    started_ = true;
  }
  handleCommands();
  modes_.update(t_);
  detectFall();

  const std::uint64_t planner_start = clock_();
  planPost();
  tick_profile_.planner = secondsSince(planner_start);
  profile_.planner += tick_profile_.planner;

  const Mode mode = shutting_down_ ? Mode::kDamp : modes_.mode();
  if (mode != last_mode_) {
    if (mode == Mode::kStandUp) stand_.beginStandUp(input_.state);
    char line[kMessageLength];
    std::snprintf(line, sizeof(line), "mode %s -> %s", modeName(last_mode_), modeName(mode));
    event(false, line);
    last_mode_ = mode;
  }
  const std::uint64_t controller_start = clock_();
  computeCommands();
  wbc_ms_ = secondsSince(controller_start) * 1e3;
  tick_profile_.controller = wbc_ms_ * 1e-3;
  profile_.controller += tick_profile_.controller;
  guardCommands();
  writeCommands();

  wbc_ms_max_ = std::max(wbc_ms_max_, wbc_ms_);
  updateTruth();
  record();
  publish();
  sendReplies();
  ++ticks_;
  const double work = secondsSince(start);
  timing_ = backend::TickTiming{};
  const std::uint64_t advance_start = clock_();
  backendStatus(backend_.advance(timing_), "advance");
  const double backend = options_.lockstep ? secondsSince(advance_start) : timing_.work;
  tick_profile_.backend = backend;
  tick_profile_.total = work + timing_.work;
  profile_.backend += backend;
  profile_.total += work + backend;
  keepSchedule(work + timing_.work);
}

void ControlLoop::keepSchedule(double work) {
  // Lockstep: simulated time waits for the loop, nothing is ever late.
  if (options_.lockstep) return;
  timing_stats_.record(timing_, work);
  if (timing_.host_stall > 0.0 && t_ >= next_host_stall_warning_) {
    // Shown (at most one a second), never a fault: the simulated motors had their commands all
    // along.
    next_host_stall_warning_ = t_ + 1.0;
    std::snprintf(message_, sizeof(message_),
                  "host stall: the host did not run the control thread for %.2f ms (the tick "
                  "worked %.2f ms); the simulated world waited. On a robot: a command gap "
                  "(PREEMPT_RT prevents it)",
                  timing_.host_stall * 1e3, work * 1e3);
    event(true, message_);
  }
  if (timing_.late) {
    // Counted and shown, not a fault by itself; logged at most every 10 s of controller time,
    // a stall (periods skipped) at most every second unless it is long, with where the tick's
    // time went.
    late_work_ = work;
    if (timing_.skipped > 0 && (t_ >= next_stall_warning_ || timing_.lateness > 5.0 * period_)) {
      next_stall_warning_ = t_ + 1.0;
      const LoopProfile& p = tick_profile_;
      std::snprintf(message_, sizeof(message_),
                    "stalled tick: began %.2f ms after its deadline, %u periods skipped; the tick "
                    "before worked %.2f ms: estimator %.2f, mapping %.2f, planner %.2f, "
                    "controller %.2f, backend %.2f (the rest %.2f)",
                    timing_.lateness * 1e3, timing_.skipped, work * 1e3, p.estimator * 1e3,
                    p.mapping * 1e3, p.planner * 1e3, p.controller * 1e3, timing_.work * 1e3,
                    (work - p.estimator - p.mapping - p.planner - p.controller - timing_.work) *
                        1e3);
      event(true, message_);
    }
    if (t_ >= next_late_warning_) {
      next_late_warning_ = t_ + 10.0;
      const TimingSummary m = timing_stats_.summary();
      std::snprintf(message_, sizeof(message_),
                    "late tick: began %.2f ms after its deadline (the tick before worked %.2f ms, "
                    "%.2f ms of it in the backend)%s; %llu late so far, lateness p99 %.2f ms, "
                    "max %.2f ms over %.0f s",
                    timing_.lateness * 1e3, work * 1e3, timing_.work * 1e3,
                    timing_.skipped ? ", periods skipped" : "",
                    static_cast<unsigned long long>(m.late_ticks), m.lateness_p99 * 1e3,
                    m.lateness_max * 1e3, m.window);
      event(true, message_);
    }
  }
  const ControlSettings& s = *settings_;
  const std::uint32_t window = timing_stats_.windowTicks();
  const std::uint32_t late = timing_stats_.lateInLastSecond();
  if (window > 0 && static_cast<double>(late) > s.max_late_fraction * s.rate) {
    std::snprintf(message_, sizeof(message_),
                  "%u of the last %u ticks were late (%s %.2f of a second's ticks); the last late "
                  "one did %.2f ms of work",
                  late, window, settingName(s, &s.max_late_fraction, "limit"), s.max_late_fraction,
                  late_work_ * 1e3);
    raise(FaultKind::kLateTicks, message_);
  }
}

void ControlLoop::planPost() {
  // The planner works in the planned modes; leaving them forgets the plan.
  const Mode mode = modes_.mode();
  const bool plan = planner_.available() && sensors_ok_ && !shutting_down_ && plannedMode(mode);
  if (!plan) {
    planning_ = false;
    have_plan_ = false;
    planner_streak_ = 0;
    return;
  }
  if (!planning_ || planner_.due(t_)) {
    planner_input_.t = t_;
    planner_input_.mode = mode;
    planner_input_.restart = !planning_;
    planner_input_.state = input_.state;
    planner_input_.command = modes_.command();
    planner_input_.lead = planLead();
    planner_input_.iteration_budget = options_.lockstep ? 0.0 : 0.5 / settings_->planner_rate;
    planning_ = true;
    bool timed_out = !planner_.post(planner_input_);
    if (planner_input_.restart) {
      first_sequence_ = planner_input_.sequence;
      restart_t_ = t_;
      warm_plans_ = 0;
    }
    if (timed_out) raise(FaultKind::kPlanner, kPlannerStuck);
  }
  bool timed_out = false;
  const PlannerOutput* p = planner_.latest(t_, timed_out);
  if (timed_out) raise(FaultKind::kPlanner, kPlannerStuck);
  // A new answer, to an input from after the restart?
  if (p && p->sequence != plan_.sequence && p->sequence != failed_sequence_ &&
      p->sequence >= first_sequence_) {
    if (p->exception) {
      std::snprintf(message_, sizeof(message_), "planner thread: %.170s", p->message);
      raise(FaultKind::kException, message_);
      failed_sequence_ = p->sequence;
    } else if (!p->valid) {
      // One failed solve is not a fall: the plan in force stays (checked for age below). The
      // first failure of a streak is logged; all are counted.
      if (planner_streak_++ == 0) {
        std::snprintf(message_, sizeof(message_),
                      "planner: no valid plan (%.150s); keeping the last one", p->message);
        event(true, message_);
      }
      ++planner_failures_;
      copyText(planner_message_, p->message);
      failed_sequence_ = p->sequence;
    } else {
      plan_ = *p;  // a copy the planner cannot overwrite (about 80 kB, once per plan)
      have_plan_ = true;
      ++warm_plans_;
      mapAgreement();
      modes_.recovering(plan_.plan.recovering, t_);
      // The solves' recent latency, for the next plan's lead (real time).
      solve_time_ = solve_time_ > 0.0 ? 0.8 * solve_time_ + 0.2 * p->solve_ms * 1e-3
                                      : p->solve_ms * 1e-3;
      planner_streak_ = 0;
      plan_age_said_ = false;
    }
  }
  // The first solves after planning (re)starts are cold, without a warm start: in real time on a
  // 2-core host of a third of its speed 60-75 ms each against 7 warm, and two of them in a row
  // outlasted safety.max_plan_age while the robot stood on the plan it had just taken. Until the
  // second plan is in, the age counts from the restart and may reach kColdStartAge; a planner that
  // never answers is a fault then too.
  const bool cold = planning_ && warm_plans_ < 2;
  const double age = cold ? t_ - restart_t_ : t_ - plan_.t;
  const double limit = cold ? std::max(kColdStartAge, settings_->max_plan_age) : settings_->max_plan_age;
  // The loop tracks the plan in force while no newer one comes (it covers planner.horizon):
  // said once at half the limit, so that a planner that comes late shows before it damps.
  const bool fault = (have_plan_ || cold) && age > limit;
  const bool late = !fault && have_plan_ && !cold && !plan_age_said_ && age > 0.5 * limit;
  if (!fault && !late) return;
  // Did it not answer because its solve computes that long, or because its thread does not
  // run (blocked, or not scheduled)? Real time only: in lockstep the loop waits for it.
  char silent[kMessageLength] = "the planner did not answer";
  if (!options_.lockstep) {
    const PlannerSlot::Progress p = planner_.progress();
    if (p.solving)
      std::snprintf(silent, sizeof(silent),
                    "the planner did not answer: in a solve for %.1f ms, %.1f ms of it on a CPU",
                    p.wall * 1e3, p.cpu * 1e3);
    else
      std::snprintf(silent, sizeof(silent), "the planner did not answer: not in a solve");
  }
  const char* reason = planner_streak_ > 0 ? planner_message_ : silent;
  const char* key = settingName(*settings_, &settings_->max_plan_age, "limit");
  if (late) {
    plan_age_said_ = true;
    std::snprintf(message_, sizeof(message_),
                  "planner: the plan in force is %.3f s old (%s %.3f s): %.120s; tracking it", age,
                  key, limit, reason);
    event(true, message_);
    return;
  }
  if (cold)
    std::snprintf(message_, sizeof(message_),
                  "no valid plan %.3f s after planning started (%.3f s allowed while it starts): "
                  "%.110s",
                  age, limit, reason);
  else
    std::snprintf(message_, sizeof(message_), "no valid plan for %.3f s (%s %.3f s): %.120s", age,
                  key, limit, reason);
  raise(FaultKind::kPlanner, message_);
}

void ControlLoop::mapAgreement() {
  if (plan_.map_agrees == map_agrees_) return;
  map_agrees_ = plan_.map_agrees;
  if (!map_agrees_)
    std::snprintf(message_, sizeof(message_),
                  "terrain: the map is %.3f m off where the stance feet stand (%s %.3f m and a "
                  "cell): planning on the plane they stood on until it agrees",
                  plan_.map_disagreement,
                  settingName(*settings_, &settings_->map_tolerance, "tolerance"),
                  settings_->map_tolerance);
  else
    std::snprintf(message_, sizeof(message_),
                  "terrain: the map agrees with the stance feet again (%.3f m): planning on it",
                  plan_.map_disagreement);
  event(!map_agrees_, message_);
}

double ControlLoop::planLead() const {
  // Lockstep: exactly the latency the pipeline gives. Real time: how long solves take now,
  // within one planner period.
  if (options_.lockstep) return settings_->planner_latency;
  return std::min(solve_time_, 1.0 / settings_->planner_rate);
}

double ControlLoop::secondsSince(std::uint64_t start_ns) const {
  return static_cast<double>(clock_() - start_ns) * 1e-9;
}

void ControlLoop::readSensors() {
  const backend::Status st = backend_.read(sensors_);
  sensors_ok_ = false;
  if (st != backend::Status::kOk) {
    backendStatus(st, "read");
    return;
  }
  if (ticks_ > 0 && sensors_.sequence == last_sequence_) {
    std::snprintf(message_, sizeof(message_),
                  "backend read(): sensor sequence %llu repeated: the data did not change",
                  static_cast<unsigned long long>(sensors_.sequence));
    raise(FaultKind::kBackendStale, message_);
    return;
  }
  last_sequence_ = sensors_.sequence;
  if (!std::isfinite(sensors_.time)) {
    raise(FaultKind::kNotANumber, "backend read(): the time is not a number");
    return;
  }
  for (int j = 0; j < nj_; ++j) {
    const int b = backend_index_[j];
    q_[j] = sensors_.q[b];
    dq_[j] = sensors_.dq[b];
    tau_[j] = sensors_.tau[b];
    if (!std::isfinite(q_[j]) || !std::isfinite(dq_[j]) || !std::isfinite(tau_[j])) {
      std::snprintf(message_, sizeof(message_),
                    "backend read(): joint %s: position, velocity or torque is not a number",
                    joint_names_[j].c_str());
      raise(FaultKind::kNotANumber, message_);
      return;
    }
  }
  const backend::Imu& imu = sensors_.imu;
  if (sensors_.imu_valid && !(finite3(imu.angular_velocity) && finite3(imu.linear_acceleration) &&
                              finite3(imu.orientation) && std::isfinite(imu.orientation[3]))) {
    raise(FaultKind::kNotANumber, "backend read(): the IMU reading is not a number");
    return;
  }
  t_ = sensors_.time;
  // The contact schedule of the plan in force (standing: every point) and the terrain heights
  // its contact points stand on (from the planner's map; before a plan, the ground height).
  scheduled_.fill(true);
  std::array<double, kNumContacts> terrain;
  terrain.fill(settings_->ground_height);
  if (have_plan_) {
    const gait::ContactFlags flags = plan_.plan.schedule.flagsAt(t_);
    for (int c = 0; c < kNumContacts; ++c) {
      scheduled_[c] = flags[c];
      terrain[c] = plan_.plan.supportHeight[c];
    }
  }
  const std::uint64_t estimator_start = clock_();
  sensors_ok_ = estimator_.update(sensors_, q_, dq_, tau_, scheduled_, terrain, input_.state);
  tick_profile_.estimator = secondsSince(estimator_start);
  profile_.estimator += tick_profile_.estimator;
  // A localisation fix bounds the drift of leg odometry (the next update shows it).
  if (sensors_ok_ && sensors_.position_fix.fresh && settings_->use_position_fix &&
      backend_.capabilities().position_fix && estimator_.correctPosition(sensors_.position_fix))
    ++position_fixes_;
}

void ControlLoop::handOffScan() {
  const MappingSettings& ms = mapper_->settings();
  // Lockstep: the map of the pending scan is waited for (the planner's way there) when it is
  // due, or before the next scan goes (one in flight at a time).
  auto takePending = [&] {
    mapper_->waitFor(scan_pending_);
    planner_input_.map_scan = scan_pending_;
    scan_pending_ = 0;
  };
  if (options_.lockstep && scan_pending_ != 0 && t_ + PlannerSlot::kTimeTolerance >= scan_due_)
    takePending();
  backend::PointCloudView view;
  if (!sensors_ok_ || !backend_.lidarScan(view)) return;
  if (t_ + PlannerSlot::kTimeTolerance < next_scan_) return;  // mapping.rate
  next_scan_ = t_ + 0.75 / ms.rate;
  if (options_.lockstep && scan_pending_ != 0) takePending();
  LidarScan& scan = mapper_->back();
  scan.index = ++scans_handed_;
  scan.t = t_;
  scan.handoff_ns = monotonicNs();
  scan.truncated = view.count > LidarScan::kMaxPoints;
  scan.count = view.xyz ? std::min(std::max(view.count, 0), LidarScan::kMaxPoints) : 0;
  std::memcpy(scan.xyz.data(), view.xyz, sizeof(float) * 3 * static_cast<std::size_t>(scan.count));
  scan.sensor_frame = view.frame == backend::ScanFrame::kSensor;
  std::memcpy(scan.sensor_link, view.sensor_link, sizeof(scan.sensor_link));
  scan.sensor_link[sizeof(scan.sensor_link) - 1] = '\0';
  for (int k = 0; k < 3; ++k) {
    scan.origin[k] = view.sensor_origin[k];
    scan.sensor_offset[k] = view.sensor_offset[k];
    scan.sensor_rpy[k] = view.sensor_rpy[k];
  }
  scan.state = input_.state;
  mapper_->handOff();
  if (options_.lockstep) {
    scan_pending_ = scan.index;
    scan_due_ = t_ + ms.latency;
  }
}

void ControlLoop::handleCommands() {
  OperatorCommand c;
  while (num_tick_replies_ < kCommandsPerTick && commands_.tryPop(c)) {
    CommandReply& reply = tick_replies_[num_tick_replies_++];
    reply = CommandReply{};
    reply.sequence = c.sequence;
    last_command_ = c.sequence;
    if (shutting_down_) {
      reply.refusal = Refusal::kRefused;
      copyText(reply.message, "ballastd is shutting down");
    } else if (c.kind == CommandKind::kSwitchSettings) {
      if (c.settings && *c.settings) {
        applySettings(*c.settings, reply);
      } else {
        reply.refusal = Refusal::kRefused;
        copyText(reply.message, "a settings switch without settings");
      }
    } else if (c.kind == CommandKind::kAdvance) {
      if (!options_.lockstep || !options_.hold) {
        reply.refusal = Refusal::kUnavailable;
        copyText(reply.message, "advance steps a held lockstep loop only: start ballastd --lockstep --hold");
      } else {
        run_until_ = std::max(run_until_, c.until);
      }
    } else if (c.kind == CommandKind::kPush) {
      const backend::Capabilities& caps = backend_.capabilities();
      const double f =
          std::sqrt(c.push.force[0] * c.push.force[0] + c.push.force[1] * c.push.force[1] +
                    c.push.force[2] * c.push.force[2]);
      backend::Error err;
      if (!caps.disturbance) {
        reply.refusal = Refusal::kUnavailable;
        std::snprintf(reply.message, sizeof(reply.message),
                      "backend '%s' takes no external pushes (simulation only)", caps.name);
      } else if (f > settings_->max_push_force || c.push.duration > settings_->max_push_duration) {
        reply.refusal = Refusal::kOutOfRange;
        std::snprintf(reply.message, sizeof(reply.message),
                      "push of %.1f N for %.2f s is beyond %s %.1f N or %s %.2f s", f,
                      c.push.duration,
                      settingName(*settings_, &settings_->max_push_force, "the force limit"),
                      settings_->max_push_force,
                      settingName(*settings_, &settings_->max_push_duration, "the duration limit"),
                      settings_->max_push_duration);
      } else if (!backend_.push(c.push, err)) {
        reply.refusal = Refusal::kBackend;
        copyText(reply.message, err.message);
      }
    } else {
      Situation s;
      s.fallen = fallen_;
      s.planner_available = planner_.available();
      s.push_available = backend_.capabilities().disturbance;
      reply.refusal = modes_.handle(c, t_, s, reply.message);
    }
    reply.mode = modes_.mode();
  }
}

void ControlLoop::sendReplies() {
  for (int i = 0; i < num_tick_replies_; ++i) replies_.tryPush(tick_replies_[i]);
  if (num_tick_replies_ > 0) notifyIo();
  num_tick_replies_ = 0;
}

void ControlLoop::applySettings(const SettingsPtr& next, CommandReply& reply) {
  // Gains blend from what is in force now to the new ones over gain_blend_time.
  blend_kp_ = kp_;
  blend_kd_ = kd_;
  blend_start_ = t_;
  settings_ = next;  // the IO side still holds the old ones: the loop frees nothing
  if (!estimator_.setSettings(*next))
    event(true, "estimator: the new profile's frames differ; the estimator keeps the old ones");
  stand_.setSettings(*next);
  if (!walking_.setSettings(*next))
    event(true, "whole-body controller: the new profile's contact frames differ; it keeps the old "
                "settings");
  modes_.configure(*next, stand_.nominalHeight());
  ++settings_generation_;
  std::snprintf(reply.message, sizeof(reply.message), "gains blend over %.2f s",
                next->gain_blend_time);
}

void ControlLoop::detectFall() {
  if (!sensors_ok_) return;
  const ControlSettings& s = *settings_;
  // In simulation the truth decides (a fall is a fact of the world, not of the estimate); on
  // hardware the estimate.
  const BaseState& b = input_.state.base;
  const model::Mat3<double> R = model::quaternionToRotation<double>(
      sensors_.has_truth ? sensors_.truth.base_orientation : b.orientation);
  const double tilt = std::acos(std::clamp(R(2, 2), -1.0, 1.0));
  double height = b.position[2] - s.ground_height;
  if (sensors_.has_truth) height = sensors_.truth.base_position[2] - s.ground_height;
  const bool nonFoot = sensors_.has_truth && sensors_.truth.non_foot_contact;
  fallen_ =
      tilt > s.max_tilt || height < s.min_base_height || (nonFoot && s.fall_on_non_foot_contact);
  const Mode m = modes_.mode();
  if (!fallen_ || !(m == Mode::kStandUp || plannedMode(m))) return;
  if (tilt > s.max_tilt)
    std::snprintf(message_, sizeof(message_), "base tilted %.2f rad (%s %.2f)", tilt,
                  settingName(s, &s.max_tilt, "limit"), s.max_tilt);
  else if (height < s.min_base_height)
    std::snprintf(message_, sizeof(message_),
                  "base height %.3f m (%s %.3f)", height,
                  settingName(s, &s.min_base_height, "limit"), s.min_base_height);
  else
    std::snprintf(message_, sizeof(message_),
                  "a body other than the feet touches the ground");
  raise(FaultKind::kFall, message_);
}

void ControlLoop::computeCommands() {
  const ControlSettings& s = *settings_;
  // Gains in force: the new settings', blended in after a switch.
  double w = 1.0;
  if (blend_start_ >= 0.0) {
    w = s.gain_blend_time > 0.0 ? std::clamp((t_ - blend_start_) / s.gain_blend_time, 0.0, 1.0)
                                : 1.0;
    if (w >= 1.0) blend_start_ = -1.0;
  }
  for (int j = 0; j < nj_; ++j) {
    kp_[j] = w >= 1.0 ? s.kp[j] : blend_kp_[j] + w * (s.kp[j] - blend_kp_[j]);
    kd_[j] = w >= 1.0 ? s.kd[j] : blend_kd_[j] + w * (s.kd[j] - blend_kd_[j]);
  }

  const Mode mode = last_mode_;
  const double* q = sensors_ok_ ? q_ : input_.state.q;
  if (!started_ || mode == Mode::kPassive) {
    passiveOutput(nj_, q, output_);
    return;
  }
  if (mode == Mode::kDamp || !sensors_ok_) {
    dampOutput(nj_, q, s.damping, output_);
    return;
  }
  input_.mode = mode;
  input_.t = t_;
  input_.stand_up_progress = modes_.standUpProgress(t_);
  input_.command = modes_.command();
  input_.plan = have_plan_ ? &plan_ : nullptr;
  if (plannedMode(mode) && walking_.ready(input_.plan)) {
    const wbc::WbcStatus status = walking_.compute(input_, output_);
    if (status == wbc::WbcStatus::kInvalidInput) {
      raise(FaultKind::kNotANumber,
            "whole-body controller: the state or the plan is not a number; damping instead");
      dampOutput(nj_, q, s.damping, output_);
    } else if (status == wbc::WbcStatus::kDegraded) {
      ++wbc_degraded_;
    }
    return;
  }
  // stand-up, and stand before the first plan: the standing controller.
  stand_.compute(input_, kp_.data(), kd_.data(), period_, output_);
}

void ControlLoop::guardCommands() {
  for (int j = 0; j < nj_; ++j) {
    const backend::JointCommand& c = output_.joint[j];
    if (std::isfinite(c.tau_ff) && std::isfinite(c.q_des) && std::isfinite(c.dq_des) &&
        std::isfinite(c.kp) && std::isfinite(c.kd))
      continue;
    std::snprintf(message_, sizeof(message_),
                  "controller: the command for joint %s is not a number; damping instead",
                  joint_names_[j].c_str());
    raise(FaultKind::kNotANumber, message_);
    dampOutput(nj_, input_.state.q, settings_->damping, output_);
    return;
  }
}

void ControlLoop::writeCommands() {
  commands_out_.time = t_;
  for (int j = 0; j < nj_; ++j) commands_out_.joint[backend_index_[j]] = output_.joint[j];
  backendStatus(backend_.write(commands_out_), "write");
  // The motors hold the last command between writes: how long they went without one, on the
  // backend's clock (the wall for hardware; a simulation's world, which waits while the
  // simulator computes), is what matters in real time; a late tick that still writes in time
  // is not a fault.
  if (!options_.lockstep && have_written_) {
    const double gap = t_ - last_write_time_;
    if (gap > settings_->max_command_gap) {
      std::snprintf(message_, sizeof(message_),
                    "the motors went %.1f ms without a command (%s %.1f ms): the control thread "
                    "stalled",
                    gap * 1e3, settingName(*settings_, &settings_->max_command_gap, "limit"),
                    settings_->max_command_gap * 1e3);
      raise(FaultKind::kCommandGap, message_);
    }
  }
  last_write_time_ = t_;
  have_written_ = true;
}

void ControlLoop::publish() {
  LoopStatus& p = published_;
  p.t = t_;
  p.ticks = ticks_;
  p.mode = shutting_down_ ? Mode::kDamp : modes_.mode();
  p.estop = modes_.estopLatched();
  p.fallen = fallen_;
  p.lockstep = options_.lockstep;
  p.held = options_.lockstep && options_.hold;
  p.run_until = run_until_;
  p.planner_available = planner_.available();
  p.stand_up_progress = modes_.standUpProgress(t_);
  p.base = input_.state.base;
  p.has_truth = sensors_.has_truth;
  p.truth = truth_;
  p.truth_non_foot_contact = sensors_.has_truth && sensors_.truth.non_foot_contact;
  p.command = modes_.command();
  for (int c = 0; c < kNumContacts; ++c) p.contacts[c] = input_.state.contact[c];
  for (int i = 0; i < 3; ++i) p.external_force[i] = input_.state.external_force[i];
  p.mpc_ms = have_plan_ ? plan_.solve_ms : 0.0;
  p.map_agrees = map_agrees_;
  p.map_disagreement = have_plan_ ? plan_.map_disagreement : kNaN;
  p.planner_failures = planner_failures_;
  p.position_fixes = position_fixes_;
  p.wbc_degraded_ticks = wbc_degraded_;
  p.wbc_ms = wbc_ms_;
  p.wbc_ms_max = wbc_ms_max_;
  p.timing = timing_stats_.summary();
  p.profile = profile_;
  p.tick_overruns = p.timing.late_ticks;
  p.faults = modes_.faults();
  p.telemetry_frames = recorded_;
  p.telemetry_dropped = dropped_;
  p.settings_generation = settings_generation_;
  p.last_command = last_command_;
  p.num_joints = nj_;
  for (int j = 0; j < nj_; ++j) {
    p.q[j] = input_.state.q[j];
    p.tau[j] = output_.joint[j].tau_ff;
  }
  status_.store(p);
}

void ControlLoop::updateTruth() {
  if (!sensors_.has_truth) return;
  baseStateFromTruth(sensors_.truth, truth_);
}

void ControlLoop::record() {
  const std::uint32_t id = writer_ ? writer_->activeRecording() : 0;
  if (id == 0 || ticks_ % static_cast<std::uint64_t>(settings_->telemetry_decimation) != 0) return;
  TelemetryFrame& f = frame_;
  f.recording = id;
  f.t = t_;
  f.mode = last_mode_;
  f.base = input_.state.base;
  f.has_truth = sensors_.has_truth;
  f.truth = truth_;
  f.command = modes_.command();
  for (int c = 0; c < kNumContacts; ++c) {
    f.contact[c] = input_.state.contact[c];
    f.planned_contact[c] = scheduled_[c];
  }
  for (int i = 0; i < kNumPriorityLevels; ++i) f.task_error[i] = output_.task_error[i];
  std::memcpy(f.contact_force, output_.contact_force, sizeof f.contact_force);
  std::memcpy(f.contact_ref, output_.contact_ref, sizeof f.contact_ref);
  std::memcpy(f.contact_position, output_.contact_position, sizeof f.contact_position);
  f.mpc_ms = have_plan_ ? plan_.solve_ms : 0.0;
  f.wbc_ms = wbc_ms_;
  f.tick_ms = secondsSince(tick_start_) * 1e3;
  f.lateness_ms = timing_.lateness * 1e3;  // the previous advance(): how late this tick began
  f.num_joints = nj_;
  for (int j = 0; j < nj_; ++j) {
    f.q[j] = input_.state.q[j];
    f.dq[j] = input_.state.dq[j];
    f.tau[j] = input_.state.tau[j];
    f.q_ref[j] = output_.q_ref[j];
    f.tau_ff[j] = output_.joint[j].tau_ff;
  }
  if (telemetry_.tryPush(f)) {
    ++recorded_;
    return;
  }
  if (options_.lockstep) {
    // Simulated time waits for the writer; a writer gone for 0.2 s of wall time loses frames.
    const std::uint64_t start = monotonicNs();
    while (static_cast<double>(monotonicNs() - start) * 1e-9 < 0.2) {
      std::this_thread::yield();
      if (telemetry_.tryPush(f)) {
        ++recorded_;
        return;
      }
    }
  }
  ++dropped_;
}

}  // namespace ballast::control
