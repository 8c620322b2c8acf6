#include "profile/locomotion_settings.hpp"

#include <algorithm>
#include <cmath>

namespace ballast::profile {

locomotion::LocomotionSettings locomotionSettings(const Profile& p, const model::Model& model,
                                                  const control::ControlSettings& control,
                                                  const wbc::WbcSettings& wbc,
                                                  double nominalHeight) {
  locomotion::LocomotionSettings s;
  const int nj = model.nj();
  for (int c = 0; c < locomotion::kNumContacts; ++c) s.contactFrames[c] = control.contact_frames[c];
  s.nominalJoints.resize(nj);
  s.armJoint.assign(nj, false);
  for (int j = 0; j < nj; ++j) {
    s.nominalJoints[j] = control.nominal_q[j];
    const std::string& name = model.jointName[j + 1];
    s.armJoint[j] = std::find(wbc.jointSpaceJoints.begin(), wbc.jointSpaceJoints.end(), name) !=
                    wbc.jointSpaceJoints.end();
  }
  s.nominalHeight = nominalHeight;
  s.maxPositionLead = p.number("planner.max_position_lead");
  s.maxAcceleration = p.number("planner.max_acceleration");
  s.maxYawAcceleration = p.number("planner.max_yaw_acceleration");
  s.walkStartDelay = p.number("gait.walk_start_delay");
  s.stopDelay = p.number("gait.stop_delay");
  s.footholdLead = p.number("gait.foothold_lead");

  s.walkGait.walking = true;
  s.walkGait.period = p.number("gait.period");
  s.walkGait.doubleSupport = p.number("gait.double_support");
  s.walkGait.toeOffLead = p.number("gait.toe_off_lead");
  s.swing.apexClearance = p.number("gait.swing_apex");
  s.swing.replanUntil = p.number("gait.replan_until");
  s.swing.stepHeight = p.number("gait.step_height");
  s.swing.stepLift = p.number("gait.step_lift");
  s.swing.minFeetDistance = p.number("gait.min_foot_distance");
  s.swing.foothold.feedbackGain = p.number("gait.foothold_gain");
  s.swing.foothold.nominalHeight = nominalHeight;
  s.swing.foothold.gravity = -model.gravity.z();

  locomotion::CostWeights& w = s.weights;
  w.linearVelocity = p.number("planner.q_linear_velocity");
  w.angularMomentum = p.number("planner.q_angular_momentum");
  const auto position = p.numbers("planner.q_base_position");
  const auto orientation = p.numbers("planner.q_base_orientation");
  for (int i = 0; i < 3; ++i) {
    w.basePosition[i] = position[i];
    w.baseOrientation[i] = orientation[i];
  }
  w.legJoint = p.number("planner.q_leg_joints");
  w.armJoint = p.number("planner.q_arm_joints");
  w.force = p.number("planner.r_forces");
  w.legJointVelocity = p.number("planner.r_leg_joint_velocities");
  w.armJointVelocity = p.number("planner.r_arm_joint_velocities");

  mpc::ProblemSettings& problem = s.problem;
  problem.terminalWeightScale = p.number("planner.terminal_weight_scale");
  problem.frictionCoefficient = p.number("planner.friction_coefficient");
  problem.minNormalForce = p.number("planner.min_normal_force");
  problem.maxNormalForce = p.number("planner.max_normal_force");
  problem.minFeetDistance = s.swing.minFeetDistance;
  problem.jointLimitMargin = p.number("planner.joint_limit_margin");
  problem.swingPositionGain = p.number("planner.swing_position_gain");
  const auto friction = p.numbers("planner.friction_barrier");
  const auto limits = p.numbers("planner.limit_barrier");
  problem.frictionBarrier = {friction[0], friction[1]};
  problem.limitBarrier = {limits[0], limits[1]};

  s.sqp.dt = p.number("planner.dt");
  s.sqp.nodes = static_cast<int>(std::lround(p.number("planner.horizon") / s.sqp.dt));
  s.sqp.threads = static_cast<int>(p.integer("planner.threads"));
  if (s.sqp.nodes < 2 || s.sqp.nodes > locomotion::kMaxNodes)
    throw ProfileError({p.problem("planner.horizon",
                                  "planner.horizon / planner.dt must give 2.." +
                                      std::to_string(locomotion::kMaxNodes) + " nodes")});
  return s;
}

}  // namespace ballast::profile
