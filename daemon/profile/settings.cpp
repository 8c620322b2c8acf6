#include "profile/settings.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <Eigen/QR>

#include "common/closest_name.hpp"  // plugins/common
#include "common/format.hpp"
#include "control/stand_posture.hpp"
#include "model/frames.hpp"
#include "model/configuration.hpp"
#include "model/forward_kinematics.hpp"
#include "model/urdf_loader.hpp"
#include "profile/schema.hpp"

namespace ballast::profile {

namespace {

/// Problems found after the schema: each names the key that fills the field it concerns.
class Problems {
 public:
  Problems(const Profile& profile, const Settings& settings) : p_(profile), s_(settings) {}

  void add(const void* field, const std::string& message) {
    list_.push_back(p_.problem(key(field), message));
  }
  void add(const void* field, const std::string& entry, const std::string& message) {
    list_.push_back(p_.problem(key(field), entry, message));
  }
  /// A library's validateSettings() answer (nothing if it found nothing).
  void add(const model::SettingsProblem& problem) {
    if (problem) add(problem.field, problem.message);
  }
  /// At element `index` of the list that fills `field`.
  void atElement(const void* field, std::size_t index, const std::string& message) {
    list_.push_back(p_.problemAtElement(key(field), index, message));
  }
  void atKey(const char* key, const std::string& message) {
    list_.push_back(p_.problem(key, message));
  }
  const char* key(const void* field) const {
    const char* k = keyOf(s_, field);
    if (!k) throw std::logic_error("no profile key fills the field a problem concerns");
    return k;
  }
  bool empty() const { return list_.empty(); }
  void raise() const {
    if (!list_.empty()) throw ProfileError(list_);
  }

 private:
  const Profile& p_;
  const Settings& s_;
  std::vector<std::string> list_;
};

const char* controlKeyOf(const control::ControlSettings& c, const void* field) {
  return table().keyWithin<&Settings::control>(c, field);
}

/// What follows from the schema's values without a model: the copies the libraries keep of the
/// robot's frames and of the control period, the planner's grid.
void derive(Settings& s) {
  control::ControlSettings& c = s.control;
  c.key_of = &controlKeyOf;
  for (int i = 0; i < model::kNumContacts; ++i)
    c.contact_frames[i] = s.contact_points[i].frameName(model::kContactFrameNames[i]);
  c.imu_frame = s.imu.frameName("imu");
  c.estimator.imuFrame = c.imu_frame;
  c.estimator.contactFrames = c.contact_frames;
  c.estimator.period = 1.0 / c.rate;
  c.wbc.contactFrames.assign(c.contact_frames.begin(), c.contact_frames.end());
  c.wbc.period = 1.0 / c.rate;
  locomotion::LocomotionSettings& l = c.locomotion;
  l.contactFrames = c.contact_frames;
  l.walkGait.walking = true;
  l.problem.minFeetDistance = l.swing.minFeetDistance;
  l.sqp.nodes = static_cast<int>(std::lround(s.planner_horizon / l.sqp.dt));
  s.mapping.map.ground = c.ground_height;
  s.mapping.map.rule.reference = c.ground_height;
}

}  // namespace

Settings readSettings(const Profile& p) {
  Settings s{};
  for (const schema::Row<Settings>& row : table().rows()) {
    schema::Value v;
    schema::Problem bad;
    if (!schema::read(row, p.value(row.name), v, bad))
      throw std::logic_error(std::string("profile value of ") + row.name + ": " + bad.what);
    row.store(s, v);
  }
  s.control.profile_name = p.name();
  derive(s);
  return s;
}

namespace {

/// Per-joint values from the joint groups: the group's value for each of its joints. Entries
/// must name groups; every group needs one.
void perJoint(const Settings& s, const schema::NamedNumbers& byGroup,
              const std::vector<std::string>& groupOf, std::array<double, control::kMaxJoints>& out,
              Problems& problems) {
  for (const auto& [group, value] : byGroup)
    if (!s.joints.groups.count(group))
      problems.add(&byGroup, group,
                   std::string("no joint group of that name in ") + problems.key(&s.joints.groups));
  for (const auto& [group, joints] : s.joints.groups)
    if (!byGroup.count(group)) problems.add(&byGroup, "no entry for joint group '" + group + "'");
  for (std::size_t j = 0; j < groupOf.size(); ++j)
    if (const auto it = byGroup.find(groupOf[j]); it != byGroup.end()) out[j] = it->second;
}

}  // namespace

const char* keyOf(const Settings& settings, const void* field) {
  return table().keyOf(settings, field);
}

const char* keyOf(const server::ServerConfig& config, const void* field) {
  return table().keyWithin<&Settings::server>(config, field);
}

Settings defaultSettings() {
  Settings s = table().defaults();
  derive(s);
  return s;
}

namespace {

/// "no link 'x' in robot.urdf; closest: a, b, c": what a profile's frame names that the URDF lacks.
std::string missingLink(const std::string& link, const model::Model& model) {
  return "no link named '" + link + "' in " + model.sourceFile + "; closest: " +
         closestNamesText(link, model.frames, [](const model::Frame& f) { return f.name; });
}

/// The frames the profile places on links ({link, offset, rpy}) added to the model, so the
/// controller's libraries find them by name like the URDF's own links.
void addProfileFrames(const Profile& profile, const Settings& s, model::Model& model,
                      std::vector<std::string>& problems) {
  auto add = [&](const schema::FrameRef& ref, const std::string& name, const std::string& where) {
    if (!ref.placed() || model.findFrame(name) >= 0) return;
    const int link = model.findFrame(ref.link);
    if (link < 0) {
      problems.push_back(where + missingLink(ref.link, model));
      return;
    }
    const Eigen::Matrix3d R = (Eigen::AngleAxisd(ref.rpy[2], Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(ref.rpy[1], Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(ref.rpy[0], Eigen::Vector3d::UnitX()))
                                  .toRotationMatrix();
    const model::SE3<double> inLink{R, Eigen::Vector3d(ref.offset[0], ref.offset[1], ref.offset[2])};
    const model::Frame& parent = model.frames[link];
    model.frames.push_back(model::Frame{name, parent.body, parent.placement * inLink});
  };
  const char* contacts = keyOf(s, &s.contact_points);
  for (int i = 0; i < model::kNumContacts; ++i) {
    const std::string where = profile.problemAtElement(contacts, i, "");
    add(s.contact_points[i], s.control.contact_frames[i], where);
  }
  add(s.imu, s.control.imu_frame, profile.problem(keyOf(s, &s.imu), ""));
}

}  // namespace

model::Model loadModel(const Profile& profile) {
  const Settings s = readSettings(profile);
  model::Model model;
  model::UrdfOptions options;
  options.locked.insert(s.joints.locked.begin(), s.joints.locked.end());
  options.lockedReason = keyOf(s, &s.joints.locked);
  try {
    model = model::loadUrdfFile(s.urdf, options);
  } catch (const model::LockedJointError& e) {
    throw ProfileError({profile.problem(keyOf(s, &s.joints.locked), e.joint, e.what())});
  } catch (const model::ModelError& e) {
    throw ProfileError({profile.problem(keyOf(s, &s.urdf), e.what())});
  }
  if (model.nj() > control::kMaxJoints)
    throw ProfileError({profile.problem(
        keyOf(s, &s.urdf),
        model.sourceFile + " has " + std::to_string(model.nj()) + " movable joints; ballast " +
            "controls at most " + std::to_string(control::kMaxJoints) + " (the backend ABI's " +
            "limit): fix the others at an angle with " + keyOf(s, &s.joints.locked))});
  std::vector<std::string> frameProblems;
  addProfileFrames(profile, s, model, frameProblems);
  if (!frameProblems.empty()) throw ProfileError(frameProblems);
  // Armature: groups first, then joints named on their own (they win).
  Problems problems(profile, s);
  for (const bool byGroup : {true, false})
    for (const auto& [name, value] : s.joints.armature) {
      const auto group = s.joints.groups.find(name);
      if (byGroup != (group != s.joints.groups.end())) continue;
      const std::vector<std::string> joints = byGroup ? group->second : std::vector{name};
      for (const std::string& joint : joints) {
        const int j = model.findJoint(joint);
        if (j < 0)
          problems.add(&s.joints.armature, name,
                       byGroup ? "group '" + name + "' names no movable joint '" + joint + "'"
                               : "no joint group or movable joint of that name in " +
                                     model.sourceFile);
        else
          model.armature[j] = value;
      }
    }
  problems.raise();
  return model;
}

namespace {
/// Why neither foot can turn about the vertical relative to the base at the nominal posture
/// (empty if one can): the vertical is not among the angular velocities the leg's joints give
/// the foot (the least-squares residual of J_ω q̇ = e_z is not small). A robot with no hip yaw,
/// or with both hip yaws locked, cannot turn: its feet stay parallel to the pelvis.
std::string feetCannotYaw(const model::Model& model, const control::ControlSettings& c) {
  model::VecX<double> q = model::neutralConfiguration(model);
  for (int j = 0; j < model.nj(); ++j) q[model::Model::qIndexOfJoint(j)] = c.nominal_q[j];
  model::Data<double> data(model);
  model::forwardKinematics(model, data, q);
  Eigen::MatrixXd J(6, model.nv);
  for (int foot : {0, 2}) {
    const int f = model.findFrame(c.contact_frames[foot]);
    if (f < 0) return "";
    model::frameJacobian(model, data, f, J);
    const Eigen::MatrixXd Jw = J.bottomRows(3).rightCols(model.nj());
    const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
    const Eigen::VectorXd v = Jw.completeOrthogonalDecomposition().solve(z);
    if ((Jw * v - z).norm() < 0.5) return "";
  }
  return "no joint of either leg turns its foot about the vertical (no hip yaw, or locked)";
}
}  // namespace

Settings settingsFor(const Profile& p, const model::Model& model) {
  Settings s = readSettings(p);
  Problems problems(p, s);
  for (const auto& [key, what] : table().broken(s)) problems.atKey(key, what);
  control::ControlSettings& c = s.control;
  const int nj = model.nj();
  c.num_joints = nj;

  // The robot's frames (those placed on a link are in the model if it came from loadModel).
  for (int i = 0; i < model::kNumContacts; ++i)
    if (model.findFrame(c.contact_frames[i]) < 0)
      problems.atElement(&s.contact_points, i, missingLink(s.contact_points[i].link, model));
  if (const int f = model.findFrame(c.imu_frame); f < 0)
    problems.add(&s.imu, missingLink(s.imu.link, model));
  else if (model.frames[f].body != 0)
    problems.add(&c.imu_frame, "'" + c.imu_frame + "' is not fixed to the floating base");

  // Joint groups: every actuated joint in exactly one.
  std::vector<std::string> groupOf(nj);
  for (const auto& [group, joints] : s.joints.groups)
    for (const auto& joint : joints) {
      const int j = model.findJoint(joint);
      if (j < 0)
        problems.add(&s.joints.groups, group,
                     "no movable joint named '" + joint + "' in " + model.sourceFile);
      else if (!groupOf[j].empty())
        problems.add(&s.joints.groups, group,
                     "joint '" + joint + "' is already in group '" + groupOf[j] + "'");
      else
        groupOf[j] = group;
    }
  std::string ungrouped;
  for (int j = 0; j < nj; ++j)
    if (groupOf[j].empty()) ungrouped += (ungrouped.empty() ? "" : ", ") + model.jointName[j + 1];
  if (!ungrouped.empty())
    problems.add(&s.joints.groups,
                 "joints in no group: " + ungrouped + " (every actuated joint needs one)");

  // The nominal posture: joints not listed stand at 0, or mid-range if 0 is outside.
  for (const auto& [joint, angle] : s.joints.posture) {
    const int j = model.findJoint(joint);
    if (j < 0) {
      problems.add(&s.joints.posture, joint, "no movable joint of that name in " + model.sourceFile);
      continue;
    }
    if (angle < model.lowerPositionLimit[j] || angle > model.upperPositionLimit[j]) {
      std::ostringstream m;
      m << angle << " rad is outside the joint's limits [" << model.lowerPositionLimit[j] << ", "
        << model.upperPositionLimit[j] << "]";
      problems.add(&s.joints.posture, joint, m.str());
    }
    c.nominal_q[j] = angle;
  }
  for (int j = 0; j < nj; ++j)
    if (!s.joints.posture.count(model.jointName[j + 1]) &&
        (model.lowerPositionLimit[j] > 0 || model.upperPositionLimit[j] < 0))
      c.nominal_q[j] = 0.5 * (model.lowerPositionLimit[j] + model.upperPositionLimit[j]);

  c.feet_cannot_yaw = feetCannotYaw(model, c);
  c.locomotion.problem.feetFollowBaseYaw = !c.feet_cannot_yaw.empty();
  c.wbc.feetFollowBaseYaw = !c.feet_cannot_yaw.empty();

  // Gains per group.
  perJoint(s, s.joints.kp, groupOf, c.kp, problems);
  perJoint(s, s.joints.kd, groupOf, c.kd, problems);

  // The whole-body controller's joints (URDF joints, or groups standing for their joints) and
  // torque limits.
  c.wbc.jointSpaceJoints.clear();
  for (const std::string& name : s.joints.joint_space) {
    if (const auto g = s.joints.groups.find(name); g != s.joints.groups.end())
      c.wbc.jointSpaceJoints.insert(c.wbc.jointSpaceJoints.end(), g->second.begin(), g->second.end());
    else
      c.wbc.jointSpaceJoints.push_back(name);
  }
  c.wbc.torqueLimit.resize(nj);
  for (int j = 0; j < nj; ++j) c.wbc.torqueLimit[j] = s.joints.torque_limit_scale * model.effortLimit[j];

  // The planner's robot: the nominal posture, which joints are arms (the WBC's joint-space
  // joints: the planner weighs them apart from the legs), gravity.
  locomotion::LocomotionSettings& l = c.locomotion;
  l.nominalJoints.resize(nj);
  l.armJoint.assign(nj, false);
  for (int j = 0; j < nj; ++j) {
    l.nominalJoints[j] = c.nominal_q[j];
    l.armJoint[j] = std::find(c.wbc.jointSpaceJoints.begin(), c.wbc.jointSpaceJoints.end(),
                              model.jointName[j + 1]) != c.wbc.jointSpaceJoints.end();
  }
  l.swing.foothold.gravity = -model.gravity.z();

  if (problems.empty()) {
    // The standing posture needs two feet; its height must be one `pose` may ask for.
    try {
      const double h = control::StandPosture(model, c).nominalHeight();
      if (h < c.min_pose_height || h > c.max_pose_height) {
        std::ostringstream m;
        m << "the nominal posture stands the base at " << h << " m, outside "
          << problems.key(&c.min_pose_height) << ".." << problems.key(&c.max_pose_height) << " ["
          << c.min_pose_height << ", " << c.max_pose_height << "]";
        problems.add(&s.joints.posture, m.str());
      }
      l.nominalHeight = h;
    } catch (const model::ModelError& e) {
      problems.add(&c.contact_frames, e.what());
    }
  }
  problems.raise();

  // The libraries' own checks, each reporting its first problem.
  problems.add(estimation::validateSettings(c.estimator, model));
  problems.raise();
  problems.add(wbc::validateSettings(c.wbc, model));
  problems.raise();
  return s;
}

control::ControlSettings buildSettings(const Profile& profile, const model::Model& model) {
  return settingsFor(profile, model).control;
}

}  // namespace ballast::profile
