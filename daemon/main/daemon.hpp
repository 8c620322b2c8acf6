// ballastd put together: profile -> robot model -> settings -> terrain map -> backend plugin
// (loaded, configured with its own profile section, started) -> planner -> control loop ->
// telemetry writer -> socket server. One function of the daemon, used by ballastd
// (daemon/main/ballastd.cpp) and by the in-process tests (test/integration/daemon_stack).
//
// Building runs nothing: the caller runs the loop (run() on its own thread, or tick() from a
// test in lockstep), the telemetry writer (startTelemetry()) and the server. A problem before the
// loop exists is a StartupError with the message ballastd prints (file:line:column: key: what is
// wrong, for the profile's); what was started is stopped again.
#pragma once

#include <atomic>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "backend/plugin_loader.hpp"
#include "control/control_loop.hpp"
#include "control/mpc_planner.hpp"
#include "control/telemetry.hpp"
#include "model/model.hpp"
#include "profile/profile.hpp"
#include "profile/settings.hpp"
#include "server/server.hpp"

namespace ballast::daemon {

struct StartupError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct DaemonOptions {
  std::string profile;  ///< a path or a profile name; empty: sim-flat
  std::vector<std::string> profile_dirs = profile::defaultProfileDirs();
  bool lockstep = false;
  /// With lockstep: controller time advances only as far as clients ask (LoopOptions::hold).
  bool hold = false;
  /// Stop after the profile, the model, the settings, the terrain map and the backend plugin's
  /// check of its section (BackendEntry::check), starting nothing (ballastd --check).
  bool check_only = false;
  /// Build the socket server (ballastd); a test that drives the loop itself needs none.
  bool serve = true;
  std::string socket;  ///< --socket: wins over the profile's
  /// Real time: SCHED_FIFO priority of the planner and its workers (0: normal).
  int planner_priority = 0;
};

class Daemon {
 public:
  /// Throws StartupError.
  explicit Daemon(const DaemonOptions& options);
  /// Detaches and destroys the planner, then the loop; stops the backend if the loop never ran
  /// (a test ticks it).
  ~Daemon();
  Daemon(const Daemon&) = delete;
  Daemon& operator=(const Daemon&) = delete;

  const profile::Profile& profile() const { return *context_.profile; }
  const profile::Settings& settings() const { return settings_; }
  const model::Model& model() const { return *model_; }
  /// What the server reaches into (also the running profile and settings after a switch).
  server::DaemonContext& context() { return context_; }
  /// The backend's note at configure (what it chose, e.g. the simulation's foot contact), or
  /// with check_only why its section went unchecked; "" if none.
  const std::string& backendNote() const { return backend_note_; }
  /// check_only: the plugin checked its section.
  bool backendChecked() const { return backend_checked_; }
  const std::string& pluginPath() const { return plugin_->path(); }
  // The parts below exist unless check_only.
  backend::Backend& backend() { return *backend_; }
  control::MpcPlanner& planner() { return *planner_; }
  control::ControlLoop& loop() { return *loop_; }
  control::TelemetryWriter& writer() { return *writer_; }
  control::TerrainMapper& mapper() { return *mapper_; }
  server::Server* server() { return server_.get(); }

  /// Starts the telemetry writer's thread, and a recording if the profile asks for one.
  /// Throws StartupError.
  void startTelemetry();
  /// The control loop until `stop`, then damped and the backend stopped (ControlLoop::run).
  void run(const std::atomic<bool>& stop);

 private:
  void fail(const std::string& message);

  server::DaemonContext context_;
  profile::Settings settings_;
  std::unique_ptr<model::Model> model_;
  std::shared_ptr<backend::Plugin> plugin_;
  backend::BackendPtr backend_;
  bool backend_started_ = false, loop_ran_ = false, backend_checked_ = false;
  std::string backend_note_;
  std::unique_ptr<control::MpcPlanner> planner_;
  std::unique_ptr<control::TerrainMapper> mapper_;
  std::unique_ptr<control::ControlLoop> loop_;
  std::unique_ptr<control::TelemetryWriter> writer_;
  std::unique_ptr<server::Server> server_;
};

}  // namespace ballast::daemon
