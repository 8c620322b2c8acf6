// What every simulation backend does with the ABI's per-tick calls, whatever its simulator:
//   read()    hands out the last sensor sample (kStale when nothing new since the last read);
//   write()   validates the commands (joint count, finite values, gains >= 0) and queues them
//             motor_latency_ticks deep; bad commands are kFault and ignored;
//   advance() applies the commands due, steps the world to the end of this period (through the
//             periods a stall skipped, the motors holding their last command), advances the
//             lidar and samples the sensors; in real time it then paces to absolute deadlines
//             (tick_pacer.hpp), after the host delays tests inject (host_delays.hpp), and the
//             simulator's own computing beyond half a period pauses the schedule (the world
//             waits) instead of making the controller look late. So does the host not running
//             the control thread although it was ready (a wake-up late by more than half a
//             period, preemption within a tick that never blocked: TickTiming::host_stall): the
//             simulator runs on that host and stops with it, and a desktop or a virtual machine
//             without PREEMPT_RT stalls tens of ms a minute, which no robot's computer does. The
//             controller's own lateness (its computing, its blocking) and the injected delays
//             (as long as asked; a late wake-up from them is the host's) pass in the world as
//             on a robot: the motors hold their command through them;
//   stop()    turns the motors off.
//   configure(), start(), push() and lidarScan() are the same for every simulator too.
// A backend derives from SimulationBackend<Derived, World> and provides:
//   makeWorld(config)  (Config::period and urdf_path already checked) parses its own section of
//                      the profile into settings_ (the keys every simulator shares:
//                      settings_schema.hpp) and builds world_; throws with a message naming the
//                      key on bad input;
//   settings()         those settings;  configuredMessage()  what configure() reports on success;
//   sampleSensors()    fills sample_;   scanLidar()          advances lidar_ on the world.
// World provides numJoints(), jointNames(), reset(), setMotorCommands(const JointCommand*),
// stepTo(seconds), time() and push(link, const double force[3], duration, message). Nothing
// here allocates after configure().
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "backend_abi.hpp"
#include "host_delays.hpp"
#include "rolling_lidar.hpp"
#include "sensor_model.hpp"
#include "tick_pacer.hpp"

namespace ballast::plugin {

template <typename Derived, typename World>
class SimulationBackend : public backend::Backend {
 public:
  const backend::Capabilities& capabilities() const override { return caps_; }
  const backend::Error& lastError() const override { return lastError_; }

  bool configure(const backend::Config& config, backend::Error& error) override {
    started_ = faulted_ = false;
    world_.reset();
    Derived& self = static_cast<Derived&>(*this);
    try {
      if (!(config.period > 0.0 && config.period <= 0.1))
        throw std::runtime_error("Config::period " + std::to_string(config.period) +
                                 " s: the control period must be in (0, 0.1] s");
      if (!config.urdf_path || !*config.urdf_path)
        throw std::runtime_error("Config::urdf_path is empty: the simulation needs the robot's URDF");
      self.makeWorld(config);
      const auto& settings = self.settings();
      period_ = config.period;
      lockstep_ = config.lockstep;
      caps_ = backend::Capabilities{};
      std::snprintf(caps_.name, sizeof caps_.name, "%s", simulator_);
      caps_.simulation = true;
      caps_.lockstep = true;
      caps_.ground_truth = true;
      caps_.lidar = lidarEnabled_ = settings.lidar_enabled;
      caps_.disturbance = true;
      caps_.position_fix = settings.position_fix_rate > 0.0;
      caps_.num_joints = world_->numJoints();
      for (int j = 0; j < caps_.num_joints; ++j)
        std::snprintf(caps_.joint_names[j], backend::kNameLength, "%s",
                      world_->jointNames()[static_cast<std::size_t>(j)].c_str());
      sensors_.configure(sensorNoise(settings), period_, config.seed);
      if (lidarEnabled_) lidar_.configure(lidarSettings(settings), config.seed);
      host_.configure(settings.host_stall_at, settings.host_stall, settings.host_jitter_from,
                      settings.host_jitter_fraction, settings.host_jitter, config.seed);
      configureCommands(settings.motor_latency_ticks);
      copyMessage(error, self.configuredMessage().c_str());
    } catch (const std::exception& e) {
      world_.reset();
      copyMessage(error, e.what());
      return false;
    } catch (...) {  // nothing may cross the plugin boundary
      world_.reset();
      std::snprintf(message_, sizeof message_, "%s: configure failed with an unknown exception",
                    simulator_);
      copyMessage(error, message_);
      return false;
    }
    return true;
  }

  bool start(backend::Error& error) override {
    if (!world_) {
      std::snprintf(message_, sizeof message_, "%s: start() before a successful configure()",
                    simulator_);
      copyMessage(error, message_);
      return false;
    }
    try {
      world_->reset();
    } catch (const std::exception& e) {
      copyMessage(error, e.what());
      return false;
    } catch (...) {
      std::snprintf(message_, sizeof message_, "%s: start failed with an unknown exception",
                    simulator_);
      copyMessage(error, message_);
      return false;
    }
    restartTicks();
    sensors_.start();
    if (lidarEnabled_) lidar_.start(0.0);
    static_cast<Derived&>(*this).sampleSensors();
    started_ = true;
    faulted_ = false;
    copyMessage(lastError_, "");
    copyMessage(error, "");
    return true;
  }

  bool push(const backend::Push& push, backend::Error& error) override {
    if (!started_ || faulted_) {
      std::snprintf(message_, sizeof message_, "%s: push() needs a started, healthy simulation",
                    simulator_);
      copyMessage(error, message_);
      return false;
    }
    try {
      const std::string body(push.body, strnlen(push.body, sizeof push.body));
      std::string message;
      if (!world_->push(body, push.force, push.duration, message)) {
        copyMessage(error, (std::string(simulator_) + ": " + message).c_str());
        return false;
      }
    } catch (...) {
      std::snprintf(message_, sizeof message_, "%s: push failed with an unknown exception",
                    simulator_);
      copyMessage(error, message_);
      return false;
    }
    copyMessage(error, "");
    return true;
  }

  bool lidarScan(backend::PointCloudView& scan) override {
    return started_ && lidarEnabled_ && lidar_.take(scan);
  }

  backend::Status read(backend::Sensors& sensors) override {
    if (!started_) return notStarted("read");
    if (faulted_) return backend::Status::kFault;
    sensors = sample_;
    if (sample_.sequence == lastReadSequence_) return backend::Status::kStale;
    lastReadSequence_ = sample_.sequence;
    return backend::Status::kOk;
  }

  backend::Status write(const backend::Commands& commands) override {
    if (!started_) return notStarted("write");
    if (faulted_) return backend::Status::kFault;
    const int n = world_->numJoints();
    if (commands.num_joints != n) {
      std::snprintf(message_, sizeof message_, "%s: commands for %d joints, the robot has %d; ignored",
                    simulator_, commands.num_joints, n);
      return refuse(message_);
    }
    for (int j = 0; j < n; ++j) {
      const backend::JointCommand& c = commands.joint[j];
      const char* bad = !std::isfinite(c.tau_ff)   ? "tau_ff is not finite"
                        : !std::isfinite(c.q_des)  ? "q_des is not finite"
                        : !std::isfinite(c.dq_des) ? "dq_des is not finite"
                        : !(c.kp >= 0.0 && std::isfinite(c.kp)) ? "kp is negative or not finite"
                        : !(c.kd >= 0.0 && std::isfinite(c.kd)) ? "kd is negative or not finite"
                                                                : nullptr;
      if (bad) {
        std::snprintf(message_, sizeof message_, "%s: joint %d (%s): %s; commands ignored",
                      simulator_, j, caps_.joint_names[j], bad);
        return refuse(message_);
      }
    }
    QueuedCommands& slot = queue_[tick_ % queue_.size()];
    slot.tick = static_cast<std::int64_t>(tick_);
    std::copy(commands.joint, commands.joint + n, slot.joint);
    return backend::Status::kOk;
  }

  backend::Status advance(backend::TickTiming& timing) override {
    timing = backend::TickTiming{};
    const timespec begin = monotonicNow();
    const ThreadRun runAtAdvance = lockstep_ ? ThreadRun{} : threadRun();
    if (!started_) return notStarted("advance");
    if (faulted_) return backend::Status::kFault;
    if (!lockstep_ && tick_ == 0) pacer_.start(period_);  // the schedule starts with the first tick
    const std::int64_t due = static_cast<std::int64_t>(tick_) - motorLatencyTicks_;
    const QueuedCommands& slot = queue_[static_cast<std::size_t>(due >= 0 ? due : 0) % queue_.size()];
    if (due >= 0 && slot.tick == due) world_->setMotorCommands(slot.joint);
    Derived& self = static_cast<Derived&>(*this);
    try {
      // After a stall (real time) the world has gone on meanwhile: it steps through the skipped
      // periods with the motors holding their last command.
      world_->stepTo(static_cast<double>(tick_ + 1) * period_);
      ++tick_;
      if (lidarEnabled_) self.scanLidar();
      self.sampleSensors();
    } catch (const std::exception& e) {
      faulted_ = true;
      return refuse(e.what());
    } catch (...) {
      faulted_ = true;
      std::snprintf(message_, sizeof message_, "%s: the simulation failed with an unknown exception",
                    simulator_);
      return refuse(message_);
    }
    if (lockstep_) return backend::Status::kOk;
    // The world's own computing beyond half a period does not exist for the robot: the world
    // waits (the schedule moves on) rather than the controller looking late. CPU time, so that
    // a host stall within the step is not counted twice.
    pacer_.pause(threadRun().cpu - runAtAdvance.cpu - kSimulationShare * period_);
    const InjectedDelay injected = host_.delay(world_->time());
    const timespec worked = monotonicNow();
    const ThreadRun run = threadRun();
    const double work = secondsBetween(begin, worked);
    // The host's share of this tick's work: its wall time beyond its CPU time, unless the
    // thread blocked (then the time is the controller's). An injected delay is the
    // controller's as asked, and the host's beyond that (the sleep's wake-up came late).
    double hostStall = 0.0;
    const double lateFromDelay = injected.wall - injected.requested;
    if (lateFromDelay > kSimulationShare * period_) hostStall = lateFromDelay;
    if (tickBegan_.tv_sec != 0 &&
        run.voluntary_switches - injected.voluntary_switches == runAtTick_.voluntary_switches) {
      const double stolen =
          secondsBetween(tickBegan_, worked) - injected.wall - (run.cpu - runAtTick_.cpu);
      if (stolen > kSimulationShare * period_) hostStall += stolen;
    }
    pacer_.pause(hostStall);
    timing = pacer_.wait();
    // A wake-up that came late is the host's too.
    if (!timing.late && timing.lateness > kSimulationShare * period_) {
      pacer_.pause(timing.lateness);
      hostStall += timing.lateness;
    }
    timing.work = work;
    timing.host_stall = hostStall;
    tick_ += timing.skipped;
    tickBegan_ = monotonicNow();
    runAtTick_ = threadRun();
    return backend::Status::kOk;
  }
  using backend::Backend::advance;

  void stop() override {
    if (started_ && world_ && !faulted_) {
      backend::JointCommand off[backend::kMaxJoints] = {};
      world_->setMotorCommands(off);
    }
    started_ = false;
  }

  // Not part of the ABI: for tests and benchmarks that link the backend directly.
  World& world() { return *world_; }
  std::uint64_t lateTicks() const { return pacer_.lateTicks(); }
  std::uint64_t ticks() const { return tick_; }

 protected:
  /// Share of each real-time period the simulation may take before its world waits.
  static constexpr double kSimulationShare = 0.5;

  /// simulator: the name messages start with ("simbody").
  explicit SimulationBackend(const char* simulator) : simulator_(simulator) {}

  /// configure(): commands reach the motors this many ticks after they are written.
  void configureCommands(int motorLatencyTicks) {
    motorLatencyTicks_ = motorLatencyTicks;
    queue_.assign(static_cast<std::size_t>(motorLatencyTicks + 1), QueuedCommands{});
  }
  /// start(): no command in flight, tick 0, a new schedule, no sample read yet.
  void restartTicks() {
    for (QueuedCommands& q : queue_) q.tick = -1;
    tick_ = 0;
    pacer_ = TickPacer{};
    tickBegan_ = timespec{};
    sample_ = backend::Sensors{};
    lastReadSequence_ = 0;
  }
  /// lastError() says message; kFault.
  backend::Status refuse(const char* message) {
    copyMessage(lastError_, message);
    return backend::Status::kFault;
  }

  backend::Capabilities caps_;
  backend::Error lastError_;
  std::unique_ptr<World> world_;
  bool lidarEnabled_ = false;
  double period_ = 0.001;
  bool lockstep_ = true;
  bool started_ = false, faulted_ = false;
  std::uint64_t tick_ = 0;  ///< advances since start()
  backend::Sensors sample_;
  SensorModel sensors_;
  RollingLidar lidar_;
  HostDelays host_;

 private:
  backend::Status notStarted(const char* call) {
    std::snprintf(message_, sizeof message_, "%s: %s() on a backend that is not started",
                  simulator_, call);
    return refuse(message_);
  }

  // Commands in flight: slot k % size holds what was written during tick k.
  struct QueuedCommands {
    std::int64_t tick = -1;
    backend::JointCommand joint[backend::kMaxJoints];
  };

  const char* simulator_;
  char message_[256] = {};
  int motorLatencyTicks_ = 0;
  std::vector<QueuedCommands> queue_;
  std::uint64_t lastReadSequence_ = 0;
  TickPacer pacer_;
  timespec tickBegan_{};  ///< when the last pacing returned (0: no tick yet since start())
  ThreadRun runAtTick_;   ///< the control thread's CPU then
};

}  // namespace ballast::plugin
