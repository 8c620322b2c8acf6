#include "urdf_multibody.hpp"

#include "urdf_joints.hpp"  // plugins/common

#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <fstream>
#include <sstream>

namespace ballast::simbody {
namespace {

SimTK::Transform toTransform(const urdf::Pose& pose) {
  const SimTK::Quaternion q(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z);
  return SimTK::Transform(SimTK::Rotation(q),
                          SimTK::Vec3(pose.position.x, pose.position.y, pose.position.z));
}

SimTK::MassProperties massProperties(const urdf::Inertial& in) {
  const SimTK::Transform X_LC = toTransform(in.origin);
  const SimTK::Inertia centralInC(SimTK::Mat33(in.ixx, in.ixy, in.ixz,  //
                                               in.ixy, in.iyy, in.iyz,  //
                                               in.ixz, in.iyz, in.izz));
  const SimTK::Inertia centralInL = centralInC.reexpress(~X_LC.R());
  return SimTK::MassProperties(in.mass, X_LC.p(),
                               centralInL.shiftFromMassCenter(X_LC.p(), in.mass));
}

class Builder {
 public:
  Builder(const urdf::ModelInterface& urdf, UrdfMultibody& mb, std::map<std::string, int> order,
          const std::map<std::string, double>& armature,
          const std::map<std::string, double>& locked)
      : urdf_(urdf), mb_(mb), order_(std::move(order)), armature_(armature), locked_(locked) {
    for (const auto& [name, position] : locked_) {
      const urdf::JointConstSharedPtr j = urdf_.getJoint(name);
      if (!j || j->type == urdf::Joint::FIXED || j->type == urdf::Joint::FLOATING ||
          j->type == urdf::Joint::PLANAR)
        throw std::runtime_error("locked joint '" + name + "' is no revolute, continuous or "
                                 "prismatic joint of the robot");
    }
  }

  void build() {
    urdf::LinkConstSharedPtr root = urdf_.getRoot();
    if (!root->inertial && root->child_joints.size() == 1 &&
        root->child_joints[0]->type == urdf::Joint::FLOATING)
      root = urdf_.getLink(root->child_joints[0]->child_link_name);
    if (!root->inertial) throw std::runtime_error("the root link '" + root->name + "' has no mass");
    SimTK::MobilizedBody::Free base(mb_.matter.Ground(), SimTK::Transform(),
                                    SimTK::Body::Rigid(massProperties(*root->inertial)),
                                    SimTK::Transform());
    mb_.base = base.getMobilizedBodyIndex();
    addLink(*root, mb_.base, SimTK::Transform());
    // Bodies are created depth first (welded links included); list joints in file order.
    std::stable_sort(mb_.jointNames.begin(), mb_.jointNames.end(),
                     [&](const auto& a, const auto& b) { return order_.at(a) < order_.at(b); });
  }

 private:
  void addLink(const urdf::Link& link, SimTK::MobilizedBodyIndex body, const SimTK::Transform& X) {
    mb_.linkFrame[link.name] = UrdfMultibody::LinkFrame{body, X};
    mb_.parentLink[link.name] = link.getParent() ? link.getParent()->name : "";
    addCollisions(link, body, X);
    std::vector<urdf::JointSharedPtr> children = link.child_joints;
    std::stable_sort(children.begin(), children.end(), [&](const auto& a, const auto& b) {
      return order_.at(a->name) < order_.at(b->name);
    });
    for (const auto& joint : children) addJoint(*joint, body, X);
  }

  void addCollisions(const urdf::Link& link, SimTK::MobilizedBodyIndex body,
                     const SimTK::Transform& X) {
    std::vector<urdf::CollisionSharedPtr> elements = link.collision_array;
    if (elements.empty() && link.collision) elements.push_back(link.collision);
    for (const auto& c : elements) {
      if (!c || !c->geometry) continue;
      UrdfMultibody::CollisionShape shape;
      shape.link = link.name;
      shape.body = body;
      shape.inBody = X * toTransform(c->origin);
      switch (c->geometry->type) {
        case urdf::Geometry::BOX: {
          const auto& box = static_cast<const urdf::Box&>(*c->geometry);
          shape.halfSize = SimTK::Vec3(box.dim.x, box.dim.y, box.dim.z) / 2;
          break;
        }
        case urdf::Geometry::SPHERE:
          shape.kind = UrdfMultibody::CollisionShape::Kind::kSphere;
          shape.halfSize[0] = static_cast<const urdf::Sphere&>(*c->geometry).radius;
          break;
        case urdf::Geometry::CYLINDER: {  // its axis is z
          const auto& cyl = static_cast<const urdf::Cylinder&>(*c->geometry);
          shape.halfSize = SimTK::Vec3(cyl.radius, cyl.radius, cyl.length / 2);
          break;
        }
        default:
          ++mb_.collisionSkipped;
          continue;
      }
      mb_.collisionShapes.push_back(shape);
    }
  }

  void addJoint(const urdf::Joint& joint, SimTK::MobilizedBodyIndex parent,
                const SimTK::Transform& X_PL) {
    const urdf::LinkConstSharedPtr child = urdf_.getLink(joint.child_link_name);
    SimTK::Transform X_PJ = X_PL * toTransform(joint.parent_to_joint_origin_transform);
    const auto lock = locked_.find(joint.name);
    const bool fixed = joint.type == urdf::Joint::FIXED || lock != locked_.end();
    if (lock != locked_.end()) {  // where the joint at that position puts the child
      const SimTK::UnitVec3 u(joint.axis.x, joint.axis.y, joint.axis.z);
      X_PJ = X_PJ * (joint.type == urdf::Joint::PRISMATIC
                         ? SimTK::Transform(lock->second * u.asVec3())
                         : SimTK::Transform(SimTK::Rotation(lock->second, u)));
    }
    const bool massless = !child->inertial || !(child->inertial->mass > 0.0);
    if (fixed && massless) {
      addLink(*child, parent, X_PJ);
      return;
    }
    // A massless link that moves carries moving links (the controller locks any joint that
    // moves nothing): a body of no mass, which Simbody takes anywhere but at a tip.
    SimTK::MassProperties mass = massless ? SimTK::MassProperties(0, SimTK::Vec3(0), SimTK::Inertia(0))
                                          : massProperties(*child->inertial);
    if (const auto a = armature_.find(joint.name); !fixed && a != armature_.end() && a->second > 0.0) {
      // The rotor: a disk on the joint axis at the joint (the child's origin), no extra mass.
      const SimTK::Vec3 u = SimTK::UnitVec3(joint.axis.x, joint.axis.y, joint.axis.z).asVec3();
      const SimTK::Mat33 axial = u * ~u;
      const SimTK::Mat33 rotor = a->second * axial + 0.5 * a->second * (SimTK::Mat33(1) - axial);
      mass = SimTK::MassProperties(mass.getMass(), mass.getMassCenter(),
                                   SimTK::Inertia(mass.getInertia().toMat33() + rotor));
    }
    const SimTK::Body::Rigid body(mass);
    SimTK::MobilizedBody& P = mb_.matter.updMobilizedBody(parent);
    const SimTK::UnitVec3 axis(joint.axis.x, joint.axis.y, joint.axis.z);
    SimTK::MobilizedBodyIndex index;
    switch (fixed ? urdf::Joint::FIXED : joint.type) {
      case urdf::Joint::FIXED:
        index = SimTK::MobilizedBody::Weld(P, X_PJ, body, SimTK::Transform())
                    .getMobilizedBodyIndex();
        break;
      case urdf::Joint::REVOLUTE:
      case urdf::Joint::CONTINUOUS: {
        // A Pin turns about z of its frames: align z with the URDF axis on both sides.
        const SimTK::Rotation R_JM(axis, SimTK::ZAxis);
        index = SimTK::MobilizedBody::Pin(P, X_PJ * SimTK::Transform(R_JM), body,
                                          SimTK::Transform(R_JM))
                    .getMobilizedBodyIndex();
        break;
      }
      case urdf::Joint::PRISMATIC: {
        const SimTK::Rotation R_JM(axis, SimTK::XAxis);  // a Slider moves along x
        index = SimTK::MobilizedBody::Slider(P, X_PJ * SimTK::Transform(R_JM), body,
                                             SimTK::Transform(R_JM))
                    .getMobilizedBodyIndex();
        break;
      }
      default:
        throw std::runtime_error("joint '" + joint.name + "' has a type Simbody is not given");
    }
    if (!fixed) {
      mb_.jointNames.push_back(joint.name);
      mb_.jointBody[joint.name] = index;
      mb_.effortLimit[joint.name] = joint.limits ? joint.limits->effort : 0.0;
      const bool bounded = joint.type != urdf::Joint::CONTINUOUS && joint.limits &&
                           joint.limits->lower < joint.limits->upper;
      mb_.positionLimits[joint.name] =
          bounded ? std::make_pair(joint.limits->lower, joint.limits->upper)
                  : std::make_pair(-SimTK::Infinity, SimTK::Infinity);
    }
    addLink(*child, index, SimTK::Transform());
  }

  const urdf::ModelInterface& urdf_;
  UrdfMultibody& mb_;
  std::map<std::string, int> order_;
  const std::map<std::string, double>& armature_;
  const std::map<std::string, double>& locked_;
};

}  // namespace

std::unique_ptr<UrdfMultibody> buildUrdfMultibody(const std::string& urdfPath,
                                                  const std::map<std::string, double>& armature,
                                                  const std::map<std::string, double>& locked) {
  std::ifstream in(urdfPath);
  if (!in) throw std::runtime_error(urdfPath + ": cannot read the URDF");
  std::stringstream text;
  text << in.rdbuf();
  const urdf::ModelInterfaceSharedPtr parsed = urdf::parseURDF(text.str());
  if (!parsed) throw std::runtime_error(urdfPath + ": urdfdom could not parse the URDF");
  auto mb = std::make_unique<UrdfMultibody>();
  mb->robotName = parsed->getName();
  try {
    Builder(*parsed, *mb, plugin::jointFileOrder(text.str()), armature, locked).build();
  } catch (const std::exception& e) {
    throw std::runtime_error(urdfPath + ": " + e.what());
  }
  return mb;
}

}  // namespace ballast::simbody
