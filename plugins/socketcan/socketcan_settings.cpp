#include "socketcan_settings.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <set>

namespace ballast::socketcan {
namespace {

constexpr double kUnset = std::numeric_limits<double>::quiet_NaN();

using S = SocketcanSettings;
using R = schema::Rule<SocketcanSettings>;
using namespace schema;  // the row declarations

// A motor entry's keys, and the ranges it may set (NaN until filled from ranges.*).
const std::vector<std::string> kMotorKeys = {"bus", "id", "position", "velocity", "torque",
                                             "kp", "kd", "direction", "offset", "hold_kp",
                                             "hold_kd"};

void parseMotors(S& s, const YAML::Node& node, const schema::Cursor& c) {
  s.motors.clear();
  if (node.IsNull()) return;
  if (!node.IsMap())
    c.fail(node.Mark(), "motors", "expected a map of URDF joint: {bus, id, ...}, got " +
                                      schema::describe(node));
  for (const auto& e : node) {
    const std::string joint = e.first.Scalar();
    const std::string key = "motors." + joint;
    const YAML::Node& m = e.second;
    if (!m.IsMap())
      c.fail(m.Mark(), key, "expected {bus: ..., id: ...}, got " + schema::describe(m));
    c.checkKeys(m, kMotorKeys, key);
    c.record(key, e.first.Mark());
    MotorEntry motor;
    motor.joint = joint;
    if (!m["bus"]) c.fail(e.first.Mark(), key, "needs bus: (one of buses)");
    if (!m["id"]) c.fail(e.first.Mark(), key, "needs id: (the motor's CAN id)");
    motor.bus = c.text(m["bus"], key + ".bus");
    c.record(key + ".bus", m["bus"].Mark());
    motor.id = static_cast<int>(c.integer(m["id"], 1, 255, key + ".id"));  // one byte in a reply
    c.record(key + ".id", m["id"].Mark());
    auto range = [&](const char* name, double lo, double hi) {
      if (!m[name]) return kUnset;
      c.record(key + "." + name, m[name].Mark());
      return c.number(m[name], lo, hi, key + "." + name);
    };
    motor.ranges.position = range("position", 0.1, 1000);
    motor.ranges.velocity = range("velocity", 0.1, 1000);
    motor.ranges.torque = range("torque", 0.1, 10000);
    motor.ranges.kp = range("kp", 0.1, 1e5);
    motor.ranges.kd = range("kd", 0.01, 1e4);
    if (m["direction"]) {
      const double d = c.number(m["direction"], -1, 1, key + ".direction");
      if (d != 1.0 && d != -1.0) c.fail(m["direction"].Mark(), key + ".direction", "must be 1 or -1");
      motor.direction = d;
    }
    if (m["offset"]) motor.offset = c.number(m["offset"], -1000, 1000, key + ".offset");
    motor.hold_kp = range("hold_kp", 0.1, 1e5);
    motor.hold_kd = range("hold_kd", 0.01, 1e4);
    s.motors.push_back(motor);
  }
}


int busIndex(const S& s, const std::string& bus) {
  for (std::size_t i = 0; i < s.buses.size(); ++i)
    if (s.buses[i] == bus) return static_cast<int>(i);
  return -1;
}

std::string busList(const S& s) {
  std::string list;
  for (const auto& b : s.buses) list += (list.empty() ? "" : ", ") + b;
  return list;
}

// Documentation groups.
constexpr const char* kBuses = "Buses";
constexpr const char* kImu = "IMU";
constexpr const char* kRanges = "Motor ranges (defaults of every motor's)";
constexpr const char* kMotors = "Motors";
constexpr const char* kHold = "Locked joints (held by their motors)";

// clang-format off
const Schema<SocketcanSettings> kSchema({
  strings("buses", "[can0]", "CAN interfaces (\"can0\"), or fd:N for an emulated bus (an open SOCK_SEQPACKET socket carrying struct can_frame); at most 16").inGroup(kBuses).into<&S::buses>(),
  number("bitrate", "1000000", 1e4, 1e6, "", "bits per second of every bus (classic CAN)").inGroup(kBuses).into<&S::bitrate>(),
  number("max_bus_load", "0.8", 0.1, 1, "", "largest share of a bus's time one tick's frames may take (configure refuses more; emulated buses have no limit)").inGroup(kBuses).into<&S::max_bus_load>(),
  integer("host_id", "0", 0, 2047, "", "CAN id the motors reply to").inGroup(kBuses).into<&S::host_id>(),
  number("reply_timeout", "0.003", 0.0005, 1, "", "a motor silent this long (s) is a fault (damp)").inGroup(kBuses).into<&S::reply_timeout>(),
  number("enable_timeout", "0.5", 0.01, 10, "", "start(): how long (s) every motor has to answer the enable command").inGroup(kBuses).into<&S::enable_timeout>(),
  number("lockstep_timeout", "2", 0.01, 60, "", "lockstep (emulated buses): wall time (s) a tick waits for every reply").inGroup(kBuses).into<&S::lockstep_timeout>(),
  flag("zero_on_start", "false", "start(): set every motor's present position as its zero (calibration pose only)").inGroup(kBuses).into<&S::zero_on_start>(),
  flag("disable_on_stop", "true", "stop(): take every motor out of motor mode").inGroup(kBuses).into<&S::disable_on_stop>(),
  text("log", "\"\"", "candump-format log of every frame sent and received (\"\": none)").inGroup(kBuses).into<&S::log>(),
  flag("imu.enabled", "true", "an IMU on the bus (imu_protocol.hpp); without it there is no estimate").inGroup(kImu).into<&S::imu_enabled>(),
  text("imu.bus", "\"\"", "its bus (\"\": the first)").inGroup(kImu).into<&S::imu_bus>(),
  integer("imu.id", "256", 1, 2045, "", "CAN id of its first frame (it uses id, id + 1, id + 2)").inGroup(kImu).into<&S::imu_id>(),
  number("imu.timeout", "0.005", 0.001, 1, "", "an IMU silent this long (s) is a fault (damp)").inGroup(kImu).into<&S::imu_timeout>(),
  number("ranges.position", "12.5", 0.1, 1000, "", "±rad the MIT position field spans").inGroup(kRanges).into<&S::ranges_position>(),
  number("ranges.velocity", "45", 0.1, 1000, "", "±rad/s of the velocity field").inGroup(kRanges).into<&S::ranges_velocity>(),
  number("ranges.torque", "0", 0, 10000, "", "±N·m of the torque field: the motor firmware's T_MAX (0: each motor must give its own)").inGroup(kRanges).into<&S::ranges_torque>(),
  number("ranges.kp", "500", 0.1, 1e5, "", "N·m/rad the kp field spans from 0").inGroup(kRanges).into<&S::ranges_kp>(),
  number("ranges.kd", "5", 0.01, 1e4, "", "N·m·s/rad the kd field spans from 0").inGroup(kRanges).into<&S::ranges_kd>(),
  flag("fault_code", "true", "an 8-byte reply's last byte is the motor driver's fault code, as drivers that append temperature and fault to the 6-byte reply send it: a code other than 0 is a fault naming the motor and the code (damp); 6-byte replies carry none").inGroup(kMotors).into<&S::fault_code>(),
  custom("motors", "{}", "URDF joint -> {bus, id, position, velocity, torque, kp, kd, direction (1 or -1), offset (rad), hold_kp, hold_kd}; every movable joint needs one, but a locked joint (robot.locked_joints) may have none").inGroup(kMotors).custom<S>(&parseMotors),
  number("hold.kp", "0", 0, 1e5, "", "N·m/rad: the motor of a joint in robot.locked_joints holds it at the locked angle with its own PD, this stiff (a motor's hold_kp overrides it; 0: each such motor must give hold_kp); no feed-forward, every tick, in every mode (damped too, like the joint welded in simulation), unless the motor reports a fault: then it is damped with hold_kd").inGroup(kHold).into<&S::hold_kp>(),
  number("hold.kd", "0", 0, 1e4, "", "N·m·s/rad: the hold's damping (a motor's hold_kd overrides it; 0: each such motor must give hold_kd)").inGroup(kHold).into<&S::hold_kd>(),
  number("hold.ramp", "1", 0, 60, "", "s over which a held motor's target moves from where its joint is at the first tick to the locked angle (0: at once)").inGroup(kHold).into<&S::hold_ramp>(),
  // Across keys (the motors' own checks follow in finish()).
  R{"buses", [](const S& s) { return s.buses.empty() ? std::string("needs at least one bus") : ""; }},
  R{"buses", [](const S& s) {
      return static_cast<int>(s.buses.size()) > kMaxBuses
                 ? "at most " + std::to_string(kMaxBuses) + " buses" : std::string();
    }},
  R{"buses", [](const S& s) {
      for (std::size_t i = 0; i < s.buses.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
          if (s.buses[i] == s.buses[j]) return s.buses[i] + " is listed twice";
      return std::string();
    }},
  R{"imu.bus", [](const S& s) {
      return !s.imu_bus.empty() && busIndex(s, s.imu_bus) < 0
                 ? s.imu_bus + " is not one of buses (" + busList(s) + ")" : std::string();
    }},
  R{"host_id", [](const S& s) {
      return s.imu_enabled && s.host_id >= s.imu_id && s.host_id <= s.imu_id + 2
                 ? std::to_string(s.host_id) + " is one of the IMU's ids (" + std::to_string(s.imu_id) +
                       ".." + std::to_string(s.imu_id + 2) + ")"
                 : std::string();
    }},
});
// clang-format on

/// What the rules leave: indices of the buses named, every motor's ranges, the motors' checks.
void finish(S& s) {
  s.imuBusIndex = s.imu_bus.empty() ? 0 : busIndex(s, s.imu_bus);
  std::set<std::pair<int, int>> used;  // (bus, id)
  std::set<std::string> joints;
  for (MotorEntry& m : s.motors) {
    const std::string key = "motors." + m.joint;
    if (!joints.insert(m.joint).second)
      throw SettingsError(s.where(key) + "given twice");
    m.busIndex = busIndex(s, m.bus);
    if (m.busIndex < 0)
      throw SettingsError(s.where(key + ".bus") + m.bus + " is not one of buses (" + busList(s) + ")");
    if (m.id == s.host_id)
      throw SettingsError(s.where(key + ".id") + std::to_string(m.id) +
                          " is host_id, the id replies are sent to");
    if (s.imu_enabled && m.busIndex == s.imuBusIndex && m.id >= s.imu_id && m.id <= s.imu_id + 2)
      throw SettingsError(s.where(key + ".id") + std::to_string(m.id) + " is one of the IMU's ids (" +
                          std::to_string(s.imu_id) + ".." + std::to_string(s.imu_id + 2) + ")");
    if (!used.insert({m.busIndex, m.id}).second)
      throw SettingsError(s.where(key + ".id") + std::to_string(m.id) + " is used twice on " + m.bus);
    MotorRanges& r = m.ranges;
    if (std::isnan(r.position)) r.position = s.ranges_position;
    if (std::isnan(r.velocity)) r.velocity = s.ranges_velocity;
    if (std::isnan(r.torque)) r.torque = s.ranges_torque;
    if (!(r.torque > 0.0))
      throw SettingsError(s.where(key) + "needs torque: the span of its torque field, the "
                          "firmware's T_MAX in N·m (or give ranges.torque for every motor)");
    if (std::isnan(r.kp)) r.kp = s.ranges_kp;
    if (std::isnan(r.kd)) r.kd = s.ranges_kd;
    if (std::isnan(m.hold_kp)) m.hold_kp = s.hold_kp;
    if (std::isnan(m.hold_kd)) m.hold_kd = s.hold_kd;
  }
}

}  // namespace

const std::vector<SettingKey>& socketcanSettingKeys() { return kSchema.rows(); }

SocketcanSettings parseSocketcanSettings(const std::string& yaml, const std::string& origin) {
  SocketcanSettings s = schema::parseSection(kSchema, yaml, origin, "the socketcan backend section");
  finish(s);
  return s;
}

std::string socketcanSettingsReference() { return schema::textReference(kSchema.keys()); }
const char* socketcanSettingsDoc(const char* format) {
  return schema::backendSectionDoc(kSchema.keys(), "socketcan", format);
}

void checkBusLoad(const SocketcanSettings& s, double period) {
  // Classic CAN, 11-bit ids, without stuffing: 47 bits + 8 per data byte (with the interframe
  // space).
  constexpr double kCommandBits = 47 + 8 * 8, kReplyBits = 47 + 8 * 6, kImuBits = 3 * (47 + 8 * 8);
  for (std::size_t b = 0; b < s.buses.size(); ++b) {
    if (s.buses[b].rfind("fd:", 0) == 0) continue;  // an emulated bus has no wire to share
    int motors = 0;
    for (const MotorEntry& m : s.motors) motors += m.busIndex == static_cast<int>(b);
    const bool imu = s.imu_enabled && s.imuBusIndex == static_cast<int>(b);
    const double bits = motors * (kCommandBits + kReplyBits) + (imu ? kImuBits : 0.0);
    const double load = bits / (s.bitrate * period);
    if (load > s.max_bus_load) {
      char text[256];
      std::snprintf(text, sizeof text,
                    "bus %s: %d motors%s need %.0f bits a tick, %.0f %% of the bus at %.0f bit/s "
                    "and %.0f Hz (max_bus_load %.0f %%): spread the motors over more buses",
                    s.buses[b].c_str(), motors, imu ? " and the IMU" : "", bits, 100 * load,
                    s.bitrate, 1.0 / period, 100 * s.max_bus_load);
      throw SettingsError(s.where("buses") + text);
    }
  }
}

}  // namespace ballast::socketcan
