#include "control/telemetry.hpp"

#include <pthread.h>

#include <charconv>
#include <chrono>
#include <cmath>
#include <cstring>

#include "model/base_conventions.hpp"

namespace ballast::control {

namespace {

/// Velocity in the heading frame (yaw only): forward and lateral.
void headingVelocity(const BaseState& b, double& forward, double& lateral) {
  const double c = std::cos(b.rpy[2]), s = std::sin(b.rpy[2]);
  forward = c * b.linear_velocity[0] + s * b.linear_velocity[1];
  lateral = -s * b.linear_velocity[0] + c * b.linear_velocity[1];
}

void putBase(double*& out, const BaseState& b, bool valid) {
  double f = kNaN, l = kNaN;
  if (valid) headingVelocity(b, f, l);
  const double* groups[4] = {b.position, b.linear_velocity, b.rpy, b.angular_velocity};
  for (const double* g : groups)
    for (int i = 0; i < 3; ++i) *out++ = valid ? g[i] : kNaN;
  *out++ = f;
  *out++ = l;
}

bool endsWith(const std::string& s, const char* suffix) {
  const std::size_t n = std::strlen(suffix);
  return s.size() >= n && s.compare(s.size() - n, n, suffix) == 0;
}

}  // namespace

std::vector<std::string> telemetryColumns(const std::vector<std::string>& joints) {
  std::vector<std::string> c = {"t", "mode"};
  for (const char* prefix : {"", "true_"})
    for (const char* n :
         {"x", "y", "z", "vx", "vy", "vz", "roll", "pitch", "yaw", "wx", "wy", "wz", "v_fwd",
          "v_lat"})
      c.push_back(std::string(prefix) + n);
  for (const char* n :
       {"cmd_vx", "cmd_vy", "cmd_yaw_rate", "cmd_height", "cmd_roll", "cmd_pitch", "cmd_yaw"})
    c.push_back(n);
  for (int i = 0; i < kNumContacts; ++i) c.push_back("contact_" + std::to_string(i));
  for (int i = 1; i <= kNumPriorityLevels; ++i) c.push_back("err_p" + std::to_string(i));
  c.push_back("mpc_ms");
  c.push_back("wbc_ms");
  c.push_back("tick_ms");
  c.push_back("lateness_ms");
  c.push_back("limb_err");  // RMS over the joints of q − q_ref, rad (the paper's Fig. 3 b)
  for (const char* prefix : {"q_", "dq_", "tau_", "qref_", "tauff_"})
    for (const auto& j : joints) c.push_back(prefix + j);
  return c;
}

std::vector<blog::Column> telemetryColumnsDescribed(const std::vector<std::string>& joints) {
  using blog::Type;
  // Units by name; every physical quantity is f32 (blog/blog.hpp says why), t is f64, the mode
  // and the contact flags u8.
  static const std::pair<const char*, const char*> kUnits[] = {
      {"t", "s"}, {"mode", "-"}, {"x", "m"}, {"y", "m"}, {"z", "m"}, {"vx", "m/s"},
      {"vy", "m/s"}, {"vz", "m/s"}, {"roll", "rad"}, {"pitch", "rad"}, {"yaw", "rad"},
      {"wx", "rad/s"}, {"wy", "rad/s"}, {"wz", "rad/s"}, {"v_fwd", "m/s"}, {"v_lat", "m/s"},
      {"cmd_vx", "m/s"}, {"cmd_vy", "m/s"}, {"cmd_yaw_rate", "rad/s"}, {"cmd_height", "m"},
      {"cmd_roll", "rad"}, {"cmd_pitch", "rad"}, {"cmd_yaw", "rad"}, {"mpc_ms", "ms"},
      {"wbc_ms", "ms"}, {"tick_ms", "ms"}, {"lateness_ms", "ms"}, {"limb_err", "rad"}};
  static const std::pair<const char*, const char*> kPrefixes[] = {
      {"true_", nullptr}, {"contact_", "-"}, {"err_p", "-"}, {"q_", "rad"}, {"dq_", "rad/s"},
      {"tau_", "N*m"}, {"qref_", "rad"}, {"tauff_", "N*m"}};
  std::vector<blog::Column> out;
  for (const std::string& name : telemetryColumns(joints)) {
    blog::Column c{name, "-", Type::kF32};
    std::string base = name;
    for (const auto& [prefix, unit] : kPrefixes)
      if (name.rfind(prefix, 0) == 0) {
        if (unit) c.unit = unit;
        else base = name.substr(std::strlen(prefix));
        break;
      }
    for (const auto& [n, unit] : kUnits)
      if (base == n) c.unit = unit;
    if (name == "t") c.type = Type::kF64;
    if (name == "mode" || name.rfind("contact_", 0) == 0) c.type = Type::kU8;
    out.push_back(c);
  }
  return out;
}

std::size_t telemetryValues(const TelemetryFrame& f, double* values) {
  double* out = values;
  *out++ = f.t;
  *out++ = static_cast<double>(f.mode);
  putBase(out, f.base, true);
  putBase(out, f.truth, f.has_truth);
  const BaseCommand& c = f.command;
  for (double x : {c.vx, c.vy, c.yaw_rate, c.height, c.roll, c.pitch, c.yaw}) *out++ = x;
  for (bool b : f.contact) *out++ = b ? 1.0 : 0.0;
  for (double e : f.task_error) *out++ = e;
  *out++ = f.mpc_ms;
  *out++ = f.wbc_ms;
  *out++ = f.tick_ms;
  *out++ = f.lateness_ms;
  double sum = 0.0;
  for (int j = 0; j < f.num_joints; ++j) sum += (f.q[j] - f.q_ref[j]) * (f.q[j] - f.q_ref[j]);
  *out++ = f.num_joints > 0 ? std::sqrt(sum / f.num_joints) : 0.0;
  const double* arrays[5] = {f.q, f.dq, f.tau, f.q_ref, f.tau_ff};
  for (const double* a : arrays)
    for (int j = 0; j < f.num_joints; ++j) *out++ = a[j];
  return static_cast<std::size_t>(out - values);
}

void formatTelemetryLine(const TelemetryFrame& f, std::string& line) {
  double values[kMaxTelemetryColumns];
  const std::size_t n = telemetryValues(f, values);
  for (std::size_t i = 0; i < n; ++i) blog::appendTsv(line, values[i]);
  line.back() = '\n';
}

TelemetryWriter::TelemetryWriter(TelemetryRing& ring, std::vector<std::string> joint_names)
    : ring_(ring),
      joint_names_(std::move(joint_names)),
      values_(kMaxTelemetryColumns) {}

TelemetryWriter::~TelemetryWriter() {
  stop();
}

void TelemetryWriter::start() {
  thread_ = std::thread([this] {
    pthread_setname_np(pthread_self(), "ballast-writer");
    run();
  });
}

void TelemetryWriter::stop() {
  if (thread_.joinable()) {
    std::uint64_t frames;
    std::string path;
    stopRecording(frames, path);
    stop_ = true;
    thread_.join();
  }
}

bool TelemetryWriter::startRecording(const std::string& path, std::string& error,
                                     const RecordingInfo& info) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (file_ || blog_.isOpen()) {
    error = "already recording to " + path_ + ": run `ballast record stop` first";
    return false;
  }
  if (endsWith(path, ".blog")) {
    blog::Header h;
    h.profile = info.profile.empty() ? "-" : info.profile;
    h.robot = info.robot.empty() ? "-" : info.robot;
    h.start_unix_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                          std::chrono::system_clock::now().time_since_epoch())
                          .count();
    h.columns = telemetryColumnsDescribed(joint_names_);
    if (!blog_.open(path, h, error)) return false;
    path_ = path;
    frames_ = 0;
    file_id_ = ++next_id_;
    recording_.store(file_id_, std::memory_order_relaxed);
    return true;
  }
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) {
    error = "cannot write " + path + ": " + std::strerror(errno);
    return false;
  }
  std::fputs("# ballast telemetry 1\n# ", f);
  const auto cols = telemetryColumns(joint_names_);
  for (std::size_t i = 0; i < cols.size(); ++i)
    std::fprintf(f, "%s%c", cols[i].c_str(), i + 1 < cols.size() ? '\t' : '\n');
  file_ = f;
  path_ = path;
  frames_ = 0;
  file_id_ = ++next_id_;
  recording_.store(file_id_, std::memory_order_relaxed);
  return true;
}

bool TelemetryWriter::stopRecording(std::uint64_t& frames, std::string& path) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!file_ && !blog_.isOpen()) return false;
    recording_.store(0, std::memory_order_relaxed);
  }
  // The loop may be pushing the recording's last frame right now: give the writer a moment to
  // take everything queued, then close.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  std::this_thread::sleep_for(std::chrono::milliseconds(2));
  while (ring_.size() > 0 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  std::lock_guard<std::mutex> lock(mutex_);
  drain(ring_.capacity());
  if (file_) std::fclose(file_);
  file_ = nullptr;
  blog_.close();
  file_id_ = 0;
  frames = frames_;
  path = path_;
  return true;
}

std::string TelemetryWriter::path() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return path_;
}

std::size_t TelemetryWriter::drain(std::size_t max_frames) {
  TelemetryFrame frame;
  std::size_t n = 0;
  for (; n < max_frames && ring_.tryPop(frame); ++n) {
    if (frame.recording != file_id_ || file_id_ == 0) continue;
    if (blog_.isOpen()) {
      telemetryValues(frame, values_.data());
      blog_.append(values_.data());
      ++frames_;
      continue;
    }
    if (!file_) continue;
    line_.clear();
    formatTelemetryLine(frame, line_);
    std::fwrite(line_.data(), 1, line_.size(), file_);
    ++frames_;
  }
  return n;
}

void TelemetryWriter::run() {
  constexpr std::size_t kBatch = 512;  // lets the IO thread in between batches
  while (!stop_.load()) {
    std::size_t n;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      n = drain(kBatch);
    }
    if (n < kBatch) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

}  // namespace ballast::control
