// A kinematic fake backend for the daemon's tests (libballast_backend_fake.so), built against
// the backend ABI only. Its joints follow their PD commands as unit inertias (q̈ = kp (q_des − q)
// + kd (dq_des − dq), feed-forward ignored: there is no gravity here); the base stands still at
// base_height, level, unless a fault is scheduled. Everything is in simulated time, so a
// lockstep run is deterministic. Section keys (all optional):
//
//   base_height: 0.9          base height (ground truth), m
//   reverse_joints: false     report joints in reverse URDF order (tests the name mapping)
//   fault_at: -1              from this time on, every call fails with kFault
//   stale_at: -1              read() returns kStale at this time (once)
//   stall_at: -1              real time: the tick at this time takes `stall` s of wall time (once)
//   stall: 0.05               ... that long
//   nan_at: -1                joint 0's position is NaN at this time (once)
//   tilt_at: -1               the base tips over (1.2 rad about x) from this time on
//   sink_at: -1               the base sinks to 0.3 m, level, from this time on
//   disturbance: true         takes external pushes (false: like hardware, it refuses them)
//   non_foot_contact_at: -1   ground truth reports a non-foot contact from this time on
//   fail_configure: false     configure() fails (for the startup error path)
//   lidar: false              a lidar: every 0.1 s a scan (world frame, from 1.4 m above the
//                             origin) of the floor with a 0.15 m step up from x = 1.2 m on
//
// Unknown keys are an error "file:line:column: key: unknown key", lines counted from the
// section origin the daemon passes, as a real backend reports them.
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "backend_abi.hpp"

using namespace ballast::backend;

namespace {

class FakeBackend final : public Backend {
 public:
  bool configure(const Config& config, Error& error) override {
    period_ = config.period;
    lockstep_ = config.lockstep;
    YAML::Node section;
    try {
      section = YAML::Load(config.section_yaml);
    } catch (const YAML::Exception& e) {
      copyMessage(error, (std::string(config.section_origin) + ": " + e.what()).c_str());
      return false;
    }
    const std::string origin = config.section_origin;
    const std::string file = origin.substr(0, origin.rfind(':'));
    const int line = std::atoi(origin.substr(origin.rfind(':') + 1).c_str());
    static const char* kKeys[] = {"base_height", "reverse_joints",      "fault_at",
                                  "stale_at",    "stall_at",            "nan_at",   "stall",
                                  "tilt_at",     "non_foot_contact_at", "fail_configure",
                                  "sink_at",     "disturbance",         "lidar"};
    if (section.IsMap())
      for (const auto& kv : section) {
        const std::string key = kv.first.Scalar();
        bool known = false;
        for (const char* k : kKeys) known |= key == k;
        if (!known) {
          const std::string msg = file + ":" + std::to_string(line + kv.first.Mark().line) + ":" +
                                  std::to_string(kv.first.Mark().column + 1) + ": " + key +
                                  ": unknown key";
          copyMessage(error, msg.c_str());
          return false;
        }
      }
    auto num = [&](const char* k, double d) { return section[k] ? section[k].as<double>() : d; };
    base_height_ = num("base_height", 0.9);
    fault_at_ = num("fault_at", -1);
    stale_at_ = num("stale_at", -1);
    stall_at_ = num("stall_at", -1);
    stall_ = num("stall", 0.05);
    nan_at_ = num("nan_at", -1);
    tilt_at_ = num("tilt_at", -1);
    sink_at_ = num("sink_at", -1);
    non_foot_at_ = num("non_foot_contact_at", -1);
    if (section["fail_configure"] && section["fail_configure"].as<bool>()) {
      copyMessage(error, (origin + ": fail_configure: asked to fail").c_str());
      return false;
    }

    // Joint names: the movable joints of the URDF, in file order.
    std::ifstream in(config.urdf_path);
    std::stringstream text;
    text << in.rdbuf();
    const std::regex joint(
        "<joint[^>]*name=\"([^\"]+)\"[^>]*type=\"(revolute|continuous|prismatic)\"");
    std::vector<std::string> names;
    const std::string xml = text.str();
    for (auto it = std::sregex_iterator(xml.begin(), xml.end(), joint);
         it != std::sregex_iterator(); ++it)
      names.push_back((*it)[1]);
    if (section["reverse_joints"] && section["reverse_joints"].as<bool>())
      std::reverse(names.begin(), names.end());
    if (names.empty() || names.size() > kMaxJoints) {
      copyMessage(error, (std::string(config.urdf_path) + ": no movable joints found").c_str());
      return false;
    }
    std::strcpy(caps_.name, "fake");
    caps_.simulation = true;
    caps_.lockstep = true;
    caps_.ground_truth = true;
    caps_.disturbance = !section["disturbance"] || section["disturbance"].as<bool>();
    caps_.lidar = section["lidar"] && section["lidar"].as<bool>();
    for (int i = 0; i < 40; ++i)
      for (int j = 0; j < 40; ++j) {
        const float x = 0.2f + 0.05f * static_cast<float>(i), y = -1.0f + 0.05f * static_cast<float>(j);
        scan_.insert(scan_.end(), {x, y, x >= 1.2f ? 0.15f : 0.0f});
      }
    caps_.num_joints = static_cast<int>(names.size());
    for (std::size_t j = 0; j < names.size(); ++j)
      std::snprintf(caps_.joint_names[j], kNameLength, "%s", names[j].c_str());
    return true;
  }
  const Capabilities& capabilities() const override { return caps_; }
  bool start(Error&) override { return true; }

  Status read(Sensors& s) override {
    if (failing()) return Status::kFault;
    if (once(stale_at_)) {
      copyMessage(error_, "no new sample");
      return Status::kStale;
    }
    s.time = time_;
    s.sequence = ++sequence_;
    s.num_joints = caps_.num_joints;
    for (int j = 0; j < caps_.num_joints; ++j) {
      s.q[j] = q_[j];
      s.dq[j] = dq_[j];
      s.tau[j] = tau_[j];
    }
    if (once(nan_at_)) s.q[0] = std::nan("");
    const bool tilted = tilt_at_ >= 0 && time_ >= tilt_at_;
    const double a = tilted ? 1.2 : 0.0;
    const double quat[4] = {std::sin(a / 2), 0, 0, std::cos(a / 2)};
    std::memcpy(s.imu.orientation, quat, sizeof(quat));
    s.imu.angular_velocity[0] = s.imu.angular_velocity[1] = s.imu.angular_velocity[2] = 0.0;
    // Specific force: gravity's reaction, in the IMU frame.
    s.imu.linear_acceleration[0] = 0.0;
    s.imu.linear_acceleration[1] = 9.81 * std::sin(a);
    s.imu.linear_acceleration[2] = 9.81 * std::cos(a);
    s.imu_valid = true;
    s.has_truth = true;
    Truth& t = s.truth;
    t.base_position[0] = t.base_position[1] = 0.0;
    const bool sunk = sink_at_ >= 0 && time_ >= sink_at_;
    t.base_position[2] = tilted || sunk ? 0.3 : base_height_;
    std::memcpy(t.base_orientation, quat, sizeof(quat));
    for (int c = 0; c < 4; ++c) t.contact[c] = !tilted;
    t.non_foot_contact = non_foot_at_ >= 0 && time_ >= non_foot_at_;
    return Status::kOk;
  }

  Status write(const Commands& c) override {
    if (failing()) return Status::kFault;
    for (int j = 0; j < caps_.num_joints; ++j) cmd_[j] = c.joint[j];
    return Status::kOk;
  }

  Status advance(TickTiming& timing) override {
    timing = TickTiming{};
    if (failing()) return Status::kFault;
    for (int j = 0; j < caps_.num_joints; ++j) {
      const JointCommand& c = cmd_[j];
      const double acc = c.kp * (c.q_des - q_[j]) + c.kd * (c.dq_des - dq_[j]);
      dq_[j] = (dq_[j] + acc * period_) * 0.999;
      q_[j] += dq_[j] * period_;
      tau_[j] = acc;
    }
    time_ += period_;
    if (once(stall_at_)) {
      const timespec pause{static_cast<time_t>(stall_), static_cast<long>(std::fmod(stall_, 1.0) * 1e9)};
      nanosleep(&pause, nullptr);
    }
    if (!lockstep_) {
      // Absolute deadlines from the first tick; after a stall the periods gone are skipped.
      if (next_.tv_sec == 0 && next_.tv_nsec == 0) clock_gettime(CLOCK_MONOTONIC, &next_);
      next_.tv_nsec += static_cast<long>(period_ * 1e9);
      while (next_.tv_nsec >= 1000000000L) next_.tv_nsec -= 1000000000L, ++next_.tv_sec;
      timespec now;
      clock_gettime(CLOCK_MONOTONIC, &now);
      const double behind = static_cast<double>(now.tv_sec - next_.tv_sec) +
                            1e-9 * static_cast<double>(now.tv_nsec - next_.tv_nsec);
      if (behind > 0.0) {
        timing.late = true;
        timing.lateness = behind;
        timing.skipped = static_cast<std::uint32_t>(behind / period_);
        for (std::uint32_t k = 0; k < timing.skipped; ++k) {
          next_.tv_nsec += static_cast<long>(period_ * 1e9);
          while (next_.tv_nsec >= 1000000000L) next_.tv_nsec -= 1000000000L, ++next_.tv_sec;
        }
        time_ += period_ * timing.skipped;
      } else {
        clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next_, nullptr);
      }
    }
    return Status::kOk;
  }

  bool lidarScan(PointCloudView& view) override {
    if (!caps_.lidar || time_ + 1e-9 < next_scan_) return false;
    next_scan_ += 0.1;
    view.xyz = scan_.data();
    view.count = static_cast<int>(scan_.size() / 3);
    view.time = time_;
    view.sensor_origin[0] = view.sensor_origin[1] = 0.0;
    view.sensor_origin[2] = 1.4;
    view.frame = ScanFrame::kWorld;
    return true;
  }

  const Error& lastError() const override { return error_; }
  void stop() override {}
  bool push(const Push& push, Error& error) override {
    if (push.body[0] && std::strcmp(push.body, "pelvis") && std::strcmp(push.body, "torso")) {
      copyMessage(error, (std::string("no body named '") + push.body + "'").c_str());
      return false;
    }
    return true;
  }

 private:
  bool failing() {
    if (fault_at_ >= 0 && time_ >= fault_at_) {
      copyMessage(error_, "the fake backend was told to fail");
      return true;
    }
    return false;
  }
  /// True on the first call at or after t (t < 0: never).
  bool once(double& t) {
    if (t < 0 || time_ < t) return false;
    t = -1;
    return true;
  }

  Capabilities caps_;
  Error error_;
  double period_ = 0.001, time_ = 0.0, base_height_ = 0.9;
  double fault_at_ = -1, stale_at_ = -1, stall_at_ = -1, stall_ = 0.05, nan_at_ = -1, tilt_at_ = -1,
         sink_at_ = -1, non_foot_at_ = -1;
  bool lockstep_ = false;
  std::uint64_t sequence_ = 0;
  double q_[kMaxJoints] = {}, dq_[kMaxJoints] = {}, tau_[kMaxJoints] = {};
  JointCommand cmd_[kMaxJoints];
  timespec next_{};
  std::vector<float> scan_;
  double next_scan_ = 0.1;
};

Backend* create() {
  return new FakeBackend;
}
void destroy(Backend* b) {
  delete b;
}
const BackendEntry kEntry{kBackendAbiVersion, "fake", "kinematic fake for ballastd's tests",
                          &create, &destroy, nullptr, nullptr};

}  // namespace

extern "C" __attribute__((visibility("default"))) const BackendEntry* ballast_backend_entry() {
  return &kEntry;
}
