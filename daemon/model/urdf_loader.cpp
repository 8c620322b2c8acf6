#include "model/urdf_loader.hpp"

#include <console_bridge/console.h>
#include <tinyxml.h>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <mutex>
#include <sstream>
#include <vector>

namespace ballast::model {
namespace {

/// Where an element starts in the file, for messages.
struct Location {
  int line = 0;
  int column = 0;
};

/// Line/column of every <link> and <joint>, and the order joints appear in (from tinyxml, since
/// urdfdom keeps neither).
struct SourceIndex {
  std::string file;
  std::map<std::string, Location> links, joints;
  std::map<std::string, int> jointOrder;

  std::string where(const std::map<std::string, Location>& table, const std::string& name) const {
    const auto it = table.find(name);
    if (it == table.end()) return file + ": ";
    return file + ":" + std::to_string(it->second.line) + ":" + std::to_string(it->second.column) +
           ": ";
  }
  std::string atLink(const std::string& name) const {
    return where(links, name) + "<link name=\"" + name + "\">: ";
  }
  std::string atJoint(const std::string& name) const {
    return where(joints, name) + "<joint name=\"" + name + "\">: ";
  }
};

SourceIndex indexSource(const std::string& xml, const std::string& file) {
  TiXmlDocument doc;
  doc.Parse(xml.c_str());
  if (doc.Error()) {
    throw ModelError(file + ":" + std::to_string(doc.ErrorRow()) + ":" +
                     std::to_string(doc.ErrorCol()) + ": XML error: " + doc.ErrorDesc());
  }
  const TiXmlElement* robot = doc.RootElement();
  if (!robot || std::string(robot->Value()) != "robot") {
    throw ModelError(file + ": the root element is <" +
                     std::string(robot ? robot->Value() : "") + ">, a URDF needs <robot>");
  }
  SourceIndex index{file, {}, {}, {}};
  int order = 0;
  for (const TiXmlElement* e = robot->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const char* name = e->Attribute("name");
    if (!name) continue;
    const Location loc{e->Row(), e->Column()};
    if (std::string(e->Value()) == "link") index.links[name] = loc;
    if (std::string(e->Value()) == "joint") {
      index.joints[name] = loc;
      index.jointOrder[name] = order++;
    }
  }
  return index;
}

/// Collects what urdfdom reports through console_bridge while it parses.
class CapturedLog : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_WARN) messages.push_back(text);
  }
  std::string joined() const {
    std::string s;
    for (const auto& m : messages) s += (s.empty() ? "" : "; ") + m;
    return s.empty() ? "urdfdom rejected the file without a message" : s;
  }
  std::vector<std::string> messages;
};

urdf::ModelInterfaceSharedPtr parseWithUrdfdom(const std::string& xml, const std::string& file) {
  static std::mutex consoleMutex;  // console_bridge's handler is process-global
  std::lock_guard<std::mutex> lock(consoleMutex);
  CapturedLog captured;
  console_bridge::useOutputHandler(&captured);
  urdf::ModelInterfaceSharedPtr parsed;
  std::string thrown;
  try {
    parsed = urdf::parseURDF(xml);
  } catch (const std::exception& e) {
    thrown = e.what();
  }
  console_bridge::restorePreviousOutputHandler();
  if (!parsed) {
    throw ModelError(file + ": invalid URDF: " + (thrown.empty() ? captured.joined() : thrown));
  }
  return parsed;
}

SE3<double> toSE3(const urdf::Pose& pose) {
  const Eigen::Quaterniond q(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z);
  return SE3<double>{q.normalized().toRotationMatrix(),
                     Vec3<double>(pose.position.x, pose.position.y, pose.position.z)};
}

/// The link's inertia in the link frame, validated; zero for a link without <inertial> or of
/// zero mass (a frame, a sensor: vendors write both). A point mass (zero inertia) is a body.
Inertia<double> linkInertia(const urdf::Link& link, const SourceIndex& src) {
  if (!link.inertial) return Inertia<double>::Zero();
  const auto& in = *link.inertial;
  const std::string at = src.atLink(link.name) + "<inertial>: ";
  if (!(in.mass >= 0.0) || !std::isfinite(in.mass))
    throw ModelError(at + "mass must be positive (or zero for a massless link) and finite, got " +
                     std::to_string(in.mass));
  Mat3<double> I;
  I << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
  if (!I.allFinite()) throw ModelError(at + "inertia has a non-finite entry");
  if (in.mass == 0.0) return Inertia<double>::Zero();
  const Eigen::SelfAdjointEigenSolver<Mat3<double>> eig(I);
  const Vec3<double> d = eig.eigenvalues();  // ascending
  if (d[0] < -1e-12 * std::max(1.0, d[2]))
    throw ModelError(at + "inertia is not positive semi-definite (smallest principal moment " +
                     std::to_string(d[0]) + ")");
  if (d[0] + d[1] < d[2] * (1.0 - 1e-9))
    throw ModelError(at + "principal moments " + std::to_string(d[0]) + ", " +
                     std::to_string(d[1]) + ", " + std::to_string(d[2]) +
                     " violate the triangle inequality (no rigid body has them)");
  const SE3<double> comFrame = toSE3(in.origin);
  return Inertia<double>::FromCom(in.mass, comFrame.p, comFrame.R * I * comFrame.R.transpose());
}

class TreeBuilder {
 public:
  TreeBuilder(const urdf::ModelInterface& urdf, const SourceIndex& src, const UrdfOptions& options)
      : urdf_(urdf), src_(src), locked_(options.locked), requestedReason_(options.lockedReason) {
    for (const auto& [name, position] : options.locked) {
      const urdf::JointConstSharedPtr joint = urdf_.getJoint(name);
      if (!joint)
        throw LockedJointError(src_.file + " has no joint '" + name + "'", name);
      const std::string at = src_.atJoint(name) + "locked at " + std::to_string(position) + ": ";
      if (joint->type != urdf::Joint::REVOLUTE && joint->type != urdf::Joint::CONTINUOUS &&
          joint->type != urdf::Joint::PRISMATIC)
        throw LockedJointError(at + "only a revolute, continuous or prismatic joint can be locked",
                               name);
      if (joint->type != urdf::Joint::CONTINUOUS && joint->limits &&
          (position < joint->limits->lower || position > joint->limits->upper))
        throw LockedJointError(at + "outside the joint's limits [" +
                                   std::to_string(joint->limits->lower) + ", " +
                                   std::to_string(joint->limits->upper) + "]",
                               name);
    }
  }

  Model build() {
    model_.name = urdf_.getName();
    model_.sourceFile = src_.file;
    urdf::LinkConstSharedPtr root = urdf_.getRoot();
    if (!root) throw ModelError(src_.file + ": no root link");
    // A massless root ("world") holding the robot by a floating joint is the world, not a body.
    if (!root->inertial && root->child_joints.size() == 1 &&
        root->child_joints[0]->type == urdf::Joint::FLOATING) {
      root = urdf_.getLink(root->child_joints[0]->child_link_name);
    }
    lockMimicJoints();
    lockJointsMovingNothing(*root);
    for (const auto& [name, position] : locked_)
      model_.lockedJoints.push_back(LockedJoint{
          name, position, urdf_.getJoint(name)->type == urdf::Joint::PRISMATIC, lockReason(name)});
    std::stable_sort(model_.lockedJoints.begin(), model_.lockedJoints.end(),
                     [&](const LockedJoint& a, const LockedJoint& b) {
                       return src_.jointOrder.at(a.name) < src_.jointOrder.at(b.name);
                     });
    model_.parent.push_back(-1);
    model_.bodyName.push_back(root->name);
    model_.jointName.push_back("");
    model_.jointType.push_back(JointType::FreeFlyer);
    model_.jointAxis.push_back(Vec3<double>::Zero());
    model_.jointPlacement.push_back(SE3<double>::Identity());
    model_.inertia.push_back(Inertia<double>::Zero());
    addRigidGroup(*root, 0, SE3<double>::Identity());
    if (!(model_.inertia[0].mass > 0.0))
      throw ModelError(src_.atLink(root->name) +
                       "the floating base (root link and links fixed to it) has no mass");
    finish();
    return std::move(model_);
  }

 private:
  /// Adds `link` and every link fixed to it as one rigid body `body` (link at `placement` in the
  /// body frame), then the bodies moved by the group's joints, in file order.
  void addRigidGroup(const urdf::Link& link, int body, const SE3<double>& placement) {
    std::vector<std::pair<const urdf::Joint*, SE3<double>>> movable;
    collectGroup(link, body, placement, movable);
    std::stable_sort(movable.begin(), movable.end(), [&](const auto& a, const auto& b) {
      return src_.jointOrder.at(a.first->name) < src_.jointOrder.at(b.first->name);
    });
    for (const auto& [joint, jointPlacement] : movable) addMovingJoint(*joint, body, jointPlacement);
  }

  static bool isMovable(const urdf::Joint& joint) {
    return joint.type == urdf::Joint::REVOLUTE || joint.type == urdf::Joint::CONTINUOUS ||
           joint.type == urdf::Joint::PRISMATIC;
  }

  /// A mimic joint has no actuator of its own: it is held where its leader's position (the
  /// leader's locked position, else zero) puts it, within its limits.
  void lockMimicJoints() {
    for (const auto& [name, joint] : urdf_.joints_) {
      if (!joint->mimic || !isMovable(*joint) || locked_.count(name)) continue;
      const auto leader = locked_.find(joint->mimic->joint_name);
      const double leaderPosition = leader == locked_.end() ? 0.0 : leader->second;
      double position = joint->mimic->multiplier * leaderPosition + joint->mimic->offset;
      if (joint->type != urdf::Joint::CONTINUOUS && joint->limits)
        position = std::clamp(position, joint->limits->lower, joint->limits->upper);
      locked_[name] = position;
      reasons_[name] = "mimics joint '" + joint->mimic->joint_name +
                       "' (no actuator of its own): held where the leader at " +
                       (leader == locked_.end() ? std::string("0")
                                                : std::to_string(leaderPosition)) +
                       " puts it";
    }
  }

  /// A joint whose links (the child and all below it) have no inertia about its axis (no mass
  /// for a prismatic one) moves nothing the dynamics can see and cannot be controlled: held at
  /// zero, within its limits. Returns the inertia of the links from `link` down, in its frame.
  Inertia<double> lockJointsMovingNothing(const urdf::Link& link) {
    Inertia<double> total = linkInertia(link, src_);
    for (const auto& joint : link.child_joints) {
      const Inertia<double> below = lockJointsMovingNothing(*urdf_.getLink(joint->child_link_name));
      if (isMovable(*joint) && !locked_.count(joint->name)) {
        const Vec3<double> axis(joint->axis.x, joint->axis.y, joint->axis.z);
        const double moved =
            joint->type == urdf::Joint::PRISMATIC
                ? below.mass
                : axis.dot(below.I * axis) / axis.squaredNorm();  // about the joint's axis
        if (!(moved > 1e-9) && axis.norm() > 1e-9) {  // a zero axis is refused as such later
          double position = 0.0;
          if (joint->type != urdf::Joint::CONTINUOUS && joint->limits)
            position = std::clamp(0.0, joint->limits->lower, joint->limits->upper);
          locked_[joint->name] = position;
          reasons_[joint->name] = "moves link '" + joint->child_link_name +
                                  "' and the links below it, which have no " +
                                  (joint->type == urdf::Joint::PRISMATIC ? "mass"
                                                                         : "inertia about its axis");
        }
      }
      const auto lock = locked_.find(joint->name);
      const SE3<double> at =
          toSE3(joint->parent_to_joint_origin_transform) *
          (lock == locked_.end() ? SE3<double>::Identity() : lockedMotion(*joint, lock->second));
      total += below.transformedBy(at);
    }
    return total;
  }

  std::string lockReason(const std::string& joint) const {
    const auto it = reasons_.find(joint);
    return it == reasons_.end() ? requestedReason_ : it->second;
  }

  void collectGroup(const urdf::Link& link, int body, const SE3<double>& placement,
                    std::vector<std::pair<const urdf::Joint*, SE3<double>>>& movable) {
    model_.frames.push_back(Frame{link.name, body, placement});
    model_.inertia[body] += linkInertia(link, src_).transformedBy(placement);
    for (const auto& joint : link.child_joints) {
      const SE3<double> at = placement * toSE3(joint->parent_to_joint_origin_transform);
      if (joint->type == urdf::Joint::FIXED) {
        collectGroup(*urdf_.getLink(joint->child_link_name), body, at, movable);
      } else if (const auto lock = locked_.find(joint->name); lock != locked_.end()) {
        collectGroup(*urdf_.getLink(joint->child_link_name), body,
                     at * lockedMotion(*joint, lock->second), movable);
      } else {
        movable.emplace_back(joint.get(), at);
      }
    }
  }

  /// The child's frame in the joint frame of a joint held at `position`.
  static SE3<double> lockedMotion(const urdf::Joint& joint, double position) {
    const Vec3<double> axis = Vec3<double>(joint.axis.x, joint.axis.y, joint.axis.z).normalized();
    if (joint.type == urdf::Joint::PRISMATIC)
      return SE3<double>{Mat3<double>::Identity(), position * axis};
    return SE3<double>{Eigen::AngleAxisd(position, axis).toRotationMatrix(), Vec3<double>::Zero()};
  }

  /// A body moved by `joint` (not fixed) relative to `parentBody`; `placement` is the joint frame
  /// in the parent body frame.
  void addMovingJoint(const urdf::Joint& joint, int parentBody, const SE3<double>& placement) {
    const urdf::LinkConstSharedPtr child = urdf_.getLink(joint.child_link_name);
    const std::string at = src_.atJoint(joint.name);
    JointType type;
    switch (joint.type) {
      case urdf::Joint::REVOLUTE:
      case urdf::Joint::CONTINUOUS:
        type = JointType::Revolute;
        break;
      case urdf::Joint::PRISMATIC:
        type = JointType::Prismatic;
        break;
      case urdf::Joint::FLOATING:
        throw ModelError(at + "type 'floating' is only allowed as the root's joint to the world");
      case urdf::Joint::PLANAR:
        throw ModelError(at + "type 'planar' is not supported (use revolute, continuous, "
                              "prismatic or fixed)");
      default:
        throw ModelError(at + "unknown joint type");
    }
    Vec3<double> axis(joint.axis.x, joint.axis.y, joint.axis.z);
    if (!(axis.norm() > 1e-9) || !axis.allFinite())
      throw ModelError(at + "<axis> must be a non-zero vector");
    axis.normalize();

    double lower = -std::numeric_limits<double>::infinity();
    double upper = std::numeric_limits<double>::infinity();
    if (!joint.limits)
      throw ModelError(at + "no <limit>: an actuated joint needs effort and velocity limits");
    if (joint.type != urdf::Joint::CONTINUOUS) {
      lower = joint.limits->lower;
      upper = joint.limits->upper;
      if (!(lower < upper))
        throw ModelError(at + "<limit> lower (" + std::to_string(lower) +
                         ") must be below upper (" + std::to_string(upper) + ")");
    }
    if (!(joint.limits->effort > 0.0))
      throw ModelError(at + "<limit> effort must be positive, got " +
                       std::to_string(joint.limits->effort));
    if (!(joint.limits->velocity > 0.0))
      throw ModelError(at + "<limit> velocity must be positive, got " +
                       std::to_string(joint.limits->velocity));

    const int body = model_.nbodies();
    model_.parent.push_back(parentBody);
    model_.bodyName.push_back(child->name);
    model_.jointName.push_back(joint.name);
    model_.jointType.push_back(type);
    model_.jointAxis.push_back(axis);
    model_.jointPlacement.push_back(placement);
    model_.inertia.push_back(Inertia<double>::Zero());
    lower_.push_back(lower);
    upper_.push_back(upper);
    velocity_.push_back(joint.limits->velocity);
    effort_.push_back(joint.limits->effort);
    addRigidGroup(*child, body, SE3<double>::Identity());
  }

  void finish() {
    const int nj = model_.nbodies() - 1;
    model_.nq = 7 + nj;
    model_.nv = 6 + nj;
    auto toVec = [](const std::vector<double>& x) {
      return Eigen::Map<const VecX<double>>(x.data(), static_cast<Eigen::Index>(x.size())).eval();
    };
    model_.lowerPositionLimit = toVec(lower_);
    model_.upperPositionLimit = toVec(upper_);
    model_.velocityLimit = toVec(velocity_);
    model_.effortLimit = toVec(effort_);
    model_.armature = VecX<double>::Zero(static_cast<Eigen::Index>(effort_.size()));
  }

  const urdf::ModelInterface& urdf_;
  const SourceIndex& src_;
  std::map<std::string, double> locked_;       ///< the profile's, then the mimic and inert ones
  std::map<std::string, std::string> reasons_;  ///< why, for those the URDF locks itself
  std::string requestedReason_;                 ///< why, for UrdfOptions::locked
  Model model_;
  std::vector<double> lower_, upper_, velocity_, effort_;
};

}  // namespace

Model loadUrdfString(const std::string& xml, const std::string& sourceName,
                     const UrdfOptions& options) {
  const SourceIndex src = indexSource(xml, sourceName);
  const urdf::ModelInterfaceSharedPtr parsed = parseWithUrdfdom(xml, sourceName);
  return TreeBuilder(*parsed, src, options).build();
}

Model loadUrdfFile(const std::string& path, const UrdfOptions& options) {
  std::ifstream in(path);
  if (!in) throw ModelError(path + ": cannot read the URDF: " + std::strerror(errno));
  std::stringstream text;
  text << in.rdbuf();
  return loadUrdfString(text.str(), path, options);
}

}  // namespace ballast::model
