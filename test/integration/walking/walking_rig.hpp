// The controller stack of the paper's Fig. 4 closed around the Simbody backend, without the
// daemon: locomotion planner (gait + MPC, every planner period of simulated time) -> plan
// sampled at 1 kHz -> whole-body controller -> motor commands (τ_ff + the motors' PD around the
// controller's targets). Lockstep, so a run is deterministic.
//
// The controller runs on the simulator's ground truth (the estimator is tested on its own); the
// daemon's acceptance tests run the same stack on the estimate, through the CLI.
//
// BALLAST_RIG_TRACE=1 in the environment prints one line per 10 ms: stance flags, base height,
// rpy and the plan's roll and pitch; base velocity and the plan's (v/pv), angular velocity and
// the plan's (w/pw), world; slip = fastest stance contact point (m/s); the norms of the
// reference base linear and angular accelerations; WBC status and per-priority errors; the
// sums of normal forces planned, chosen by the WBC and measured by the simulator, with the
// four measured ones; the last SQP step, constraint violation and cost.
#pragma once

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "backend/plugin_loader.hpp"
#include "control/plan_reference.hpp"
#include "locomotion/locomotion_planner.hpp"
#include "model/algorithms.hpp"
#include "wbc/whole_body_controller.hpp"

namespace ballast::test {

struct WalkingRigOptions {
  double plannerPeriod = 0.01;   ///< s of simulated time between planner updates
  double motorKp = 20.0;         ///< N·m/rad, the motors' PD around the controller's targets
  double motorKd = 2.0;          ///< N·m·s/rad
  std::string simSection = "lidar: {enabled: false}\n";
  unsigned seed = 7;
};

class WalkingRig {
 public:
  explicit WalkingRig(const WalkingRigOptions& options = {});
  ~WalkingRig();

  /// Runs for `seconds` of simulated time under `command`. Stops early on a fall (returns false).
  bool run(const locomotion::LocomotionCommand& command, double seconds);
  /// A push on the named body (world force, N) for `duration` s, starting now.
  bool push(const char* body, const Eigen::Vector3d& force, double duration);

  // Ground truth of the latest tick.
  double time() const { return sensors_.time; }
  Eigen::Vector3d basePosition() const { return Eigen::Vector3d(sensors_.truth.base_position); }
  Eigen::Vector3d baseVelocity() const {
    return Eigen::Vector3d(sensors_.truth.base_linear_velocity);
  }
  Eigen::Matrix3d baseRotation() const;
  /// Contact point c (left toe, left heel, right toe, right heel) touches the ground (truth).
  bool inContact(int c) const { return sensors_.truth.contact[c]; }
  bool fallen() const { return fallen_; }
  const std::string& why() const { return why_; }
  /// Joint positions (model order) of the latest tick.
  Eigen::VectorXd jointPositions() const { return q_.tail(model_.nj()); }
  const model::Model& model() const { return model_; }
  const locomotion::LocomotionPlanner& planner() const { return *planner_; }
  int degradedTicks() const { return degraded_; }
  const locomotion::Plan& plan() const { return plan_; }
  int failedPlans() const { return failedPlans_; }

 private:
  void readState();
  void tick(const locomotion::LocomotionCommand& command);

  WalkingRigOptions options_;
  const model::Model& model_;
  std::shared_ptr<backend::Plugin> plugin_;
  backend::BackendPtr sim_;
  std::vector<int> modelJoint_;
  gait::FlatTerrain ground_;
  locomotion::LocomotionSettings settings_;
  std::unique_ptr<locomotion::LocomotionPlanner> planner_;
  std::unique_ptr<locomotion::PlanSampler> sampler_;
  std::unique_ptr<wbc::WholeBodyController> wbc_;
  locomotion::Plan plan_;
  locomotion::PlanSample now_, ahead_;
  wbc::WbcState state_;
  wbc::WbcReference reference_;
  wbc::WbcOutput output_;
  backend::Sensors sensors_;
  backend::Commands commands_;
  Eigen::VectorXd q_, v_;
  model::Data<double> traceData_{model_};
  double nextPlan_ = 0.0;
  bool fallen_ = false;
  std::string why_;
  int degraded_ = 0, failedPlans_ = 0;
};

/// The planner settings for the humanoid: nominal posture = the simulator's standing posture.
locomotion::LocomotionSettings humanoidLocomotionSettings(const model::Model& model);

}  // namespace ballast::test
