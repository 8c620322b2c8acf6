// The loop's estimator seat: backend sensors -> estimation::StateEstimator (the Kalman filter of
// DESIGN.md: IMU + leg kinematics + contact forces) -> EstimatedState, with the planner's
// contact schedule as the scheduled stance and the terrain height under the contact points.
// estimator.source = truth (diagnostics only) uses the simulator's ground truth for the base
// and the contacts instead; the filter keeps running beside it.
// Sized at construction; update() allocates nothing.
#pragma once

#include <array>

#include "control/settings.hpp"
#include "control/types.hpp"
#include "estimation/state_estimator.hpp"

namespace ballast::control {

class LoopEstimator {
 public:
  /// Throws std::invalid_argument (the estimator's settings check) for frames not in the model.
  LoopEstimator(const model::Model& model, const ControlSettings& settings);

  /// A profile switch (same frames: restart keys). Returns false if the estimator refused.
  bool setSettings(const ControlSettings& settings);
  /// The next update starts over at this horizontal position (the filter's, not the truth's).
  void reset(double x, double y) { filter_.reset(x, y); }

  /// One sample: joint arrays in the model's order; `scheduled` from the plan (all true when
  /// there is none), `terrain` the ground height under each contact point. Returns false while
  /// there is no estimate yet (no IMU sample so far and no truth to use).
  bool update(const backend::Sensors& sensors, const double* q, const double* dq,
              const double* tau, const std::array<bool, kNumContacts>& scheduled,
              const std::array<double, kNumContacts>& terrain, EstimatedState& out);

  /// Fuses a position fix into the filter (the next update shows it). False when the filter has
  /// no estimate yet or refuses the fix (not finite, σ not positive).
  bool correctPosition(const backend::PositionFix& fix);

  const estimation::EstimatorOutput& filterOutput() const { return output_; }
  estimation::EstimatorStatus filterStatus() const { return status_; }

 private:
  const model::Model& model_;
  const ControlSettings* settings_;
  estimation::StateEstimator filter_;
  estimation::EstimatorInput input_;
  estimation::EstimatorOutput output_;
  estimation::EstimatorStatus status_ = estimation::EstimatorStatus::kWaitingForImu;
};

/// base.rpy from base.orientation.
void fillRpy(BaseState& base);
/// The simulation's ground-truth base state (pose, twist, rpy) into `base`.
void baseStateFromTruth(const backend::Truth& truth, BaseState& base);

}  // namespace ballast::control
