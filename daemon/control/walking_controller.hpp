// Stand and walk under the whole-body controller (paper Fig. 4: MPC -> WBC -> motors): the
// latest plan sampled at the controller's time -> WbcReference (plan_reference.hpp) -> its
// WholeBodyController (built from the settings, reconfigured from new ones at a profile switch)
// -> τ_ff plus joint targets for the motors' PD (the settings' wbc_motor_kp/kd; the torques do
// the work, the PD acts within the tick where the controller cannot).
//
// The loop runs it in stand and walk whenever a plan exists; before the first plan (and during
// stand-up) the standing controller holds the robot. Everything is sized at construction;
// compute() allocates nothing.
//
// Per-level errors reported: the WBC's ‖A ξ − b‖ per paper priority (wbc/interface.hpp).
#pragma once

#include <memory>

#include "control/settings.hpp"
#include "control/types.hpp"
#include "locomotion/locomotion_planner.hpp"
#include "model/model.hpp"
#include "wbc/interface.hpp"
#include "wbc/whole_body_controller.hpp"

namespace ballast::control {

/// Joint j's motor command from the whole-body controller's output (model joint order, j in
/// 0..nj-1): τ_ff and the targets the motor's PD tracks with gains kp, kd.
inline backend::JointCommand motorCommand(const wbc::WbcOutput& out, int j, double kp, double kd) {
  backend::JointCommand c;
  c.tau_ff = out.jointTorque[j];
  c.q_des = out.jointPositionTarget[j];
  c.dq_des = out.jointVelocityTarget[j];
  c.kp = kp;
  c.kd = kd;
  return c;
}

class WalkingController {
 public:
  /// Throws model::ModelError when the contact frames are not in the model.
  WalkingController(const model::Model& model, const ControlSettings& settings);

  /// New settings (they outlive their use here); the controller takes their numbers without
  /// allocating. False when the whole-body controller could not take them (other contact
  /// frames): it keeps its old ones.
  bool setSettings(const ControlSettings& settings);
  /// True when there is a whole-body controller and `plan` is a valid plan.
  bool ready(const PlannerOutput* plan) const;

  /// One tick (ready() must hold). Returns the controller's status: kInvalidInput means the
  /// output holds no usable command (the caller damps).
  wbc::WbcStatus compute(const ControllerInput& in, ControllerOutput& out);

 private:
  const model::Model& model_;
  const ControlSettings* settings_;
  std::unique_ptr<wbc::WholeBodyController> wbc_;
  locomotion::PlanSampler sampler_;
  locomotion::PlanSample now_, ahead_;
  wbc::WbcState state_;
  wbc::WbcReference reference_;
  wbc::WbcOutput output_;
};

}  // namespace ballast::control
