#include "socketcan_backend.hpp"

#include <poll.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "urdf_joints.hpp"  // plugins/common

namespace ballast::socketcan {

using backend::Status;
using plugin::monotonicNow;
using plugin::secondsBetween;

namespace {

std::string motorName(const MotorEntry& m) {
  return m.joint + " (" + m.bus + " id " + std::to_string(m.id) + ")";
}

}  // namespace

Status SocketcanBackend::fault(const char* message) {
  copyMessage(lastError_, message);
  faulted_ = true;
  return Status::kFault;
}

bool SocketcanBackend::configure(const backend::Config& config, backend::Error& error) {
  try {
    settings_ = parseSocketcanSettings(config.section_yaml ? config.section_yaml : "",
                                       config.section_origin ? config.section_origin : "");
    period_ = config.period;
    const std::vector<plugin::UrdfJoint> joints =
        plugin::urdfJoints(config.urdf_path ? config.urdf_path : "");
    // A motor for every movable joint, in URDF order; no motor for anything else.
    motors_.clear();
    for (const plugin::UrdfJoint& j : joints) {
      if (!j.movable) continue;
      const auto it = std::find_if(settings_.motors.begin(), settings_.motors.end(),
                                   [&](const MotorEntry& m) { return m.joint == j.name; });
      if (it == settings_.motors.end())
        throw SettingsError(settings_.where("motors") + "joint " + j.name + " of " +
                            config.urdf_path + " has no motor (give motors." + j.name +
                            ": {bus: ..., id: ...})");
      Motor m;
      m.entry = *it;
      if (m.entry.torqueFromUrdf) {
        if (!(j.effort > 0.0))
          throw SettingsError(settings_.where("motors." + j.name) +
                              "the URDF gives no effort limit: give it a torque: range");
        m.entry.ranges.torque = j.effort;
      }
      motors_.push_back(m);
    }
    for (const MotorEntry& m : settings_.motors)
      if (std::none_of(motors_.begin(), motors_.end(),
                       [&](const Motor& x) { return x.entry.joint == m.joint; }))
        throw SettingsError(settings_.where("motors." + m.joint) + std::string(config.urdf_path) +
                            " has no movable joint " + m.joint);
    if (static_cast<int>(motors_.size()) > backend::kMaxJoints)
      throw SettingsError(settings_.where("motors") + "more motors than the ABI's " +
                          std::to_string(backend::kMaxJoints) + " joints");

    buses_.clear();
    buses_.resize(settings_.buses.size());
    bool allEmulated = true;
    for (std::size_t b = 0; b < buses_.size(); ++b) {
      std::string why;
      if (!buses_[b].open(settings_.buses[b], why)) throw SettingsError(settings_.where("buses") + why);
      allEmulated = allEmulated && buses_[b].emulated();
    }
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
    caps_.num_joints = static_cast<int>(motors_.size());
    for (std::size_t j = 0; j < motors_.size(); ++j)
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
  return lockstep_ ? static_cast<double>(tick_) * period_ : secondsBetween(start_, monotonicNow());
}

bool SocketcanBackend::send(int bus, const can_frame& frame) {
  log_.record(bus, frame);
  if (buses_[static_cast<std::size_t>(bus)].send(frame)) return true;
  ++sendFailures_;
  lastSendErrno_ = buses_[static_cast<std::size_t>(bus)].lastError();
  lastSendBus_ = bus;
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
      if (f.can_id & CAN_ERR_FLAG) continue;  // controller errors show up as silent motors
      const int id = replyMotor(f, settings_.host_id);
      if (id >= 0) {
        const int index = byId_[b][static_cast<std::size_t>(id)];
        if (index < 0) continue;  // a motor this profile does not drive
        Motor& m = motors_[static_cast<std::size_t>(index)];
        MitReply r;
        unpackReply(f, settings_.host_id, m.entry.ranges, r);
        m.q = m.entry.offset + m.entry.direction * r.position;
        m.dq = m.entry.direction * r.velocity;
        m.tau = m.entry.direction * r.torque;
        m.lastReply = t;
        m.replied = true;
        continue;
      }
      if (settings_.imu_enabled && static_cast<int>(b) == settings_.imuBusIndex) {
        bool completed = false;
        if (imu_.take(f, completed) && completed) lastImu_ = t;
      }
    }
  }
  return any;
}

template <typename Done>
bool SocketcanBackend::waitUntil(Done done, double timeout) {
  const timespec begin = monotonicNow();
  pollfd fds[16];
  const int n = static_cast<int>(std::min<std::size_t>(buses_.size(), 16));
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
    if (listed < 6) list += (listed++ ? ", " : "") + motorName(m.entry);
    else ++more;
  }
  if (more > 0) list += " and " + std::to_string(more) + " more";
  return list;
}

void SocketcanBackend::sendToAll(MitSpecial which) {
  can_frame f;
  for (Motor& m : motors_) {
    packSpecial(m.entry.id, which, f);
    m.replied = false;
    send(m.entry.busIndex, f);
  }
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
  start_ = monotonicNow();
  tick_ = 0;
  faulted_ = false;
  lastImu_ = -1.0;
  for (Motor& m : motors_) m.lastReply = -1.0;
  can_frame f;
  for (CanBus& bus : buses_)  // what was on the buses before is not about this run
    while (bus.receive(f)) {
    }
  auto allReplied = [this] {
    return std::all_of(motors_.begin(), motors_.end(), [](const Motor& m) { return m.replied; });
  };
  auto silent = [](const Motor& m) { return !m.replied; };
  sendToAll(MitSpecial::kEnable);
  if (!waitUntil(allReplied, settings_.enable_timeout)) {
    copyMessage(error, ("socketcan: no answer to the enable command within " +
                        plugin::SectionCursor::formatNumber(settings_.enable_timeout) + " s from " +
                        motorList(silent) + ": check power, wiring, ids and bus bit rate")
                           .c_str());
    sendToAll(MitSpecial::kDisable);
    log_.close();
    return false;
  }
  if (settings_.zero_on_start) {
    sendToAll(MitSpecial::kZero);
    if (!waitUntil(allReplied, settings_.enable_timeout)) {
      copyMessage(error, ("socketcan: no answer to the zero command from " + motorList(silent)).c_str());
      sendToAll(MitSpecial::kDisable);
      log_.close();
      return false;
    }
  }
  if (settings_.imu_enabled &&
      !waitUntil([this] { return lastImu_ >= 0.0; }, settings_.enable_timeout)) {
    copyMessage(error, ("socketcan: no sample from the IMU (" +
                        settings_.buses[static_cast<std::size_t>(settings_.imuBusIndex)] + " ids " +
                        std::to_string(settings_.imu_id) + ".." + std::to_string(settings_.imu_id + 2) +
                        ") within " + plugin::SectionCursor::formatNumber(settings_.enable_timeout) + " s")
                           .c_str());
    sendToAll(MitSpecial::kDisable);
    log_.close();
    return false;
  }
  // The replies and the IMU sample came at time 0 of the run.
  for (Motor& m : motors_) m.lastReply = 0.0;
  if (settings_.imu_enabled) lastImu_ = 0.0;
  start_ = monotonicNow();
  pacer_.start(period_);
  started_ = true;
  copyMessage(lastError_, "");
  copyMessage(error, "");
  return true;
}

Status SocketcanBackend::read(backend::Sensors& s) {
  if (!started_) return fault("socketcan: read() on a backend that is not started");
  if (faulted_) return Status::kFault;
  drain();
  const double t = clock();
  char message[backend::kMessageLength];
  const double timeout = settings_.reply_timeout;
  auto late = [&](const Motor& m) { return t - m.lastReply > timeout; };
  if (std::any_of(motors_.begin(), motors_.end(), late)) {
    std::snprintf(message, sizeof message,
                  "socketcan: no reply for more than %.1f ms (reply_timeout) from %s%s%s%s",
                  timeout * 1e3, motorList(late).c_str(),
                  lastSendErrno_ ? "; the last failed send on " : "",
                  lastSendErrno_ ? settings_.buses[static_cast<std::size_t>(lastSendBus_)].c_str() : "",
                  lastSendErrno_ ? (std::string(": ") + std::strerror(lastSendErrno_)).c_str() : "");
    return fault(message);
  }
  if (settings_.imu_enabled && t - lastImu_ > settings_.imu_timeout) {
    std::snprintf(message, sizeof message,
                  "socketcan: the IMU (%s id %d) sent no sample for more than %.1f ms (imu.timeout)",
                  settings_.buses[static_cast<std::size_t>(settings_.imuBusIndex)].c_str(),
                  settings_.imu_id, settings_.imu_timeout * 1e3);
    return fault(message);
  }
  // A tick without a new frame (the host was late reading, a frame was lost) reuses the last
  // replies: each is younger than reply_timeout, checked above.
  s.time = t;
  s.sequence = ++sequence_;
  s.num_joints = static_cast<int>(motors_.size());
  for (std::size_t j = 0; j < motors_.size(); ++j) {
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
  if (faulted_) return Status::kFault;
  if (commands.num_joints != static_cast<int>(motors_.size())) {
    char message[160];
    std::snprintf(message, sizeof message, "socketcan: commands for %d joints, the robot has %zu",
                  commands.num_joints, motors_.size());
    return fault(message);
  }
  can_frame f;
  imuSamplesAtWrite_ = imu_.samples();
  for (std::size_t j = 0; j < motors_.size(); ++j) {
    const backend::JointCommand& c = commands.joint[j];
    if (!std::isfinite(c.tau_ff) || !std::isfinite(c.q_des) || !std::isfinite(c.dq_des) ||
        !std::isfinite(c.kp) || !std::isfinite(c.kd)) {
      char message[200];
      std::snprintf(message, sizeof message,
                    "socketcan: the command for joint %s is not finite; nothing sent",
                    motors_[j].entry.joint.c_str());
      return fault(message);
    }
  }
  for (std::size_t j = 0; j < motors_.size(); ++j) {
    Motor& m = motors_[j];
    const backend::JointCommand& c = commands.joint[j];
    MitCommand mc;
    mc.position = m.entry.direction * (c.q_des - m.entry.offset);
    mc.velocity = m.entry.direction * c.dq_des;
    mc.torque = m.entry.direction * c.tau_ff;
    mc.kp = c.kp;
    mc.kd = c.kd;
    clamped_ += static_cast<std::uint64_t>(packCommand(m.entry.id, mc, m.entry.ranges, f));
    m.replied = false;
    send(m.entry.busIndex, f);
  }
  return Status::kOk;
}

Status SocketcanBackend::advance() {
  if (!started_) return fault("socketcan: advance() on a backend that is not started");
  if (faulted_) return Status::kFault;
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
  double late = 0.0;
  if (!pacer_.wait(late)) {
    char message[160];
    std::snprintf(message, sizeof message, "socketcan: tick %llu ended %.3f ms after its deadline",
                  static_cast<unsigned long long>(tick_), late * 1e3);
    copyMessage(lastError_, message);
    return Status::kOverrun;
  }
  return Status::kOk;
}

void SocketcanBackend::stop() {
  if (started_ && settings_.disable_on_stop) {
    sendToAll(MitSpecial::kDisable);
    waitUntil([this] {
      return std::all_of(motors_.begin(), motors_.end(), [](const Motor& m) { return m.replied; });
    }, 0.05);
  }
  started_ = false;
  log_.close();
}

}  // namespace ballast::socketcan
