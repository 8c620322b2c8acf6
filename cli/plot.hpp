// `ballast plot`: a telemetry recording (ballastd(8), FILES) to a PNG laid out like the paper's
// Fig. 3: (a) velocity tracking, (b) limb tracking error, (c) height, (d) roll, (e) pitch,
// (f) yaw; estimate, ground truth (simulation) and command in each. gnuplot (pngcairo) draws it.
#pragma once

#include <string>
#include <vector>

namespace ballast::cli {

struct TelemetryTable {
  std::vector<std::string> columns;
  std::vector<bool> has_data;  ///< per column: some row holds a number (not NaN)
  std::size_t rows = 0;
  int column(const std::string& name) const;  ///< 1-based (gnuplot's), 0 if absent
};

/// Reads the header and scans the rows; false with a message for a file that is not a
/// recording.
bool readTelemetry(const std::string& path, TelemetryTable& table, std::string& error);

/// The gnuplot script for the six panels.
std::string plotScript(const TelemetryTable& table, const std::string& data,
                       const std::string& output, const std::string& title);

/// Runs gnuplot ($BALLAST_GNUPLOT or gnuplot on PATH) on the script; false with a message.
bool runGnuplot(const std::string& script, std::string& error);

}  // namespace ballast::cli
