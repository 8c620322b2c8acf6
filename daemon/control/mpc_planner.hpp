// The kino-dynamic MPC in the control loop's planner seat (PlannerSlot): PlannerInput ->
// locomotion::LocomotionPlanner (gait, footholds, swing trajectories, SQP iterations) ->
// PlannerOutput. Runs on the planner thread only.
//
//   mode walk  -> LocomotionCommand{walk, the velocity command while it is active (else 0)}
//   mode stand -> standing, at the commanded pose (height, roll, pitch, yaw), with the joint
//                 posture that realises it (StandPosture) as the joints' reference
// PlannerInput::restart, or new settings, rebuild the LocomotionPlanner (the planner thread
// allocates; the 1 kHz loop never does). New settings (a profile switch: the IO thread hands over
// the value the loop switches to, shared, through requestSettings()) take effect at the first plan
// made standing — a planner rebuilt mid-stride would lose its gait phase — or at a restart; the
// planner lets go of them once it has taken their numbers.
// A failed SQP iteration or a plan with a non-finite number is reported invalid with the
// solver's message; the loop keeps its last valid plan and raises a planner fault.
// The terrain (MapTerrain) is the world, not a setting: a map handed over by setTerrain() is
// taken at the start of the next plan(), walking or not.
//
// Latency: a plan reaches the controller `lead` seconds after the state it was made from (the
// solve's time). A plan that starts at the measured state is then already `lead` old when it is
// first used, and the whole-body controller spends the time until the next one pulling the robot
// back onto a trajectory that began in the past: at 8 ms of latency walking went unstable. So the
// plan starts at t + lead, from the measured state moved on by what the plan in force predicts
// for those `lead` seconds (its base pose, twist and joints), as MPC delay compensation does.
#pragma once

#include <memory>
#include <mutex>

#include "control/map_terrain.hpp"
#include "control/planner_slot.hpp"
#include "control/settings.hpp"
#include "control/stand_posture.hpp"
#include "control/types.hpp"
#include "locomotion/locomotion_planner.hpp"

namespace ballast::control {

class MpcPlanner final : public Planner {
 public:
  /// Keeps a reference to the model, which must outlive the planner. Throws what
  /// LocomotionPlanner's constructor throws, std::invalid_argument for a null terrain.
  MpcPlanner(const model::Model& model, const ControlSettings& settings,
             std::shared_ptr<const terrain::HeightMap> terrain);

  void plan(const PlannerInput& input, PlannerOutput& output) override;
  /// The next plan's SQP preparation (locomotion::LocomotionPlanner::prepare) for an input at
  /// t with the lead of the last one, after a valid plan.
  void prepare(double t) override;

  /// Any thread but the loop's: the settings for the next rebuild (shared, not copied; a later
  /// request replaces one not yet taken).
  void requestSettings(SettingsPtr settings);
  /// Any thread but the loop's: the terrain from the next plan() on (MapTerrain::publish).
  /// `scan`, `handoff_ns`: the last lidar scan in it and when the loop handed it off
  /// (MapTerrain::publish).
  void setTerrain(std::shared_ptr<const terrain::HeightMap> terrain, std::uint64_t scan = 0,
                  std::uint64_t handoff_ns = 0);
  /// The planner's terrain, for its latency figures (any thread).
  const MapTerrain& terrain() const { return terrain_; }

 private:
  void rebuild();

  const model::Model& model_;
  MapTerrain terrain_;  // before planner_, which refers to it
  locomotion::LocomotionSettings settings_;
  std::unique_ptr<locomotion::LocomotionPlanner> planner_;
  StandPosture posture_;
  locomotion::LocomotionCommand command_;
  Eigen::VectorXd q_, v_;
  /// The last valid plan and a sampler for it: the prediction over the lead.
  locomotion::Plan previous_;
  bool have_previous_ = false;
  locomotion::PlanSampler sampler_;
  locomotion::PlanSample at_t_, at_lead_;
  /// Moves the model state (q_, v_) on from t to t + lead as previous_ predicts.
  void predict(double t, double lead);
  double map_tolerance_;  // ControlSettings::map_tolerance
  bool walking_ = false;
  bool planned_ = false;  // the planner has made a plan since it was built
  double lead_ = 0.0;     // the last plan's lead
  static constexpr int kFreshIterations = 5;

  std::mutex pending_mutex_;  // IO thread <-> planner thread only
  SettingsPtr pending_;
};

}  // namespace ballast::control
