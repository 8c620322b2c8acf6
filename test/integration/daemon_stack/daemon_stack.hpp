// ballastd's control core in process: the daemon put together by the function ballastd uses
// (daemon/main/daemon.hpp), without the socket server, the loop ticked here. Lockstep, so every
// run is deterministic and a command or a push lands at an exact controller time — what a test
// needs to reach, say, every phase of the gait.
#pragma once

#include <cstdlib>
#include <memory>
#include <string>

#include "main/daemon.hpp"

namespace ballast::test {

/// The shipped default profile, profiles/sim-flat.yaml.
inline const std::string kDefaultProfile =
    std::string(BALLAST_SOURCE_DIR) + "/profiles/sim-flat.yaml";

/// The environment variable `name` as a number, `fallback` when it is unset: a test's knob for
/// a run by hand.
inline double envOr(const char* name, double fallback) {
  const char* v = std::getenv(name);
  return v ? std::atof(v) : fallback;
}

class DaemonStack {
 public:
  /// Loads the profile (a path) and starts everything; throws with the daemon's message when
  /// the profile, the backend or the loop refuses.
  explicit DaemonStack(const std::string& profilePath);
  ~DaemonStack();

  /// Runs the loop for `seconds` of controller time; false as soon as the robot is damped or
  /// has fallen.
  bool run(double seconds);
  /// Submits a command and ticks until its reply; the refusal (kNone when taken).
  control::Refusal command(control::OperatorCommand c);
  control::Refusal walk(double vx, double vy = 0.0, double yawRate = 0.0, double ttl = 600.0);
  control::Refusal push(const char* body, double fx, double fy, double fz, double duration);
  /// Ticks until the mode is `mode` (false after `seconds`).
  bool waitForMode(control::Mode mode, double seconds);

  control::LoopStatus status() const { return loop_->status(); }
  /// The loop itself, between ticks: its last sensor sample and estimator output.
  const control::ControlLoop& loop() const { return *loop_; }
  double t() const { return loop_->status().t; }
  const model::Model& model() const { return daemon_->model(); }
  const control::ControlSettings& settings() const { return daemon_->settings().control; }

 private:
  std::unique_ptr<daemon::Daemon> daemon_;
  control::ControlLoop* loop_ = nullptr;
  std::uint64_t sequence_ = 0;
};

}  // namespace ballast::test
