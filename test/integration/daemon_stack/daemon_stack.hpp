// ballastd's control core in process: a profile's settings and model, its backend plugin, the
// MPC planner and the control loop, put together as daemon/main/ballastd.cpp does, without the
// socket server. Lockstep, so every run is deterministic and a command or a push lands at an
// exact controller time — what a test needs to reach, say, every phase of the gait.
#pragma once

#include <memory>
#include <string>

#include "backend/plugin_loader.hpp"
#include "control/control_loop.hpp"
#include "control/mpc_planner.hpp"
#include "model/model.hpp"
#include "profile/profile.hpp"

namespace ballast::test {

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
  double t() const { return loop_->status().t; }
  const model::Model& model() const { return *model_; }
  const control::ControlSettings& settings() const { return *settings_; }

 private:
  std::unique_ptr<profile::Profile> profile_;
  std::unique_ptr<model::Model> model_;
  std::shared_ptr<const control::ControlSettings> settings_;
  std::shared_ptr<backend::Plugin> plugin_;
  backend::BackendPtr backend_;
  std::unique_ptr<control::MpcPlanner> planner_;
  std::unique_ptr<control::ControlLoop> loop_;
  std::uint64_t sequence_ = 0;
};

}  // namespace ballast::test
