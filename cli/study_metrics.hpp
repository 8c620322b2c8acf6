// ballast-study's figures of one run, from its telemetry recording (ballastd(8), FILES): did the
// robot fall and when, and how well it tracked over a window of controller time — the columns
// of the paper's comparison (Sec. III-A) and of its Fig. 3 and Fig. 5.
//
// A Recording is a .blog (or made up in a test): column names and frames, each frame one value
// per column, t (controller time, s) first. The run's ground truth (true_*) is used where the
// recording has it (simulation), the estimate otherwise.
//
// Metrics over [begin, end], cut at the fall (the first frame in mode damp: ballastd damps a
// fallen robot) so that a fall's tumbling does not count as tracking:
//   velocity  RMS of forward velocity (heading frame) − cmd_vx, m/s
//   limb      RMS of limb_err (RMS over the joints of q − the plan's q), rad
//   height    RMS of the base height about its mean, m (the reference height is not recorded;
//             walking, it is constant)
//   roll, pitch  RMS of the angle − its command, rad
//   yaw       RMS of the yaw − the yaw at `headingTime` (the heading walking started with), rad
//   mpc, wbc  mean solve times, ms, from `headingTime` to the end or the fall (wall time on
//             this machine: the only figures that differ from run to run)
#pragma once

#include <string>
#include <vector>

namespace ballast::cli {

struct Recording {
  std::vector<std::string> columns;
  std::vector<double> values;  ///< frame after frame, columns.size() per frame
  std::size_t frames() const { return columns.empty() ? 0 : values.size() / columns.size(); }
  int column(const std::string& name) const;  ///< 0-based, −1 if absent
  double at(std::size_t frame, int column) const { return values[frame * columns.size() + column]; }
};

/// Reads a .blog recording; false with a message.
bool loadRecording(const std::string& path, Recording& recording, std::string& error);

struct MetricsWindow {
  double begin = 0.0, end = 1e9;  ///< controller time, s
  double headingTime = 0.0;       ///< the yaw reference is the yaw here
};

struct RunMetrics {
  bool fell = false;
  double fallTime = -1.0;  ///< controller time of the first damped frame, s
  double velocity = 0.0, limb = 0.0, height = 0.0, roll = 0.0, pitch = 0.0, yaw = 0.0;
  double mpcMs = 0.0, wbcMs = 0.0;
  std::size_t samples = 0;  ///< frames in the window (before the fall)
};

/// The column true_NAME where the recording has ground truth (its first value finite), else
/// NAME (the estimate); -1 if neither is there.
int truthOrEstimate(const Recording& r, const std::string& name);

/// The metrics of a run over a window; false with a message when a column they need is
/// missing or the window holds no frame. A robot that fell before the window has no figures:
/// they are NaN, samples 0.
bool computeMetrics(const Recording& recording, const MetricsWindow& window, RunMetrics& metrics,
                    std::string& error);

}  // namespace ballast::cli
