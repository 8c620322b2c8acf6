#include "cli/study_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <string>

#include "blog/blog.hpp"
#include "server/protocol.hpp"

namespace ballast::cli {

int Recording::column(const std::string& name) const {
  const auto it = std::find(columns.begin(), columns.end(), name);
  return it == columns.end() ? -1 : static_cast<int>(it - columns.begin());
}

bool loadRecording(const std::string& path, Recording& r, std::string& error) {
  blog::Reader reader;
  if (!reader.open(path, error)) return false;
  r.columns.clear();
  for (const blog::Column& c : reader.header().columns) r.columns.push_back(c.name);
  r.values.clear();
  std::vector<double> block;
  std::size_t frames = 0;
  while (reader.nextBlock(block, frames))
    r.values.insert(r.values.end(), block.begin(), block.begin() + frames * r.columns.size());
  if (r.column("t") != 0) {
    error = path + ": the first column is not t";
    return false;
  }
  return true;
}

namespace {
/// Mean of squares accumulated, and the root.
struct Rms {
  double sum = 0.0;
  std::size_t n = 0;
  void add(double e) {
    if (!std::isfinite(e)) return;
    sum += e * e;
    ++n;
  }
  double value() const { return n ? std::sqrt(sum / n) : 0.0; }
};
}  // namespace

int truthOrEstimate(const Recording& r, const std::string& name) {
  const int truth = r.column("true_" + name);
  if (truth >= 0 && r.frames() > 0 && std::isfinite(r.at(0, truth))) return truth;
  return r.column(name);
}

bool computeMetrics(const Recording& r, const MetricsWindow& w, RunMetrics& m, std::string& error) {
  m = RunMetrics{};
  // Truth where the simulation gives it.
  auto source = [&](const char* name) { return truthOrEstimate(r, name); };
  const int t = 0, mode = r.column("mode"), vFwd = source("v_fwd"), z = source("z"),
            roll = source("roll"), pitch = source("pitch"), yaw = source("yaw"),
            cmdVx = r.column("cmd_vx"), cmdRoll = r.column("cmd_roll"),
            cmdPitch = r.column("cmd_pitch"), limb = r.column("limb_err"),
            mpc = r.column("mpc_ms"), wbc = r.column("wbc_ms");
  for (const auto& [index, name] : {std::pair{mode, "mode"}, {vFwd, "v_fwd"}, {z, "z"},
                                    {roll, "roll"}, {pitch, "pitch"}, {yaw, "yaw"},
                                    {cmdVx, "cmd_vx"}, {cmdRoll, "cmd_roll"},
                                    {cmdPitch, "cmd_pitch"}, {limb, "limb_err"},
                                    {mpc, "mpc_ms"}, {wbc, "wbc_ms"}})
    if (index < 0) {
      error = std::string("the recording has no column ") + name;
      return false;
    }
  // The fall: the first damped frame (the mode column holds the index into protocol::kModes).
  const double kDamp = static_cast<double>(
      std::find_if(std::begin(protocol::kModes), std::end(protocol::kModes),
                   [](const char* name) { return std::string(name) == "damp"; }) -
      std::begin(protocol::kModes));
  for (std::size_t f = 0; f < r.frames(); ++f)
    if (r.at(f, mode) == kDamp) {
      m.fell = true;
      m.fallTime = r.at(f, t);
      break;
    }
  const double end = m.fell ? std::min(w.end, m.fallTime) : w.end;
  double heading = 0.0;
  bool haveHeading = false;
  for (std::size_t f = 0; f < r.frames() && !haveHeading; ++f)
    if (r.at(f, t) >= w.headingTime - 1e-9) {
      heading = r.at(f, yaw);
      haveHeading = true;
    }
  // Height about its mean: two passes.
  double zSum = 0.0, mpcSum = 0.0, wbcSum = 0.0;
  std::size_t n = 0, solves = 0;
  auto inWindow = [&](std::size_t f) { return r.at(f, t) >= w.begin - 1e-9 && r.at(f, t) < end; };
  for (std::size_t f = 0; f < r.frames(); ++f) {
    // Solve times from the heading time on, so that a robot that fell early still has them.
    if (r.at(f, t) >= w.headingTime - 1e-9 && r.at(f, t) < end) {
      mpcSum += r.at(f, mpc);
      wbcSum += r.at(f, wbc);
      ++solves;
    }
    if (!inWindow(f)) continue;
    zSum += r.at(f, z);
    ++n;
  }
  m.mpcMs = solves ? mpcSum / solves : std::nan("");
  m.wbcMs = solves ? wbcSum / solves : std::nan("");
  if (n == 0 && m.fell && m.fallTime <= w.begin + 1e-9) {  // fell before the window: no figures
    m.velocity = m.limb = m.height = m.roll = m.pitch = m.yaw = std::nan("");
    return true;
  }
  if (n == 0) {
    error = "no frame between t = " + std::to_string(w.begin) + " and " + std::to_string(end) + " s";
    return false;
  }
  const double zMean = zSum / n;
  auto command = [&](std::size_t f, int c) {  // an unset command (NaN) is zero
    const double value = r.at(f, c);
    return std::isfinite(value) ? value : 0.0;
  };
  Rms v, l, h, ro, pi, ya;
  for (std::size_t f = 0; f < r.frames(); ++f) {
    if (!inWindow(f)) continue;
    v.add(r.at(f, vFwd) - command(f, cmdVx));
    l.add(r.at(f, limb));
    h.add(r.at(f, z) - zMean);
    ro.add(r.at(f, roll) - command(f, cmdRoll));
    pi.add(r.at(f, pitch) - command(f, cmdPitch));
    ya.add(std::remainder(r.at(f, yaw) - heading, 2.0 * M_PI));
  }
  m.velocity = v.value();
  m.limb = l.value();
  m.height = h.value();
  m.roll = ro.value();
  m.pitch = pi.value();
  m.yaw = ya.value();
  m.samples = n;
  return true;
}

}  // namespace ballast::cli
