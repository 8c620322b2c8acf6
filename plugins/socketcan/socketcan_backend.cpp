#include "socketcan_backend.hpp"

#include <linux/can/error.h>
#include <poll.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "format.hpp"       // plugins/common
#include "urdf_joints.hpp"  // plugins/common

namespace ballast::socketcan {

using backend::Status;
using plugin::monotonicNow;
using plugin::secondsBetween;

namespace {

std::string motorName(const MotorEntry& m) {
  return m.joint + " (" + m.bus + " id " + std::to_string(m.id) + ")";
}

/// The key a motor's setting was given at: its entry's, else the section-wide default's.
std::string keyOf(const SocketcanSettings& s, const MotorEntry& m, const char* entryKey,
                  const char* sectionKey) {
  const std::string key = "motors." + m.joint + "." + entryKey;
  return s.location.count(key) ? key : sectionKey;
}

/// A locked joint's motor can hold it: gains given, within the fields' spans, the angle within
/// the position field (else the packing would clamp them, holding somewhere else or softer).
void checkHold(const SocketcanSettings& s, const MotorEntry& m, double angle) {
  const std::string key = "motors." + m.joint;
  if (!(m.hold_kp > 0.0) || !(m.hold_kd > 0.0))
    throw SettingsError(s.where(key) + "joint " + m.joint + " is locked at " + formatNumber(angle) +
                        " rad (robot.locked_joints) and this motor holds it there: give it " +
                        (m.hold_kp > 0.0 ? "hold_kd" : m.hold_kd > 0.0 ? "hold_kp" : "hold_kp and hold_kd") +
                        " (or hold.kp and hold.kd for every locked joint's motor), or leave its "
                        "motor out of motors to leave it unpowered");
  if (m.hold_kp > m.ranges.kp)
    throw SettingsError(s.where(keyOf(s, m, "hold_kp", "hold.kp")) + formatNumber(m.hold_kp) +
                        " is beyond motor " + m.joint + "'s kp field (" +
                        formatNumber(m.ranges.kp) + ")");
  if (m.hold_kd > m.ranges.kd)
    throw SettingsError(s.where(keyOf(s, m, "hold_kd", "hold.kd")) + formatNumber(m.hold_kd) +
                        " is beyond motor " + m.joint + "'s kd field (" +
                        formatNumber(m.ranges.kd) + ")");
  const double p = m.direction * (angle - m.offset);
  if (std::abs(p) > m.ranges.position)
    throw SettingsError(s.where(key) + "joint " + m.joint + " is locked at " + formatNumber(angle) +
                        " rad, motor position " + formatNumber(p) + " rad, beyond its position field (±" +
                        formatNumber(m.ranges.position) + ")");
}

/// What a CAN error frame says, briefly.
const char* errorClass(const can_frame& f) {
  if (f.can_id & CAN_ERR_BUSOFF) return "bus-off";
  if (f.can_id & CAN_ERR_ACK) return "no acknowledgement (nothing listening?)";
  if (f.can_id & CAN_ERR_TX_TIMEOUT) return "transmit timeout";
  if (f.can_id & CAN_ERR_CRTL) return "controller error (error passive or warning)";
  return "error frame";
}

}  // namespace

Status SocketcanBackend::fault(const char* message) {
  copyMessage(lastError_, message);
  return Status::kFault;
}

bool SocketcanBackend::configure(const backend::Config& config, backend::Error& error) {
  return configure(config, error, true);
}

bool SocketcanBackend::check(const backend::Config& config, backend::Error& error) {
  SocketcanBackend b;
  return b.configure(config, error, false);
}

bool SocketcanBackend::configure(const backend::Config& config, backend::Error& error,
                                 bool openBuses) {
  try {
    settings_ = parseSocketcanSettings(config.section_yaml ? config.section_yaml : "",
                                       config.section_origin ? config.section_origin : "");
    period_ = config.period;
    checkBusLoad(settings_, period_);
    const std::vector<plugin::UrdfJoint> joints =
        plugin::urdfJoints(config.urdf_path ? config.urdf_path : "");
    // The joints the model holds (the profile's locks, mimic joints, joints moving no inertia)
    // are commanded by nobody. One without a motor (a finger coupled to its leader, a sensor's
    // joint) needs nothing; one with a motor is held by it at its angle (hold_kp, hold_kd).
    std::vector<std::pair<std::string, double>> held;  // joint, locked angle
    for (int i = 0; i < config.num_joint_models; ++i)
      if (config.joints && config.joints[i].locked && config.joints[i].name)
        held.emplace_back(config.joints[i].name, config.joints[i].locked_position);
    auto heldAt = [&](const std::string& joint) {
      return std::find_if(held.begin(), held.end(), [&](const auto& h) { return h.first == joint; });
    };
    // A motor for every movable joint not held, in URDF order, then the held joints' motors; no
    // motor for anything else.
    motors_.clear();
    std::vector<Motor> holding;
    for (const plugin::UrdfJoint& j : joints) {
      if (!j.movable) continue;
      const auto it = std::find_if(settings_.motors.begin(), settings_.motors.end(),
                                   [&](const MotorEntry& m) { return m.joint == j.name; });
      const auto lock = heldAt(j.name);
      if (lock == held.end() && it == settings_.motors.end())
        throw SettingsError(settings_.where("motors") + "joint " + j.name + " of " +
                            config.urdf_path + " has no motor (give motors." + j.name +
                            ": {bus: ..., id: ..., torque: ...})");
      if (it == settings_.motors.end()) continue;
      Motor m;
      m.entry = *it;
      m.effort = j.effort > 0.0 ? j.effort : m.entry.ranges.torque;
      if (lock != held.end()) {
        checkHold(settings_, m.entry, lock->second);
        m.held = true;
        m.lockedAt = lock->second;
        holding.push_back(m);
      } else {
        motors_.push_back(m);
      }
    }
    commanded_ = motors_.size();
    motors_.insert(motors_.end(), holding.begin(), holding.end());
    for (const MotorEntry& m : settings_.motors)
      if (std::none_of(motors_.begin(), motors_.end(),
                       [&](const Motor& x) { return x.entry.joint == m.joint; }))
        throw SettingsError(settings_.where("motors." + m.joint) + std::string(config.urdf_path) +
                            " has no movable joint " + m.joint);
    if (static_cast<int>(commanded_) > backend::kMaxJoints)
      throw SettingsError(settings_.where("motors") + "more motors than the ABI's " +
                          std::to_string(backend::kMaxJoints) + " joints");

    if (!openBuses) {  // a check: the section and the URDF agree; the buses are not touched
      copyMessage(error, "");
      return true;
    }
    buses_.clear();
    buses_.resize(settings_.buses.size());
    bool allEmulated = true;
    for (std::size_t b = 0; b < buses_.size(); ++b) {
      std::string why;
      if (!buses_[b].open(settings_.buses[b], why)) throw SettingsError(settings_.where("buses") + why);
      allEmulated = allEmulated && buses_[b].emulated();
    }
    busState_.assign(buses_.size(), BusState{});
    byId_.assign(buses_.size(), {});
    for (auto& table : byId_) table.fill(-1);
    for (std::size_t i = 0; i < motors_.size(); ++i)
      byId_[motors_[i].entry.busIndex][motors_[i].entry.id] = static_cast<std::int16_t>(i);
    imu_.setBaseId(settings_.imu_id);

    lockstep_ = config.lockstep;
    if (lockstep_ && !allEmulated)
      throw SettingsError(settings_.where("buses") +
                          "lockstep needs emulated buses (fd:N): real motors cannot wait for it");
    caps_ = backend::Capabilities{};
    std::snprintf(caps_.name, sizeof caps_.name, "socketcan");
    caps_.simulation = false;
    caps_.lockstep = allEmulated;
    caps_.num_joints = static_cast<int>(commanded_);
    for (std::size_t j = 0; j < commanded_; ++j)
      std::snprintf(caps_.joint_names[j], backend::kNameLength, "%s", motors_[j].entry.joint.c_str());
  } catch (const std::exception& e) {
    buses_.clear();
    copyMessage(error, e.what());
    return false;
  }
  configured_ = true;
  copyMessage(error, "");
  return true;
}

double SocketcanBackend::clock() const {
  if (lockstep_) return static_cast<double>(tick_) * period_;
  return running_ ? secondsBetween(start_, monotonicNow()) : 0.0;
}

bool SocketcanBackend::send(int bus, const can_frame& frame) {
  BusState& b = busState_[static_cast<std::size_t>(bus)];
  if (buses_[static_cast<std::size_t>(bus)].send(frame)) {
    log_.record(bus, frame);  // what went on the wire (candump sees no frame that was not sent)
    return true;
  }
  ++sendFailures_;
  b.sendErrno = buses_[static_cast<std::size_t>(bus)].lastError();
  b.failedThisTick = true;
  return false;
}

bool SocketcanBackend::drain() {
  bool any = false;
  const double t = clock();
  can_frame f;
  for (std::size_t b = 0; b < buses_.size(); ++b) {
    while (buses_[b].receive(f)) {
      any = true;
      log_.record(static_cast<int>(b), f);
      if (f.can_id & CAN_ERR_FLAG) {
        busState_[b].error = errorClass(f);
        continue;
      }
      if (settings_.imu_enabled && static_cast<int>(b) == settings_.imuBusIndex) {
        bool completed = false;
        if (imu_.take(f, completed)) {
          if (completed) lastImu_ = t;
          continue;
        }
      }
      const int id = replyMotor(f, settings_.host_id);
      if (id < 0) continue;
      const int index = byId_[b][static_cast<std::size_t>(id)];
      if (index < 0) continue;  // a motor this profile does not drive
      Motor& m = motors_[static_cast<std::size_t>(index)];
      MitReply r;
      unpackReply(f, settings_.host_id, m.entry.ranges, r);
      m.q = m.entry.offset + m.entry.direction * r.position;
      m.dq = m.entry.direction * r.velocity;
      m.tau = m.entry.direction * r.torque;
      m.fault = settings_.fault_code ? r.fault : 0;
      m.lastReply = t;
      m.replied = true;
    }
  }
  return any;
}

template <typename Done>
bool SocketcanBackend::waitUntil(Done done, double timeout) {
  const timespec begin = monotonicNow();
  pollfd fds[kMaxBuses];
  const int n = static_cast<int>(buses_.size());
  for (int i = 0; i < n; ++i) fds[i] = pollfd{buses_[static_cast<std::size_t>(i)].fd(), POLLIN, 0};
  for (;;) {
    drain();
    if (done()) return true;
    const double left = timeout - secondsBetween(begin, monotonicNow());
    if (left <= 0.0) return false;
    poll(fds, static_cast<nfds_t>(n), std::max(1, static_cast<int>(left * 1e3)));
  }
}

template <typename Missing>
std::string SocketcanBackend::motorList(Missing missing) const {
  std::string list;
  int listed = 0, more = 0;
  for (const Motor& m : motors_) {
    if (!missing(m)) continue;
    if (listed < 6)
      list += (listed++ ? ", " : "") + motorName(m.entry) + (m.held ? " holding its locked joint" : "");
    else ++more;
  }
  if (more > 0) list += " and " + std::to_string(more) + " more";
  return list;
}

std::string SocketcanBackend::busTrouble() const {
  std::string what;
  for (std::size_t b = 0; b < buses_.size(); ++b) {
    const BusState& s = busState_[b];
    if (s.error) what += "; bus " + settings_.buses[b] + " reported " + s.error;
    if (s.sendErrno) what += "; sending on " + settings_.buses[b] + " failed: " + std::strerror(s.sendErrno);
  }
  return what;
}

void SocketcanBackend::sendToAll(MitSpecial which, bool onlySilent) {
  can_frame f;
  for (Motor& m : motors_) {
    if (onlySilent && m.replied) continue;
    packSpecial(m.entry.id, which, f);
    m.replied = false;
    send(m.entry.busIndex, f);
  }
}

bool SocketcanBackend::sequence(MitSpecial which, double timeout) {
  // Every motor must answer; the silent ones are asked again (a frame may have been lost or the
  // transmit queue full) until the time is up.
  auto allReplied = [this] {
    return std::all_of(motors_.begin(), motors_.end(), [](const Motor& m) { return m.replied; });
  };
  sendToAll(which, false);
  const timespec begin = monotonicNow();
  while (!waitUntil(allReplied, std::min(0.02, timeout))) {
    if (secondsBetween(begin, monotonicNow()) >= timeout) return false;
    sendToAll(which, true);
  }
  return true;
}

bool SocketcanBackend::start(backend::Error& error) {
  if (!configured_) {
    copyMessage(error, "socketcan: start() before a successful configure()");
    return false;
  }
  if (!settings_.log.empty()) {
    std::string why;
    if (!log_.open(settings_.log, settings_.buses, why)) {
      copyMessage(error, (settings_.where("log") + why).c_str());
      return false;
    }
  }
  tick_ = 0;
  running_ = false;
  lastImu_ = -1.0;
  for (BusState& b : busState_) b = BusState{};
  for (Motor& m : motors_) m.lastReply = -1.0, m.fault = 0;
  can_frame f;
  for (CanBus& bus : buses_)  // what was on the buses before is not about this run
    while (bus.receive(f)) {
    }
  auto silent = [](const Motor& m) { return !m.replied; };
  auto failWith = [&](const std::string& message) {
    copyMessage(error, message.c_str());
    sequence(MitSpecial::kDisable, 0.05);
    log_.close();
    return false;
  };
  if (!sequence(MitSpecial::kEnable, settings_.enable_timeout))
    return failWith("socketcan: no answer to the enable command within " +
                    formatNumber(settings_.enable_timeout) + " s from " +
                    motorList(silent) + ": check power, wiring, ids and bus bit rate" + busTrouble());
  if (std::any_of(motors_.begin(), motors_.end(), [](const Motor& m) { return m.fault != 0; }))
    return failWith("socketcan: motors report a fault code when enabled (the driver's; see its "
                    "manual): " + motorList([](const Motor& m) { return m.fault != 0; }) + busTrouble());
  if (settings_.zero_on_start && !sequence(MitSpecial::kZero, settings_.enable_timeout))
    return failWith("socketcan: no answer to the zero command from " + motorList(silent) + busTrouble());
  if (settings_.imu_enabled &&
      !waitUntil([this] { return lastImu_ >= 0.0; }, settings_.enable_timeout))
    return failWith("socketcan: no sample from the IMU (" +
                    settings_.buses[static_cast<std::size_t>(settings_.imuBusIndex)] + " ids " +
                    std::to_string(settings_.imu_id) + ".." + std::to_string(settings_.imu_id + 2) +
                    ") within " + formatNumber(settings_.enable_timeout) +
                    " s" + busTrouble());
  started_ = true;
  copyMessage(lastError_, "");
  copyMessage(error, "");
  return true;
}

void SocketcanBackend::beginRun() {
  // The run's clock starts at the first tick, not at start(): the daemon builds its planner and
  // loop in between, and an MIT motor answers only when it is commanded. The state the enable
  // sequence brought back is the first tick's.
  start_ = monotonicNow();
  pacer_.start(period_);
  running_ = true;
  for (Motor& m : motors_) {
    m.lastReply = 0.0;
    m.holdFrom = m.q;  // what the enable sequence read: the hold starts where the joint is
  }
  if (settings_.imu_enabled) lastImu_ = 0.0;
}

Status SocketcanBackend::read(backend::Sensors& s) {
  if (!started_) return fault("socketcan: read() on a backend that is not started");
  if (!running_) beginRun();
  drain();
  const double t = clock();
  char message[backend::kMessageLength];
  const double timeout = settings_.reply_timeout;
  auto late = [&](const Motor& m) { return t - m.lastReply > timeout; };
  // Faults are reported for as long as they last; the daemon damps at the first and keeps
  // writing (damping commands still go out).
  if (std::any_of(motors_.begin(), motors_.end(), late)) {
    std::snprintf(message, sizeof message,
                  "socketcan: no reply for more than %.1f ms (reply_timeout) from %s%s",
                  timeout * 1e3, motorList(late).c_str(), busTrouble().c_str());
    return fault(message);
  }
  if (const auto bad = std::find_if(motors_.begin(), motors_.end(),
                                    [](const Motor& m) { return m.fault != 0; });
      bad != motors_.end()) {
    std::snprintf(message, sizeof message,
                  "socketcan: motor %s (%s id %d) reports fault code %d (the driver's; see its "
                  "manual)%s%s",
                  bad->entry.joint.c_str(), bad->entry.bus.c_str(), bad->entry.id, bad->fault,
                  bad->held ? "; it holds the locked joint, and is damped now" : "",
                  busTrouble().c_str());
    return fault(message);
  }
  if (settings_.imu_enabled && t - lastImu_ > settings_.imu_timeout) {
    std::snprintf(message, sizeof message,
                  "socketcan: the IMU (%s id %d) sent no sample for more than %.1f ms (imu.timeout)%s",
                  settings_.buses[static_cast<std::size_t>(settings_.imuBusIndex)].c_str(),
                  settings_.imu_id, settings_.imu_timeout * 1e3, busTrouble().c_str());
    return fault(message);
  }
  // A tick without a new frame (the host was late reading, a frame was lost) reuses the last
  // replies: each is younger than reply_timeout, checked above.
  s.time = t;
  s.sequence = ++sequence_;
  s.num_joints = static_cast<int>(commanded_);
  for (std::size_t j = 0; j < commanded_; ++j) {
    s.q[j] = motors_[j].q;
    s.dq[j] = motors_[j].dq;
    s.tau[j] = motors_[j].tau;
  }
  s.imu_valid = settings_.imu_enabled;
  if (s.imu_valid) {
    const ImuSample& sample = imu_.latest();
    std::memcpy(s.imu.orientation, sample.orientation, sizeof s.imu.orientation);
    std::memcpy(s.imu.angular_velocity, sample.angular_velocity, sizeof s.imu.angular_velocity);
    std::memcpy(s.imu.linear_acceleration, sample.linear_acceleration,
                sizeof s.imu.linear_acceleration);
  }
  s.has_truth = false;
  s.position_fix.fresh = false;
  return Status::kOk;
}

Status SocketcanBackend::write(const backend::Commands& commands) {
  if (!started_) return fault("socketcan: write() on a backend that is not started");
  if (!running_) beginRun();
  if (commands.num_joints != static_cast<int>(commanded_)) {
    char message[160];
    std::snprintf(message, sizeof message, "socketcan: commands for %d joints, the robot has %zu",
                  commands.num_joints, commanded_);
    return fault(message);
  }
  can_frame f;
  imuSamplesAtWrite_ = imu_.samples();
  for (BusState& b : busState_) b.failedThisTick = false;
  const char* notFinite = nullptr;
  for (std::size_t j = 0; j < commanded_; ++j) {
    Motor& m = motors_[j];
    const backend::JointCommand& c = commands.joint[j];
    MitCommand mc;
    if (std::isfinite(c.tau_ff) && std::isfinite(c.q_des) && std::isfinite(c.dq_des) &&
        std::isfinite(c.kp) && std::isfinite(c.kd)) {
      mc.position = m.entry.direction * (c.q_des - m.entry.offset);
      mc.velocity = m.entry.direction * c.dq_des;
      // The joint's own limit (URDF effort) as well as the field's span.
      const double tau = std::clamp(c.tau_ff, -m.effort, m.effort);
      clamped_ += tau != c.tau_ff;
      mc.torque = m.entry.direction * tau;
      mc.kp = c.kp;
      mc.kd = c.kd;
    } else {
      notFinite = m.entry.joint.c_str();  // limp: nothing but zeros for this motor
    }
    clamped_ += static_cast<std::uint64_t>(packCommand(m.entry.id, mc, m.entry.ranges, f));
    m.replied = false;
    send(m.entry.busIndex, f);
  }
  // The locked joints' motors hold them whatever the commands say (socketcan_backend.hpp).
  const double ramp = settings_.hold_ramp > 0.0 ? std::min(1.0, clock() / settings_.hold_ramp) : 1.0;
  for (std::size_t j = commanded_; j < motors_.size(); ++j) {
    Motor& m = motors_[j];
    const double target = m.holdFrom + ramp * (m.lockedAt - m.holdFrom);
    MitCommand mc;
    mc.position = m.entry.direction * (target - m.entry.offset);
    mc.kp = m.fault != 0 ? 0.0 : m.entry.hold_kp;
    mc.kd = m.entry.hold_kd;
    clamped_ += static_cast<std::uint64_t>(packCommand(m.entry.id, mc, m.entry.ranges, f));
    m.replied = false;
    send(m.entry.busIndex, f);
  }
  // A bus that could not take a tick's frames for longer than reply_timeout is a fault (the
  // motors' silence will say so too, but this says why).
  for (std::size_t b = 0; b < buses_.size(); ++b) {
    BusState& s = busState_[b];
    s.failingTicks = s.failedThisTick ? s.failingTicks + 1 : 0;
    if (!s.failedThisTick) s.sendErrno = 0;
    if (s.failingTicks * period_ > settings_.reply_timeout) {
      char message[backend::kMessageLength];
      std::snprintf(message, sizeof message,
                    "socketcan: bus %s has refused frames for %d ticks: %s (is it up? `ip -details "
                    "link show %s`)",
                    settings_.buses[b].c_str(), s.failingTicks, std::strerror(s.sendErrno),
                    settings_.buses[b].c_str());
      return fault(message);
    }
  }
  if (notFinite) {
    char message[200];
    std::snprintf(message, sizeof message,
                  "socketcan: the command for joint %s is not finite; that motor got zeros", notFinite);
    return fault(message);
  }
  return Status::kOk;
}

Status SocketcanBackend::advance(backend::TickTiming& timing) {
  timing = backend::TickTiming{};
  if (!started_) return fault("socketcan: advance() on a backend that is not started");
  if (!running_) beginRun();
  if (lockstep_) {
    auto done = [this] {
      return std::all_of(motors_.begin(), motors_.end(), [](const Motor& m) { return m.replied; }) &&
             (!settings_.imu_enabled || imu_.samples() > imuSamplesAtWrite_);
    };
    if (!waitUntil(done, settings_.lockstep_timeout)) {
      char message[backend::kMessageLength];
      std::snprintf(message, sizeof message,
                    "socketcan: lockstep tick %llu: no reply within %.1f s (lockstep_timeout) from %s%s",
                    static_cast<unsigned long long>(tick_), settings_.lockstep_timeout,
                    motorList([](const Motor& m) { return !m.replied; }).c_str(),
                    settings_.imu_enabled && imu_.samples() == imuSamplesAtWrite_ ? " (and the IMU)" : "");
      return fault(message);
    }
    ++tick_;
    // What arrived for this tick is the next tick's data.
    for (Motor& m : motors_)
      if (m.replied) m.lastReply = clock();
    if (settings_.imu_enabled) lastImu_ = clock();
    return Status::kOk;
  }
  ++tick_;
  timing = pacer_.wait();
  return Status::kOk;
}

void SocketcanBackend::stop() {
  // The daemon has damped the motors for a while before it stops the backend; leaving motor
  // mode is the last step, asked again of any motor that does not answer.
  if (started_ && settings_.disable_on_stop) sequence(MitSpecial::kDisable, 0.1);
  started_ = false;
  running_ = false;
  log_.close();
}

}  // namespace ballast::socketcan
