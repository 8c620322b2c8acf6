#include "control/walking_controller.hpp"

#include "control/model_state.hpp"
#include "control/plan_reference.hpp"

namespace ballast::control {

WalkingController::WalkingController(const model::Model& model, const ControlSettings& settings)
    : model_(model),
      settings_(&settings),
      sampler_(model, locomotion::contactFrameIds(model, settings.locomotion)) {
  // Built and sized once: every later settings are for the same model and contact points
  // (restart keys), and setSettings() reconfigures the controller without allocating. Settings
  // that do not describe a controller (built by hand, without a profile) leave none: the
  // standing controller holds the robot.
  if (!wbc::validateSettings(settings.wbc, model)) {
    wbc_ = std::make_unique<wbc::WholeBodyController>(model, settings.wbc);
    state_ = wbc_->makeState();
    reference_ = wbc_->makeReference();
    output_ = wbc_->makeOutput();
  }
}

bool WalkingController::setSettings(const ControlSettings& settings) {
  settings_ = &settings;
  return !wbc_ || wbc_->setSettings(settings.wbc);
}

bool WalkingController::ready(const PlannerOutput* plan) const {
  return wbc_ && plan && plan->valid && plan->plan.valid && plan->plan.nodes > 0;
}

wbc::WbcStatus WalkingController::compute(const ControllerInput& in, ControllerOutput& out) {
  // Accelerations fed forward: the plan's velocities differenced over this look-ahead.
  constexpr double kLookAhead = 0.005;  // s
  const locomotion::Plan& plan = in.plan->plan;
  sampler_.sample(plan, in.t, now_);
  sampler_.sample(plan, in.t + kLookAhead, ahead_);
  planToWbcReference(now_, ahead_, kLookAhead, model_.nj(), reference_);
  reference_.pushStep = plan.pushStepping || plan.recovering;
  toModelState(model_, in.state, state_.q, state_.v);
  const wbc::WbcStatus status = wbc_->update(state_, reference_, output_);
  const double kp = settings_->wbc_motor_kp, kd = settings_->wbc_motor_kd;
  for (int j = 0; j < model_.nj(); ++j) {
    out.joint[j] = motorCommand(output_, j, kp, kd);
    out.q_ref[j] = reference_.jointPosition[j];
  }
  for (int i = 0; i < kNumPriorityLevels; ++i) out.task_error[i] = output_.taskError[i];
  const auto& force = output_.contactForce;
  for (int c = 0; c < kNumContacts; ++c)
    for (int k = 0; k < 3; ++k)
      out.contact_force[c][k] = 3 * c + k < force.size() ? force[3 * c + k] : kNaN;
  for (int c = 0; c < kNumContacts; ++c)
    for (int k = 0; k < 3; ++k) {
      out.contact_ref[c][k] = reference_.contactPosition(k, c);
      out.contact_position[c][k] = wbc_->contactPositions()(k, c);
    }
  return status;
}

}  // namespace ballast::control
