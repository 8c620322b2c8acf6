#include "locomotion/locomotion_planner.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "gait/cadence.hpp"
#include "model/algorithms.hpp"

namespace ballast::locomotion {

using model::CentroidalLayout;

std::array<int, kNumContacts> contactFrameIds(const model::Model& model,
                                              const LocomotionSettings& settings) {
  std::array<int, kNumContacts> ids{};
  for (int c = 0; c < kNumContacts; ++c) ids[c] = model.frameId(settings.contactFrames[c]);
  return ids;
}

namespace {

/// Q and R from the physical weights.
void fillWeights(const model::Model& model, const LocomotionSettings& s, mpc::ProblemSettings& p) {
  const CentroidalLayout L{model.nj(), kNumContacts};
  const double m = model.totalMass();
  const CostWeights& w = s.weights;
  p.stateWeights.resize(L.nx());
  p.stateWeights.segment<3>(0).setConstant(w.linearVelocity / (m * m));
  p.stateWeights.segment<3>(3).setConstant(w.angularMomentum / (m * m));
  p.stateWeights.segment<3>(L.kBasePosition) = w.basePosition;
  p.stateWeights.segment<3>(L.kBaseZyx) = w.baseOrientation;
  const int soles = mpc::KinodynamicProblem::soleMoments(p);
  p.inputWeights.resize(L.nu() + soles);
  p.inputWeights.head(3 * kNumContacts).setConstant(w.force);
  for (int j = 0; j < model.nj(); ++j) {
    p.stateWeights[L.kJoints + j] = s.armJoint[j] ? w.armJoint : w.legJoint;
    p.inputWeights[L.jointVelocity() + j] = s.armJoint[j] ? w.armJointVelocity : w.legJointVelocity;
  }
  // A sole's moment m is what a force of 2m/w at its edge exerts: weighted as that force.
  if (soles > 0) p.inputWeights.tail(soles).setConstant(w.force * 4.0 / (p.soleWidth * p.soleWidth));
}

gait::VelocityCommand planarCommand(const LocomotionCommand& c) {
  return c.walk ? gait::VelocityCommand{c.vx, c.vy, c.yawRate} : gait::VelocityCommand{};
}

/// Heading of the feet: the mean toe-minus-heel direction.
double feetHeading(const std::array<Eigen::Vector3d, kNumContacts>& p) {
  const Eigen::Vector3d d = (p[0] - p[1]) + (p[2] - p[3]);
  return std::atan2(d.y(), d.x());
}

}  // namespace

LocomotionPlanner::LocomotionPlanner(const model::Model& model, const LocomotionSettings& settings,
                                     const gait::TerrainQuery& terrain)
    : model_(model),
      settings_(settings),
      terrain_(terrain),
      frames_(contactFrameIds(model, settings)),
      data_(model),
      swings_(settings.swing, {}) {
  if (settings_.nominalJoints.size() != model.nj() ||
      static_cast<int>(settings_.armJoint.size()) != model.nj())
    throw std::invalid_argument("locomotion settings: nominal posture and joint groups need " +
                                std::to_string(model.nj()) + " joints");
  if (settings_.sqp.nodes > kMaxNodes || model.nj() > kMaxJoints)
    throw std::invalid_argument("locomotion settings: at most " + std::to_string(kMaxNodes) +
                                " MPC nodes and " + std::to_string(kMaxJoints) + " joints");
  fillWeights(model, settings_, settings_.problem);
  // The nominal stance: contact points relative to the base at the nominal posture.
  Eigen::VectorXd q = model::neutralConfiguration(model);
  q.tail(model.nj()) = settings_.nominalJoints;
  model::forwardKinematics(model, data_, q);
  double sole = 0.0;
  for (int c = 0; c < kNumContacts; ++c) {
    stance_[c] = model::framePlacement(model, data_, frames_[c]).p;
    sole += stance_[c].z() / kNumContacts;
    stance_[c].z() = 0.0;
  }
  // The pendulum of the capture point: the centre of mass above the soles in the nominal posture.
  model::compositeWorldInertias(model, data_);
  settings_.swing.foothold.comHeight = data_.com.z() - sole;
  swings_ = gait::SwingPlanner(settings_.swing, stance_);
  if (settings_.model == PlannerModel::kSingleRigidBody) {
    mpc::ProblemSettings p = settings_.problem;
    const int n = mpc::SingleRigidBodyProblem::kStateSize, m = mpc::SingleRigidBodyProblem::kInputSize;
    p.stateWeights = settings_.problem.stateWeights.head(n);
    p.inputWeights = settings_.problem.inputWeights.head(m);
    problem_ = std::make_unique<mpc::SingleRigidBodyProblem>(
        nominalBody(model, settings_.nominalJoints), p);
  } else {
    problem_ = std::make_unique<mpc::KinodynamicProblem>(model, frames_, settings_.problem);
  }
  sqp_ = std::make_unique<mpc::SqpSolver>(*problem_, settings_.sqp);
}

LocomotionPlanner::~LocomotionPlanner() = default;

mpc::RigidBody LocomotionPlanner::nominalBody(const model::Model& model,
                                              const Eigen::VectorXd& nominalJoints) {
  model::Data<double> data(model);
  Eigen::VectorXd q = model::neutralConfiguration(model);  // base at the origin: world = base
  q.tail(model.nj()) = nominalJoints;
  model::forwardKinematics(model, data, q);
  model::compositeWorldInertias(model, data);
  mpc::RigidBody body;
  body.mass = model.totalMass();
  body.inertia = data.oYcrb[0].inertiaAboutCom();
  body.com = data.com;
  body.gravity = model.gravity;
  return body;
}

Eigen::VectorXd LocomotionPlanner::measuredState(const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
  const CentroidalLayout L{model_.nj(), kNumContacts};
  model::ccrba(model_, data_, q, v);
  Eigen::Vector3d zyx = model::zyxFromRotation(model::quaternionToRotation<double>(q.segment<4>(3)));
  if (haveYaw_) zyx[0] = lastYaw_ + std::remainder(zyx[0] - lastYaw_, 2.0 * M_PI);
  lastYaw_ = zyx[0];
  haveYaw_ = true;
  Eigen::VectorXd x(L.nx());
  x << data_.hg, q.head<3>(), zyx, q.tail(model_.nj());
  return x;
}

LocomotionCommand LocomotionPlanner::slewed(double t, const LocomotionCommand& operatorCommand) {
  const double dt = velocityTime_ < 0.0 ? 0.0 : std::clamp(t - velocityTime_, 0.0, 0.1);
  velocityTime_ = t;
  const bool walk = operatorCommand.walk;
  auto toward = [dt](double& value, double target, double rate) {
    value += std::clamp(target - value, -rate * dt, rate * dt);
  };
  // The base starts moving when the feet do (walkStartDelay): a reference that left earlier
  // would have to be caught up with, faster than commanded.
  const bool moving = walk && t >= walkStartsAt_ - 1e-9;
  const double targetVx = moving ? operatorCommand.vx : 0.0;
  const double targetVy = moving ? operatorCommand.vy : 0.0;
  const double targetYawRate = moving ? operatorCommand.yawRate : 0.0;
  toward(velocity_.vx, targetVx, settings_.maxAcceleration);
  toward(velocity_.vy, targetVy, settings_.maxAcceleration);
  toward(velocity_.yawRate, targetYawRate, settings_.maxYawAcceleration);
  accelerating_ = std::abs(velocity_.vx - targetVx) > 1e-9 || std::abs(velocity_.vy - targetVy) > 1e-9 ||
                  std::abs(velocity_.yawRate - targetYawRate) > 1e-9;
  LocomotionCommand c = operatorCommand;
  c.vx = velocity_.vx;
  c.vy = velocity_.vy;
  c.yawRate = velocity_.yawRate;
  // Keep stepping while the base still moves at the commanded velocity, and stopDelay longer:
  // the steps that take out what the body still carries.
  const bool commanded = std::abs(c.vx) > 1e-6 || std::abs(c.vy) > 1e-6 || std::abs(c.yawRate) > 1e-6;
  if (commanded) lastCommandedMotion_ = t;
  c.walk = walk || commanded || recovering_ ||
           (walking_ && t < lastCommandedMotion_ + settings_.stopDelay);
  return c;
}

void LocomotionPlanner::updateRecovery(double t, bool operatorWalks, const gait::GaitState& state,
                                       double yaw) {
  if (operatorWalks) {  // the operator's walk takes over the steps
    recovering_ = recoveryActive_ = false;
    updatePushSteps(t, state);
    return;
  }
  pushStepping_ = false;
  const gait::SupportCheck support =
      gait::supportCheck(state.contactPositions, state.com.head<2>(), state.comVelocity.head<2>(),
                         state.externalForce.head<2>(), state.mass, swings_.omega());
  // Only from standing: the last steps of a stop are the paper's footholds' to take (walking
  // stays the paper's controller), and a recovery that is ending finishes its step first.
  const bool standing = !schedule_.latestGait().walking && !schedule_.gaitAt(t).walking;
  if (!recovering_ && recoveryActive_ && gait::needsStep(support, settings_.recovery)) {
    recovering_ = true;  // still stepping after a recovery that was ending: on in the same order
  } else if (!recovering_ && standing && gait::needsStep(support, settings_.recovery)) {
    recovering_ = recoveryActive_ = true;
    // The foot on the side the point left to first, at once (no walkStartDelay: the double
    // support that begins the cycle shifts the weight).
    recoveryGait_ = settings_.walkGait;
    const bool left = gait::leftFootFirst(support.point, state.contactPositions, yaw);
    recoveryGait_.rightFirst = !left;
    const int toe = left ? gait::kRightToe : gait::kLeftToe;
    const int heel = left ? gait::kRightHeel : gait::kLeftHeel;
    recoveryGait_.period = gait::recoveryPeriod(
        support.point, state.contactPositions[toe].head<2>(), state.contactPositions[heel].head<2>(),
        yaw, left, settings_.swing.limits, swings_.omega(), settings_.walkGait.period,
        settings_.recovery.minPeriod);
  } else if (recovering_ && gait::recovered(support, state.comVelocity.head<2>().norm(),
                                            settings_.recovery)) {
    recovering_ = false;
  }
}

void LocomotionPlanner::updatePushSteps(double t, const gait::GaitState& state) {
  // The paper's footholds answer a velocity error with k (v - v_des), a quarter of what a step
  // must do to catch the body, and see no push: 60 N for 1 s felled the walking robot at every
  // phase. The capture point's steps catch it, but they walk worse undisturbed (README, Pushes),
  // so they take over only while a push lasts. Handing back waits for a double support: a swing
  // the capture point re-aimed on its way has no cubic of the paper's from its lift-off.
  const double limit = settings_.recovery.walkingPushForce(state.mass);
  const double push = state.externalForce.head<2>().norm();
  if (limit <= 0.0) {
    pushStepping_ = false;
    return;
  }
  if (push > limit) {
    pushStepping_ = true;
    pushDirection_ = state.externalForce.head<2>() / push;
  }
  if (push > 0.5 * limit) lastPushTime_ = t;
  const bool doubleSupport = gait::numStance(schedule_.flagsAt(t)) == kNumContacts;
  if (pushStepping_ && doubleSupport && t > lastPushTime_ + schedule_.gaitAt(t).period)
    pushStepping_ = false;
}

bool LocomotionPlanner::update(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                               const LocomotionCommand& operatorCommand, Plan& plan) {
  // Walking from standing starts walkStartDelay later, so the plan has time to shift the weight
  // onto the first stance foot before the other one lifts.
  const bool starting = operatorCommand.walk && !schedule_.latestGait().walking;
  if (starting) walkStartsAt_ = t + settings_.walkStartDelay;
  const Eigen::VectorXd x = measuredState(q, v);  // also leaves FK and composite inertias in data_
  const Eigen::Matrix3d R = model::quaternionToRotation<double>(q.segment<4>(3));
  const Eigen::Vector3d baseVelocity = R * v.head<3>();
  gait::GaitState gaitState;
  gaitState.t = t;
  gaitState.baseVelocity = baseVelocity;
  gaitState.com = data_.com;
  gaitState.comVelocity = data_.hg.head<3>() / model_.totalMass();
  gaitState.mass = model_.totalMass();
  gaitState.externalForce = externalForce_;
  for (int c = 0; c < kNumContacts; ++c)
    gaitState.contactPositions[c] = model::framePlacement(model_, data_, frames_[c]).p;
  updateRecovery(t, operatorCommand.walk, gaitState, x[CentroidalLayout::kBaseZyx]);
  const LocomotionCommand command = slewed(t, operatorCommand);
  const gait::PlanarPose start =
      referenceStart(t, x, command, feetHeading(gaitState.contactPositions));
  // Footholds: the hip at touch-down predicted from where the base is, moved towards the
  // reference base by at most footholdLead, at the commanded velocity; the measured velocity
  // enters through the capture-point term. From the reference base itself (a lead of up to
  // maxPositionLead), a robot behind its reference — pushed back, or slower than the command —
  // is asked for steps longer by the whole lead, which it takes by crouching, and one ahead of
  // it — pushed forward, stopping — for steps too short to stop it: it fell over them. From the
  // base alone nothing brings a position error back, and the plan keeps walking off it.
  gaitState.base.position = x.segment<3>(CentroidalLayout::kBasePosition);
  gaitState.base.yaw = start.yaw;
  Eigen::Vector3d lead = start.position - gaitState.base.position;
  lead.z() = 0.0;
  if (lead.norm() > settings_.footholdLead) lead *= settings_.footholdLead / lead.norm();
  gaitState.base.position += lead;

  // Gait: walking or standing, changed only where the schedule allows. Walking on keeps the foot
  // order in force (a recovery may have begun with the right foot), so the feet alternate.
  const double horizon = settings_.sqp.nodes * settings_.sqp.dt;  // the MPC's, s
  gait::Gait next;  // the gait asked of the schedule
  if (recovering_) {
    next = recoveryGait_;
  } else if (command.walk) {
    // Faster, shorter cycles (gait/cadence.hpp), at the commanded speed as it slews.
    next = gait::gaitAtSpeed(settings_.walkGait, std::hypot(command.vx, command.vy),
                             settings_.swing.limits.maxForward, settings_.maxSwingSpeed);
    if (schedule_.latestGait().walking) next.rightFirst = schedule_.latestGait().rightFirst;
    // Step timing, walking on the capture point's footholds: a step the capture point asks
    // beyond the step limits (a push) comes sooner, and so does the one after it. The period is
    // the longest (from the gait's own down to recovery.minPeriod) at which the next two steps
    // are within the limits, tried on copies of the schedule and the swings: each update asks
    // it afresh, whatever gait is in force (testing the limits on the gait in force switched it
    // back and forth: the short gait brings the steps within the limits, the long one is then
    // asked again). A shorter cycle is taken only as far as its next two swings keep to
    // gait.max_swing_speed, the double support shortened first (gait::fitSwing): a step held
    // to the limits is up to twice the longest step from lift-off to touch-down whatever the
    // cycle, so a shorter cycle asks its swing foot for more speed, not for a shorter step.
    // Traced, 90 N along +x at 0.5 m/s: the 0.6 s cycle's swings of 1.0 m in 0.24 s (4.2 m/s;
    // walking keeps 3.1) fell behind their path, the swing leg folded (its knee past its range,
    // the foot 0.8 m up) and the robot fell.
    const gait::Gait& inForce = schedule_.latestGait();
    if (swings_.parameters().rule == gait::FootholdRule::kCapturePoint &&
        (swings_.stepsLimited() ||
         (inForce.walking && (inForce.period < next.period ||
                              inForce.doubleSupport < next.doubleSupport)))) {
      const double longest = next.period;
      const double shortest = std::min(settings_.recovery.minPeriod, longest);
      constexpr double kPeriodStep = 0.05;  // s between the periods tried
      const gait::Gait walk = next;
      for (double p = longest;; p -= kPeriodStep) {
        gait::Gait trial = walk;
        trial.period = std::max(p, shortest);
        gait::ContactSchedule schedule = schedule_;
        schedule.setGait(trial, starting ? walkStartsAt_ : t);
        gait::SwingPlanner swings = swings_;
        swings.update(schedule, gaitState, planarCommand(command), horizon, terrain_);
        // The touch-downs, and with them the footholds, do not move with the double support.
        const bool swingFits =
            gait::fitSwing(trial, swings.longestNextSwing(t), settings_.maxSwingSpeed);
        if (!swingFits && trial.period < longest) break;  // the previous cycle (next) stays
        next = trial;
        if (!swings.stepsLimited() || trial.period <= shortest + 1e-9) break;
      }
    }
  }
  schedule_.setGait(next, starting ? walkStartsAt_ : t);
  if (recoveryActive_ && !recovering_ && !schedule_.gaitAt(t).walking) recoveryActive_ = false;
  // Recovery steps take the capture point's footholds whatever the profile's rule is: they are
  // what the steps are for.
  gait::SwingPlannerParameters swing = settings_.swing;
  if ((recoveryActive_ && !operatorCommand.walk) || pushStepping_)
    swing.rule = gait::FootholdRule::kCapturePoint;
  // Handed over from the paper's footholds: across a push along the walk, the paper's keep them.
  if (pushStepping_ && operatorCommand.walk && settings_.swing.rule == gait::FootholdRule::kPaper)
    swing.walkingPush = gait::walkingPushAxis(
        pushDirection_,
        gait::fromHeading(Eigen::Vector2d(command.vx, command.vy), gaitState.base.yaw));
  swings_.setParameters(swing);
  swings_.update(schedule_, gaitState, planarCommand(command), horizon, terrain_);

  fillReferences(t, start, command);
  bool ok;
  if (settings_.model == PlannerModel::kSingleRigidBody) {
    // The rigid body's own rotation: the base's angular velocity through the body's inertia.
    // The centroidal angular momentum would count the swinging legs' as the body's turning.
    Eigen::VectorXd xs = x.head(problem_->nx());
    const mpc::RigidBody& body = static_cast<const mpc::SingleRigidBodyProblem&>(*problem_).body();
    xs.segment<3>(3) = R * body.inertia * v.segment<3>(3);
    ok = sqp_->solve(t, xs, iterationBudget_);
  } else {
    ok = sqp_->solve(t, x, iterationBudget_);
  }
  if (!ok) return false;

  const mpc::MpcSolution& s = sqp_->solution();
  plan.valid = true;
  plan.t0 = s.t0;
  plan.dt = s.dt;
  plan.nodes = s.nodes();
  // In the kino-dynamic layout whatever the problem: a single rigid body's joints stay at the
  // nominal posture, not moving.
  const CentroidalLayout L{model_.nj(), kNumContacts};
  plan.nx = L.nx();
  plan.nu = L.nu();
  const int nx = problem_->nx(), nu = problem_->nu();
  for (int k = 0; k <= plan.nodes; ++k) {
    Eigen::Map<Eigen::VectorXd> xk(plan.x[k], plan.nx);
    xk.head(nx) = s.x[k];
    if (nx < plan.nx) xk.tail(plan.nx - nx) = settings_.nominalJoints;
  }
  // The kino-dynamic layout's inputs: the soles' moments after them stay in the MPC (the
  // whole-body controller's standing feet do not roll; kinodynamic_problem.hpp).
  const int shared = std::min(nu, plan.nu);
  for (int k = 0; k < plan.nodes; ++k) {
    Eigen::Map<Eigen::VectorXd> uk(plan.u[k], plan.nu);
    uk.head(shared) = s.u[k].head(shared);
    uk.tail(plan.nu - shared).setZero();
  }
  plan.schedule = schedule_;
  plan.swings = swings_;
  plan.walking = command.walk;
  plan.recovering = recoveryActive_ && !operatorCommand.walk;
  plan.pushStepping = pushStepping_ && operatorCommand.walk;
  for (int c = 0; c < kNumContacts; ++c) {
    const Eigen::Vector3d& p = gaitState.contactPositions[c];
    const gait::SwingTrajectory* swing = swings_.swingAt(c, t);
    plan.supportHeight[c] = swing ? swing->touchDownPosition.z() : terrain_.height(p.x(), p.y());
  }
  return true;
}

gait::PlanarPose LocomotionPlanner::referenceStart(double t, const Eigen::VectorXd& x,
                                                  const LocomotionCommand& command,
                                                  double feetYaw) {
  // Where the base reference starts: walking, the commanded pose; standing, over the feet.
  gait::PlanarPose start;
  start.position = x.segment<3>(CentroidalLayout::kBasePosition);
  const double yaw = x[CentroidalLayout::kBaseZyx];
  const Eigen::Vector2d measured = start.position.head<2>();
  if (command.walk) {
    // From where the base is, along its heading: when walking starts, and while the commanded
    // velocity changes — a lead gathered then (the robot cannot follow a velocity ramp exactly)
    // would be made up afterwards by walking faster than commanded.
    // Recovering, too: the body goes where the push took it, the steps are what stop it.
    if (!walking_ || accelerating_ || recovering_) {
      heading_ = yaw;
      position_ = measured;
    } else {
      gait::PlanarPose advanced;
      advanced.position << position_, 0.0;
      advanced.yaw = heading_;
      advanced = advanced.predicted(planarCommand(command), std::max(0.0, t - commandTime_));
      heading_ = advanced.yaw;
      // Walking on the capture point's footholds for a push, likewise for the position (the
      // heading stays the operator's): a reference left on the path, up to maxPositionLead
      // behind the body, has the plan pull the body back against the push and the steps.
      position_ = pushStepping_ ? measured : Eigen::Vector2d(advanced.position.head<2>());
    }
    const Eigen::Vector2d lead = position_ - measured;
    if (lead.norm() > settings_.maxPositionLead)
      position_ = measured + lead * (settings_.maxPositionLead / lead.norm());
    start.position.head<2>() = position_;
    start.yaw = yaw + std::remainder(heading_ - yaw, 2.0 * M_PI);
  } else {
    Eigen::Vector3d feet = Eigen::Vector3d::Zero(), nominal = Eigen::Vector3d::Zero();
    for (int c = 0; c < kNumContacts; ++c) {
      feet += model::framePlacement(model_, data_, frames_[c]).p / kNumContacts;
      nominal += stance_[c] / kNumContacts;
    }
    start.yaw = yaw + std::remainder(feetYaw + command.yaw - yaw, 2.0 * M_PI);
    const double cy = std::cos(feetYaw), sy = std::sin(feetYaw);
    start.position.head<2>() =
        feet.head<2>() - Eigen::Vector2d(cy * nominal.x() - sy * nominal.y(),
                                         sy * nominal.x() + cy * nominal.y());
  }
  walking_ = command.walk;
  commandTime_ = t;
  return start;
}

void LocomotionPlanner::fillReferences(double t, const gait::PlanarPose& start,
                                       const LocomotionCommand& command) {
  const CentroidalLayout L{model_.nj(), kNumContacts};
  const double m = model_.totalMass();
  const double dt = settings_.sqp.dt;
  const double izz = data_.oYcrb[0].inertiaAboutCom()(2, 2);
  const double height = command.height > 0.0 ? command.height : settings_.nominalHeight;
  const gait::VelocityCommand velocity = planarCommand(command);
  // Turning, the body leans into the turn as the inverted pendulum does: the centre of mass
  // accelerates by w x v, and the line from the centre of pressure up to it tilts by
  // atan(|w x v| / g). Held upright (the paper's reference), the body rolled outwards by about
  // that angle (0.05 rad at 1.0 m/s and 0.4 rad/s), and at 1.2 m/s it fell. Heading frame:
  // w x v = (-w vy, w vx); a positive pitch leans forward, a positive roll to the right.
  const double g = -model_.gravity.z();
  const double leanPitch = std::atan(-velocity.yawRate * velocity.vy / g);
  const double leanRoll = -std::atan(velocity.yawRate * velocity.vx / g);

  auto& refs = sqp_->references();
  for (int k = 0; k <= settings_.sqp.nodes; ++k) {
    const double tk = t + k * dt;
    mpc::NodeReference& r = refs[k];
    const gait::ContactFlags flags = schedule_.flagsAt(tk);
    // The ground the feet stand on at t_k (a swinging point: where it lands), which the base's
    // height is above: stepping onto a stage, the terrain under the base put the base over the
    // floor with a foot already on the stage, that leg crouched by the whole step (its knee and
    // hip at the torque limits when the other foot lifted), and rose by it when the base passed
    // the edge. On flat ground both are the same.
    double support = 0.0;
    for (int c = 0; c < kNumContacts; ++c) {
      r.stance[c] = flags[c];
      // At the interval's middle, where the problems evaluate the swing and the lever arms.
      const gait::PointReference p = swings_.reference(c, tk + 0.5 * dt);
      r.contactPosition[c] = p.position;
      if (!flags[c]) {
        r.swingPosition[c] = p.position;
        r.swingVelocity[c] = p.velocity;
      }
      const gait::SwingTrajectory* swing = swings_.swingAt(c, tk);
      const Eigen::Vector3d& at = swing ? swing->touchDownPosition : p.position;
      support += terrain_.height(at.x(), at.y()) / kNumContacts;
    }
    const gait::PlanarPose pose = start.predicted(velocity, k * dt);
    const double cy = std::cos(pose.yaw), sy = std::sin(pose.yaw);
    const Eigen::Vector3d vWorld(cy * velocity.vx - sy * velocity.vy,
                                 sy * velocity.vx + cy * velocity.vy, 0.0);
    r.x.segment<3>(0) = m * vWorld;
    r.x.segment<3>(3) = Eigen::Vector3d(0.0, 0.0, izz * velocity.yawRate);
    r.x.segment<3>(L.kBasePosition) =
        Eigen::Vector3d(pose.position.x(), pose.position.y(), support + height);
    r.x.segment<3>(L.kBaseZyx) =
        Eigen::Vector3d(pose.yaw, command.pitch + leanPitch, command.roll + leanRoll);
    if (r.x.size() == L.nx())  // the single rigid body has no joints
      r.x.segment(L.kJoints, model_.nj()) =
          !command.walk && command.standingJoints.size() == model_.nj() ? command.standingJoints
                                                                         : settings_.nominalJoints;
    // The push in the dynamics goes with the capture point's footholds: with the paper's, the
    // estimate's model errors (10-20 N walking at 1 m/s) made walking fall.
    r.externalForce = swings_.parameters().rule == gait::FootholdRule::kCapturePoint
                          ? externalForce_
                          : Eigen::Vector3d::Zero();
    weightOnStance(flags, r.u);
  }
}

void LocomotionPlanner::weightOnStance(const gait::ContactFlags& flags, Eigen::VectorXd& u) const {
  const double m = model_.totalMass();
  const double g = -model_.gravity.z();
  int stanceCount = 0;
  for (int c = 0; c < kNumContacts; ++c) stanceCount += flags[c];
  u.setZero();
  for (int c = 0; c < kNumContacts; ++c)
    if (flags[c]) u[CentroidalLayout::force(c) + 2] = m * g / stanceCount;
}

void LocomotionPlanner::prepare(double t) {
  // The references as the next update() sets them if the contact schedule holds: their modes
  // and forces, all the SQP's preparation reads.
  auto& refs = sqp_->references();
  for (int k = 0; k <= settings_.sqp.nodes; ++k) {
    const gait::ContactFlags flags = schedule_.flagsAt(t + k * settings_.sqp.dt);
    std::copy(flags.begin(), flags.end(), refs[k].stance.begin());
    weightOnStance(flags, refs[k].u);
  }
  sqp_->prepare(t);
}

PlanSampler::PlanSampler(const model::Model& model,
                         const std::array<int, kNumContacts>& contactFrames)
    : model_(model),
      frames_(contactFrames.begin(), contactFrames.end()),
      data_(model),
      x_(CentroidalLayout{model.nj(), kNumContacts}.nx()),
      u_(CentroidalLayout{model.nj(), kNumContacts}.nu()),
      xdot_(CentroidalLayout{model.nj(), kNumContacts}.nx()) {}

void PlanSampler::sample(const Plan& plan, double t, PlanSample& out) {
  const CentroidalLayout L{model_.nj(), kNumContacts};
  double s = std::clamp((t - plan.t0) / plan.dt, 0.0, static_cast<double>(plan.nodes));
  if (std::abs(s - std::round(s)) < 1e-6) s = std::round(s);  // on a node: that node's input
  const int k = std::min(static_cast<int>(std::floor(s)), plan.nodes - 1);
  const double a = s - k;
  x_ = (1.0 - a) * Eigen::Map<const Eigen::VectorXd>(plan.x[k], plan.nx) +
       a * Eigen::Map<const Eigen::VectorXd>(plan.x[k + 1], plan.nx);
  // Inputs interpolated between nodes too (as OCS2's controllers read a policy): joint
  // velocities, forces and the base velocity they imply change at the rate the plan asks for,
  // (u_k+1 − u_k)/dt, from the node on, instead of jumping at the next node — a jump that the
  // base and arm acceleration references (differences over a few ms) would turn into spikes.
  // The controller reads a plan only in its first planner period, from its node 0 on.
  // Not across a change of contact mode: a point's force and the joint velocities that keep
  // the stance points still jump there by design (touch-down, lift-off).
  const int i = std::min(k, std::max(plan.nodes - 2, 0));
  const bool sameMode = plan.schedule.flagsAt(plan.t0 + i * plan.dt) ==
                        plan.schedule.flagsAt(plan.t0 + (i + 1) * plan.dt);
  const double b = plan.nodes > 1 && sameMode ? std::clamp(s - i, 0.0, 1.0) : 0.0;
  u_ = (1.0 - b) * Eigen::Map<const Eigen::VectorXd>(plan.u[i], plan.nu);
  if (b > 0.0) u_ += b * Eigen::Map<const Eigen::VectorXd>(plan.u[i + 1], plan.nu);
  model::centroidalDynamics(model_, data_, frames_, x_, u_, xdot_);

  const Eigen::Vector3d zyx = x_.segment<3>(L.kBaseZyx);
  out.momentum = x_.head<6>();
  out.basePosition = x_.segment<3>(L.kBasePosition);
  out.baseZyx = zyx;
  out.baseLinearVelocity = xdot_.segment<3>(L.kBasePosition);
  out.baseAngularVelocity =
      model::zyxRateToAngularVelocity<double>(zyx) * xdot_.segment<3>(L.kBaseZyx);
  for (int j = 0; j < model_.nj(); ++j) {
    out.jointPositions[j] = x_[L.kJoints + j];
    out.jointVelocities[j] = u_[L.jointVelocity() + j];
  }
  const gait::ContactFlags flags = plan.schedule.flagsAt(t);
  for (int c = 0; c < kNumContacts; ++c) {
    out.stance[c] = flags[c];
    out.contactForce[c] = flags[c] ? Eigen::Vector3d(u_.segment<3>(L.force(c))) : Eigen::Vector3d::Zero();
    out.contact[c] = plan.swings.reference(c, t);
  }
}

}  // namespace ballast::locomotion
