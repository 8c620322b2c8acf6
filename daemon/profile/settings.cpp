#include "profile/settings.hpp"

#include <cmath>
#include <set>
#include <sstream>

#include "control/stand_posture.hpp"
#include "profile/locomotion_settings.hpp"
#include "profile/wbc_settings.hpp"
#include "model/urdf_loader.hpp"

namespace ballast::profile {

model::Model loadModel(const Profile& profile) {
  model::Model model;
  try {
    model = model::loadUrdfFile(profile.text("robot.urdf"));
  } catch (const model::ModelError& e) {
    throw ProfileError({profile.problem("robot.urdf", e.what())});
  }
  // Armature: groups first, then joints named on their own (they win).
  const auto armature = profile.numberMap("robot.armature");
  const auto groups = profile.groupMap("robot.joint_groups");
  std::vector<std::string> problems;
  for (const bool byGroup : {true, false})
    for (const auto& [name, value] : armature) {
      const auto group = groups.find(name);
      if (byGroup != (group != groups.end())) continue;
      const std::vector<std::string> joints = byGroup ? group->second : std::vector{name};
      for (const std::string& joint : joints) {
        const int j = model.findJoint(joint);
        if (j < 0)
          problems.push_back(profile.problem("robot.armature", name,
                                             byGroup ? "group '" + name + "' names no movable joint '" + joint + "'"
                                                     : "no joint group or movable joint of that name in " +
                                                           model.sourceFile));
        else
          model.armature[j] = value;
      }
    }
  if (!problems.empty()) throw ProfileError(problems);
  return model;
}

control::ControlSettings buildSettings(const Profile& p, const model::Model& model) {
  std::vector<std::string> problems;
  control::ControlSettings s;
  const int nj = model.nj();
  s.profile_name = p.name();
  s.num_joints = nj;

  // robot
  const auto frames = p.strings("robot.contact_frames");
  for (int c = 0; c < control::kNumContacts; ++c) {
    s.contact_frames[c] = frames[c];
    if (model.findFrame(frames[c]) < 0)
      problems.push_back(p.problem("robot.contact_frames",
                                   "no link named '" + frames[c] + "' in " + model.sourceFile));
  }
  s.imu_frame = p.text("robot.imu_frame");
  if (const int f = model.findFrame(s.imu_frame); f < 0)
    problems.push_back(
        p.problem("robot.imu_frame", "no link named '" + s.imu_frame + "' in " + model.sourceFile));
  else if (model.frames[f].body != 0)
    problems.push_back(
        p.problem("robot.imu_frame", "'" + s.imu_frame + "' is not fixed to the floating base"));

  const auto groups = p.groupMap("robot.joint_groups");
  std::vector<std::string> groupOf(nj);
  for (const auto& [group, joints] : groups)
    for (const auto& joint : joints) {
      const int j = model.findJoint(joint);
      if (j < 0)
        problems.push_back(
            p.problem("robot.joint_groups", group,
                      "no movable joint named '" + joint + "' in " + model.sourceFile));
      else if (!groupOf[j].empty())
        problems.push_back(
            p.problem("robot.joint_groups", group,
                      "joint '" + joint + "' is already in group '" + groupOf[j] + "'"));
      else
        groupOf[j] = group;
    }
  std::string ungrouped;
  for (int j = 0; j < nj; ++j)
    if (groupOf[j].empty()) ungrouped += (ungrouped.empty() ? "" : ", ") + model.jointName[j + 1];
  if (!ungrouped.empty())
    problems.push_back(p.problem("robot.joint_groups", "joints in no group: " + ungrouped +
                                                           " (every actuated joint needs one)"));

  for (const auto& [joint, angle] : p.numberMap("robot.nominal_posture")) {
    const int j = model.findJoint(joint);
    if (j < 0) {
      problems.push_back(p.problem("robot.nominal_posture", joint,
                                   "no movable joint of that name in " + model.sourceFile));
      continue;
    }
    if (angle < model.lowerPositionLimit[j] || angle > model.upperPositionLimit[j]) {
      std::ostringstream m;
      m << angle << " rad is outside the joint's limits [" << model.lowerPositionLimit[j] << ", "
        << model.upperPositionLimit[j] << "]";
      problems.push_back(p.problem("robot.nominal_posture", joint, m.str()));
    }
    s.nominal_q[j] = angle;
  }
  for (int j = 0; j < nj; ++j)  // joints not listed stand at 0, or mid-range if 0 is outside
    if (!p.numberMap("robot.nominal_posture").count(model.jointName[j + 1]) &&
        (model.lowerPositionLimit[j] > 0 || model.upperPositionLimit[j] < 0))
      s.nominal_q[j] = 0.5 * (model.lowerPositionLimit[j] + model.upperPositionLimit[j]);

  // Per-group maps must name existing groups; gains need every group.
  auto checkGroups = [&](const std::string& key, bool everyGroup) {
    const auto values = p.numberMap(key);
    for (const auto& [group, v] : values)
      if (!groups.count(group))
        problems.push_back(
            p.problem(key, group, "no joint group of that name in robot.joint_groups"));
    if (everyGroup)
      for (const auto& [group, joints] : groups)
        if (!values.count(group))
          problems.push_back(p.problem(key, "no entry for joint group '" + group + "'"));
    return values;
  };
  const auto kp = checkGroups("control.joint_kp", true);
  const auto kd = checkGroups("control.joint_kd", true);
  for (int j = 0; j < nj; ++j) {
    if (const auto it = kp.find(groupOf[j]); it != kp.end()) s.kp[j] = it->second;
    if (const auto it = kd.find(groupOf[j]); it != kd.end()) s.kd[j] = it->second;
  }

  // control
  s.rate = p.number("control.rate");
  s.initial_mode = p.text("control.initial_mode") == "stand-up" ? control::Mode::kStandUp
                                                                : control::Mode::kPassive;
  s.stand_up_duration = p.number("control.stand_up_duration");
  s.gain_blend_time = p.number("control.gain_blend_time");
  s.gravity_compensation = p.flag("control.gravity_compensation");
  s.pose_speed = p.number("control.pose_speed");
  s.pose_angular_speed = p.number("control.pose_angular_speed");

  // estimator, terrain
  s.use_truth = p.text("estimator.source") == "truth";
  s.use_position_fix = p.flag("estimator.position_fix");
  s.estimator.imuFrame = s.imu_frame;
  for (int c = 0; c < control::kNumContacts; ++c) s.estimator.contactFrames[c] = s.contact_frames[c];
  s.estimator.period = 1.0 / p.number("control.rate");
  s.estimator.contactForceCheck = p.flag("estimator.contact_force_check");
  for (const estimation::EstimatorNumberKey& k : estimation::estimatorNumberKeys())
    s.estimator.*k.field = p.number(std::string("estimator.") + k.key);
  s.ground_height = p.number("terrain.ground_height");

  // safety
  s.damping = p.number("safety.damping");
  s.max_tilt = p.number("safety.max_tilt");
  s.min_base_height = p.number("safety.min_base_height");
  s.fall_on_non_foot_contact = p.flag("safety.fall_on_non_foot_contact");
  s.command_ttl = p.number("safety.command_ttl");
  s.max_command_ttl = p.number("safety.max_command_ttl");
  if (s.command_ttl > s.max_command_ttl)
    problems.push_back(p.problem("safety.command_ttl", "is larger than safety.max_command_ttl"));
  s.max_vx = p.number("safety.max_vx");
  s.max_vy = p.number("safety.max_vy");
  s.max_yaw_rate = p.number("safety.max_yaw_rate");
  s.min_pose_height = p.number("safety.min_pose_height");
  s.max_pose_height = p.number("safety.max_pose_height");
  if (s.min_pose_height >= s.max_pose_height)
    problems.push_back(p.problem("safety.min_pose_height", "must be below safety.max_pose_height"));
  s.max_pose_tilt = p.number("safety.max_pose_tilt");
  s.max_pose_yaw = p.number("safety.max_pose_yaw");
  s.max_push_force = p.number("safety.max_push_force");
  s.max_plan_age = p.number("safety.max_plan_age");
  s.max_command_gap = p.number("safety.max_command_gap");
  s.max_late_fraction = p.number("safety.max_late_fraction");
  s.max_push_duration = p.number("safety.max_push_duration");

  // planner, telemetry
  s.planner_rate = p.number("planner.rate");
  s.planner_latency = p.number("planner.latency");
  if (s.planner_latency > 1.0 / s.planner_rate + 1e-9)
    problems.push_back(p.problem("planner.latency", "must be at most one planner period (1 / planner.rate)"));
  if (p.number("planner.dt") >= p.number("planner.horizon"))
    problems.push_back(p.problem("planner.dt", "must be shorter than planner.horizon"));
  else if (p.number("planner.horizon") / p.number("planner.dt") > locomotion::kMaxNodes + 0.5)
    problems.push_back(p.problem("planner.dt", "planner.horizon / planner.dt is more than " +
                                                   std::to_string(locomotion::kMaxNodes) +
                                                   " nodes: make dt longer"));
  if (p.number("planner.min_normal_force") >= p.number("planner.max_normal_force"))
    problems.push_back(
        p.problem("planner.min_normal_force", "must be below planner.max_normal_force"));
  s.telemetry_decimation = static_cast<int>(p.integer("telemetry.decimation"));

  if (problems.empty()) {
    // The standing posture needs two feet; its height must be one `pose` may ask for.
    try {
      const control::StandPosture posture(model, s);
      const double h = posture.nominalHeight();
      if (h < s.min_pose_height || h > s.max_pose_height) {
        std::ostringstream m;
        m << "the nominal posture stands the base at " << h
          << " m, outside safety.min_pose_height..max_pose_height [" << s.min_pose_height << ", "
          << s.max_pose_height << "]";
        problems.push_back(p.problem("robot.nominal_posture", m.str()));
      }
    } catch (const model::ModelError& e) {
      problems.push_back(p.problem("robot.contact_frames", e.what()));
    }
  }
  if (!problems.empty()) throw ProfileError(problems);

  // The estimator, the whole-body controller and the planner (their own checks, located at
  // the keys they name).
  if (const std::string why = estimation::validateSettings(s.estimator, model); !why.empty()) {
    std::string key = why.substr(0, why.find_first_of(":["));
    if (!findKey(key)) key = "estimator.source";
    throw ProfileError({p.problem(key, why.substr(why.find(':') + 2))});
  }
  const wbc::WbcSettings wbc = wbcSettings(p, model);
  s.wbc = std::make_shared<wbc::WholeBodyController>(model, wbc);
  s.wbc_motor_kp = p.number("wbc.motor_kp");
  s.wbc_motor_kd = p.number("wbc.motor_kd");
  s.locomotion =
      locomotionSettings(p, model, s, wbc, control::StandPosture(model, s).nominalHeight());
  return s;
}

}  // namespace ballast::profile
