// Telemetry: one frame per control tick (every telemetry.decimation ticks), written by its own
// thread either as tab-separated text that gnuplot and `ballast plot` read directly (FILE.tsv, or
// any other name) or as the compact binary log of blog/blog.hpp (FILE.blog: 5x smaller, converted
// by `ballast log`).
//
// The loop fills a TelemetryFrame and pushes it into a ring; it never formats, allocates or
// touches the file. The writer thread drains the ring into the file while recording. If the
// ring is full the loop drops the frame and counts it (real time), or, in lockstep, waits for
// room, since there simulated time waits with it.
//
// File format (ballastd(8), TELEMETRY, documents it): a first line "# ballast telemetry 1", a
// second line "# " followed by the tab-separated column names (telemetryColumns), then one line
// per frame, each value as the column table keeps it (blog::TextFormat: the .blog of the same
// frames converts to the same text). NaN marks a value that does not exist (no ground truth, no
// such priority level). The columns are the rows of one table (TelemetryColumn,
// telemetry_columns.cpp).
#pragma once

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "blog/blog.hpp"
#include "control/spsc_ring.hpp"
#include "control/types.hpp"

namespace ballast::model {
struct Model;
}

namespace ballast::control {

struct TelemetryFrame {
  std::uint32_t recording = 0;  ///< which recording it belongs to
  double t = 0.0;
  Mode mode = Mode::kPassive;
  BaseState base;
  bool has_truth = false;
  BaseState truth;
  BaseCommand command;
  bool contact[kNumContacts] = {};
  bool planned_contact[kNumContacts] = {};  ///< stance in the plan in force (standing: all)
  double task_error[kNumPriorityLevels] = {};
  double contact_force[kNumContacts][3] = {};  ///< ControllerOutput::contact_force
  double contact_ref[kNumContacts][3] = {};       ///< ControllerOutput::contact_ref
  double contact_position[kNumContacts][3] = {};  ///< ControllerOutput::contact_position
  double mpc_ms = 0.0, wbc_ms = 0.0;
  double tick_ms = 0.0;      ///< the tick's work until it was recorded (read through write)
  double lateness_ms = 0.0;  ///< how late the tick began (real time; 0 in lockstep)
  int num_joints = 0;
  double q[kMaxJoints] = {}, dq[kMaxJoints] = {}, tau[kMaxJoints] = {};
  double q_ref[kMaxJoints] = {}, tau_ff[kMaxJoints] = {};
};

using TelemetryRing = SpscRing<TelemetryFrame>;

/// A row of the column table: one column, or one per contact point (name + 0..3), priority level
/// (name + 1..4) or joint (name + the URDF joint name).
enum class Repeat : std::uint8_t { kOnce, kPerContact, kPerLevel, kPerJoint };
struct TelemetryColumn {
  const char* name;  ///< the column's name, or a repeated row's prefix
  Repeat repeat;
  const char* unit;
  blog::Type type;    ///< kF64, kU8: kept exactly; kI32: to the resolution
  double resolution;  ///< kI32: the step a recording keeps (in unit); 0 for the others
  const char* doc;
  double (*value)(const TelemetryFrame& frame, int index);  ///< index: contact, level, joint
};
/// The table, in file order (telemetry_columns.cpp).
const std::vector<TelemetryColumn>& telemetryTable();
/// The table as ballastd(8)'s TELEMETRY section lists it (roff: per row .TP, the name, then its
/// unit, what a recording keeps and the doc).
std::string telemetryColumnsMan();

/// The most columns a frame has (t, mode, base estimate and truth, command, contacts measured and
/// planned, their forces, positions and references, task errors, times, limb error, five values per joint); a test holds
/// it to the table.
inline constexpr std::size_t kMaxTelemetryColumns =
    2 + 28 + 7 + 11 * kNumContacts + kNumPriorityLevels + 5 + 5 * kMaxJoints;

/// Column names, in file order, for a robot with these joints.
std::vector<std::string> telemetryColumns(const std::vector<std::string>& joint_names);
/// The same with each column's unit, type, resolution and doc, as a .blog header has them.
std::vector<blog::Column> telemetryColumnsDescribed(const std::vector<std::string>& joint_names);
/// One frame's values in column order (values holds telemetryColumns().size()); returns how
/// many it wrote.
std::size_t telemetryValues(const TelemetryFrame& frame, double* values);
/// Appends one frame as a line (tab-separated, '\n'-terminated), each value as format (made of
/// telemetryColumnsDescribed) prints it.
void formatTelemetryLine(const TelemetryFrame& frame, const blog::TextFormat& format,
                         std::string& line);

/// What a recording's .blog header says besides the columns.
struct RecordingInfo {
  std::string profile, robot;
  std::vector<blog::Group> limbs;  ///< by joint name
};
/// The profile's name and the model's robot and limbs (model::limbs).
RecordingInfo recordingInfo(const std::string& profile, const model::Model& model);

class TelemetryWriter {
 public:
  TelemetryWriter(TelemetryRing& ring, std::vector<std::string> joint_names);
  ~TelemetryWriter();

  void start();
  /// Drains what is left of the current recording, closes it and ends the thread.
  void stop();

  /// IO side. Opens path (truncating) and starts a recording, binary if path ends in .blog, TSV
  /// otherwise; false with a message if the file cannot be opened or a recording is already on.
  bool startRecording(const std::string& path, std::string& error, const RecordingInfo& info = {});
  /// Ends the recording after writing every frame the loop produced for it. Returns the frames
  /// written; false if nothing was recording.
  bool stopRecording(std::uint64_t& frames, std::string& path);
  bool recording() const { return recording_.load(std::memory_order_relaxed) != 0; }
  std::string path() const;

  /// Loop side: the recording frames belong to, 0 when none.
  std::uint32_t activeRecording() const { return recording_.load(std::memory_order_relaxed); }

 private:
  void run();
  std::size_t drain(std::size_t max_frames);

  TelemetryRing& ring_;
  std::vector<std::string> joint_names_;
  std::atomic<std::uint32_t> recording_{0};
  std::uint32_t next_id_ = 0;
  mutable std::mutex mutex_;  // file_, path_, file_id_, frames_: writer thread and IO thread
  std::FILE* file_ = nullptr;
  std::uint32_t file_id_ = 0;
  std::string path_;
  std::uint64_t frames_ = 0;
  std::string line_;
  blog::TextFormat text_format_;  // the TSV's columns
  blog::Writer blog_;            // open while recording a .blog
  std::vector<double> values_;   // one frame's values (sized once)
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace ballast::control
