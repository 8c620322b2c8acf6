// `ballast plot`: a telemetry recording (ballastd(8), TELEMETRY; text or .blog) to a PNG of one
// of the figures of kFigures, each a grid of panels gnuplot (pngcairo) draws:
//   fig3      the paper's Fig. 3: (a) velocity tracking, (b) limb tracking error, (c) height,
//             (d) roll, (e) pitch, (f) yaw; estimate, ground truth (simulation) and command
//   fig6      the paper's Fig. 6 (walking over uneven terrain): (a) height, (b) yaw, (c) pitch,
//             (d) roll; estimate, ground truth and command
//   contacts  normal forces per foot (toe, heel, sum), the contact schedule per point, the
//             friction the feet use (|f_t| / f_z)
//   timing    MPC and WBC solve times and the tick's work and lateness over time, and the
//             histograms of the lateness and of the solve times (log counts)
//   joints    tracking error q - qref per joint, one panel per limb (the recording's "limb"
//             lines; one without them, from before they were written: six joints to a panel)
// A .blog is first converted to a TSV of the figure's columns in the window (blog::convert); a
// text recording is plotted as it is, the window applied by gnuplot.
#pragma once

#include <string>
#include <vector>

#include "blog/blog.hpp"

namespace ballast::cli {

struct TelemetryTable {
  std::vector<std::string> columns;
  std::vector<bool> has_data;  ///< per column: some row holds a number (not NaN)
  std::vector<double> max;     ///< per column: the largest number (-inf if none)
  std::size_t rows = 0;
  std::vector<blog::Group> limbs;  ///< the robot's limbs (its "# limb" lines), by joint name
  int column(const std::string& name) const;  ///< 1-based (gnuplot's), 0 if absent
};

/// Reads the header and scans the rows of a text recording whose t lies in [from, to] (rows,
/// has_data and max count those); false with a message for a file that is not one, or no row in
/// the window.
bool readTelemetry(const std::string& path, TelemetryTable& table, std::string& error,
                   double from = -1.0 / 0.0, double to = 1.0 / 0.0);

struct Figure {
  const char* name;
  const char* doc;
  const char* columns;  ///< the columns it draws (shell patterns, comma-separated)
};
inline constexpr Figure kFigures[] = {
    {"fig3", "the paper's Fig. 3: velocity, limb error, height, roll, pitch, yaw",
     "v_fwd,true_v_fwd,cmd_vx,limb_err,z,true_z,cmd_height,roll,true_roll,cmd_roll,pitch,"
     "true_pitch,cmd_pitch,yaw,true_yaw,cmd_yaw"},
    {"fig6", "the paper's Fig. 6 (uneven terrain): height, yaw, pitch, roll",
     "z,true_z,cmd_height,yaw,true_yaw,cmd_yaw,pitch,true_pitch,cmd_pitch,roll,true_roll,cmd_roll"},
    {"contacts", "contact forces and schedule per foot", "contact_*,fx_*,fy_*,fz_*"},
    {"timing", "MPC/WBC solve times, tick work and lateness, their histograms",
     "mpc_ms,wbc_ms,tick_ms,lateness_ms"},
    {"joints", "joint tracking error per limb", "q_*,qref_*"},
};
/// The figure of this name, nullptr if none.
const Figure* findFigure(const std::string& name);

struct PlotOptions {
  const Figure* figure = &kFigures[0];
  std::string title;
  double from = -1.0 / 0.0, to = 1.0 / 0.0;  ///< the window of t (s)
  /// The data holds the window's frames only (a slice of a binary recording): the window then
  /// sets the time axes and is not applied to the data again.
  bool sliced = false;
};

/// The gnuplot script for a figure of the recording in data (a text recording).
std::string plotScript(const TelemetryTable& table, const std::string& data,
                       const std::string& output, const PlotOptions& options);

/// s as a gnuplot string literal ('...', quotes doubled).
std::string gnuplotQuoted(const std::string& s);

/// Runs gnuplot ($BALLAST_GNUPLOT or gnuplot on PATH) on the script; false with a message.
bool runGnuplot(const std::string& script, std::string& error);

}  // namespace ballast::cli
