#include "control/mpc_planner.hpp"

#include <cmath>
#include <cstdio>
#include <utility>

#include "control/model_state.hpp"
#include "model/base_conventions.hpp"

namespace ballast::control {

MpcPlanner::MpcPlanner(const model::Model& model, const ControlSettings& settings,
                       std::shared_ptr<const terrain::HeightMap> terrain)
    : model_(model),
      terrain_(std::move(terrain)),
      settings_(settings.locomotion),
      posture_(model, settings),
      q_(Eigen::VectorXd::Zero(model.nq)),
      v_(Eigen::VectorXd::Zero(model.nv)),
      sampler_(model, locomotion::contactFrameIds(model, settings.locomotion)),
      map_tolerance_(settings.map_tolerance) {
  command_.standingJoints = Eigen::VectorXd::Zero(model.nj());
  // Built here for its checks (it throws on settings it cannot plan with), then let go: the
  // planner thread builds its own at its first plan, so that the SQP's worker team is started
  // from that thread and has its priority. Destroying a team started here, at normal priority,
  // from the real-time planner thread waits for its workers to be scheduled to exit: 80 ms on
  // a loaded host, and the first plan after standing up came too late (safety.max_plan_age).
  rebuild();
  planner_.reset();
}

void MpcPlanner::rebuild() {
  planner_ = std::make_unique<locomotion::LocomotionPlanner>(model_, settings_, terrain_);
  walking_ = false;
  planned_ = false;
  have_previous_ = false;
}

void MpcPlanner::predict(double t, double lead) {
  sampler_.sample(previous_, t, at_t_);
  sampler_.sample(previous_, t + lead, at_lead_);
  // World-frame increments of the plan over the lead, applied to the measured state.
  const Eigen::Matrix3d R0 = model::rotationFromZyx<double>(at_t_.baseZyx);
  const Eigen::Matrix3d R1 = model::rotationFromZyx<double>(at_lead_.baseZyx);
  const Eigen::Vector4d quat = q_.segment<4>(3);
  const Eigen::Matrix3d R = model::quaternionToRotation<double>(quat.data());
  const Eigen::Matrix3d Rnext = R1 * R0.transpose() * R;
  const Eigen::Vector3d v = R * v_.head<3>() + at_lead_.baseLinearVelocity - at_t_.baseLinearVelocity;
  const Eigen::Vector3d w =
      R * v_.segment<3>(3) + at_lead_.baseAngularVelocity - at_t_.baseAngularVelocity;
  q_.head<3>() += at_lead_.basePosition - at_t_.basePosition;
  q_.segment<4>(3) = model::quaternionXyzwFromRotation(Rnext);
  v_.head<3>().noalias() = Rnext.transpose() * v;
  v_.segment<3>(3).noalias() = Rnext.transpose() * w;
  for (int j = 0; j < model_.nj(); ++j) {
    q_[model::Model::qIndexOfJoint(j)] += at_lead_.jointPositions[j] - at_t_.jointPositions[j];
    v_[model::Model::vIndexOfJoint(j)] += at_lead_.jointVelocities[j] - at_t_.jointVelocities[j];
  }
}

void MpcPlanner::requestSettings(SettingsPtr settings) {
  std::lock_guard<std::mutex> lock(pending_mutex_);
  pending_.swap(settings);  // a request not yet taken goes outside the lock
}

void MpcPlanner::setTerrain(std::shared_ptr<const terrain::HeightMap> terrain,
                            std::uint64_t scan, std::uint64_t handoff_ns) {
  terrain_.publish(std::move(terrain), scan, handoff_ns);
}

void MpcPlanner::plan(const PlannerInput& input, PlannerOutput& output) {
  terrain_.refresh(input.map_scan);
  const bool walk = input.mode == Mode::kWalk;
  const bool built = !planner_;
  if (built) rebuild();
  if (input.restart || !walking_) {
    SettingsPtr next;
    {
      std::lock_guard<std::mutex> lock(pending_mutex_);
      next = std::move(pending_);
    }
    if (next) {
      settings_ = next->locomotion;
      map_tolerance_ = next->map_tolerance;
      posture_.setNominal(*next);
      rebuild();
    } else if (input.restart && !built) {
      rebuild();
    }
  }
  terrain_.checkUnderFeet(input.state, map_tolerance_);
  output.map_agrees = terrain_.agrees();
  output.map_disagreement = terrain_.disagreement();
  const bool fresh = !planned_;
  toModelState(model_, input.state, q_, v_);
  const BaseCommand& c = input.command;
  locomotion::LocomotionCommand& command = command_;
  command.walk = walk;
  const bool moving = walk && c.velocity_active;
  command.vx = moving ? c.vx : 0.0;
  command.vy = moving ? c.vy : 0.0;
  command.yawRate = moving ? c.yaw_rate : 0.0;
  command.height = c.height > 0.0 ? c.height : posture_.nominalHeight();
  command.roll = c.roll;
  command.pitch = c.pitch;
  command.yaw = c.yaw;
  posture_.solve(command.height, c.roll, c.pitch, c.yaw, 5, command.standingJoints.data());
  planner_->setExternalForce(Eigen::Vector3d(input.state.external_force));
  planner_->setIterationBudget(input.iteration_budget);

  // The plan starts where it will be used (see the header comment); a fresh one, with nothing
  // to predict from, at the measured state.
  const double lead = have_previous_ && !fresh ? input.lead : 0.0;
  if (lead > 0.0) predict(input.t, lead);
  const double t = input.t + lead;
  lead_ = lead;
  output.t = t;
  output.message[0] = '\0';
  // A fresh planner starts its SQP from the references, not from a previous solution: one
  // real-time iteration from there is no plan to act on. Converge it first.
  for (int i = 0; fresh && i < kFreshIterations; ++i)
    planner_->update(t, q_, v_, command, output.plan);
  output.valid = planner_->update(t, q_, v_, command, output.plan);
  planned_ = output.valid;
  if (!output.valid) {
    copyText(output.message, planner_->statistics().message.c_str());
    return;
  }
  // Walking until the plan stands again (the planner keeps stepping while it slows down).
  walking_ = output.plan.walking;
  const locomotion::Plan& p = output.plan;
  for (int k = 0; k <= p.nodes; ++k) {
    bool finite = Eigen::Map<const Eigen::VectorXd>(p.x[k], p.nx).allFinite();
    if (k < p.nodes) finite = finite && Eigen::Map<const Eigen::VectorXd>(p.u[k], p.nu).allFinite();
    if (!finite) {
        output.valid = false;
        std::snprintf(output.message, sizeof(output.message),
                      "the MPC solution has a non-finite value at node %d", k);
        return;
    }
  }
  previous_ = output.plan;
  have_previous_ = true;
}

void MpcPlanner::prepare(double t) {
  if (planner_ && planned_) planner_->prepare(t + lead_);
}

}  // namespace ballast::control
