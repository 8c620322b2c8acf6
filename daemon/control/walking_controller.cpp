#include "control/walking_controller.hpp"

#include "control/model_state.hpp"
#include "control/plan_reference.hpp"

namespace ballast::control {

WalkingController::WalkingController(const model::Model& model, const ControlSettings& settings)
    : model_(model),
      settings_(&settings),
      sampler_(model, locomotion::contactFrameIds(model, settings.locomotion)) {
  // Sized once; every settings' controller is for the same model and contact points (restart
  // keys), so these fit them all.
  if (settings.wbc) {
    state_ = settings.wbc->makeState();
    reference_ = settings.wbc->makeReference();
    output_ = settings.wbc->makeOutput();
  }
}

bool WalkingController::ready(const PlannerOutput* plan) const {
  return settings_->wbc && state_.q.size() == model_.nq && plan && plan->valid &&
         plan->plan.valid && plan->plan.nodes > 0;
}

wbc::WbcStatus WalkingController::compute(const ControllerInput& in, ControllerOutput& out) {
  // Accelerations fed forward: the plan's velocities differenced over this look-ahead.
  constexpr double kLookAhead = 0.005;  // s
  const locomotion::Plan& plan = in.plan->plan;
  sampler_.sample(plan, in.t, now_);
  sampler_.sample(plan, in.t + kLookAhead, ahead_);
  planToWbcReference(now_, ahead_, kLookAhead, model_.nj(), reference_);
  toModelState(model_, in.state, state_.q, state_.v);
  const wbc::WbcStatus status = settings_->wbc->update(state_, reference_, output_);
  const double kp = settings_->wbc_motor_kp, kd = settings_->wbc_motor_kd;
  for (int j = 0; j < model_.nj(); ++j) {
    out.joint[j] = motorCommand(output_, j, kp, kd);
    out.q_ref[j] = reference_.jointPosition[j];
  }
  for (int i = 0; i < kNumPriorityLevels; ++i) out.task_error[i] = output_.taskError[i];
  return status;
}

}  // namespace ballast::control
