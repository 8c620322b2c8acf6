// A Simbody multibody system built from a URDF with urdfdom directly — independently of the
// daemon's model loader, which makes it a fair oracle for daemon/model and keeps the plugin
// free of daemon internals.
//
// Every URDF link with <inertial> becomes a Simbody body: the root on a Free mobilizer, links on
// revolute/continuous joints on Pin, prismatic on Slider, fixed ones on Weld. Links without
// <inertial> or of zero mass (contact points, sensor frames) fixed to their parent are not
// bodies: they are frames on their nearest massive ancestor (linkFrame); moved by a joint, they
// are bodies without mass. Simbody's Free mobilizer has q = (quaternion, position) and
// u = (ω, v) with world axes; the Pin's q and u are the joint angle and rate.
//
// For the simulation backend it also keeps what the URDF says about collisions (box, sphere and
// cylinder <collision> elements, on their bodies), joint position limits and the link tree.
//
// Compile users with -UNDEBUG (see DEPENDENCIES.md and ballast_use_simbody()).
#pragma once

#include <Simbody.h>

#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace ballast::simbody {

struct UrdfMultibody {
  /// A URDF link as a frame on a Simbody body.
  struct LinkFrame {
    SimTK::MobilizedBodyIndex body;
    SimTK::Transform inBody;  ///< link frame in the body frame
  };

  SimTK::MultibodySystem system;
  SimTK::SimbodyMatterSubsystem matter{system};
  SimTK::GeneralForceSubsystem forces{system};

  std::string robotName;
  SimTK::MobilizedBodyIndex base;                      ///< root link, Free mobilizer
  std::vector<std::string> jointNames;                 ///< movable joints, in file order
  std::map<std::string, SimTK::MobilizedBodyIndex> jointBody;  ///< movable joint -> body it moves
  std::map<std::string, LinkFrame> linkFrame;          ///< every link
  std::map<std::string, double> effortLimit;           ///< movable joint -> URDF effort
  /// Movable joint -> URDF position limits (lower, upper); ±infinity for continuous joints.
  std::map<std::string, std::pair<double, double>> positionLimits;
  std::map<std::string, std::string> parentLink;       ///< link -> parent link ("" for the root)

  /// A URDF <collision> element on its body. Cylinders are kept as their bounding box; meshes
  /// are not kept (collisionSkipped counts them).
  struct CollisionShape {
    enum class Kind { kBox, kSphere };
    std::string link;
    SimTK::MobilizedBodyIndex body;
    SimTK::Transform inBody;  ///< shape frame in the body frame
    Kind kind = Kind::kBox;
    SimTK::Vec3 halfSize{0};  ///< box half extents; sphere: radius in [0]
  };
  std::vector<CollisionShape> collisionShapes;
  int collisionSkipped = 0;

  const SimTK::MobilizedBody& body(SimTK::MobilizedBodyIndex i) const {
    return matter.getMobilizedBody(i);
  }
};

/// Builds the system (topology not yet realized). Throws std::runtime_error naming the file.
///
/// armature (joint -> kg·m², the controller's robot.armature) puts each joint's rotor on the
/// body it moves, as a disk on the joint axis at the joint: its armature about the axis, half of
/// it across. Simbody has no reflected inertia; the disk gives the joint's own entry of M
/// exactly and couples it to the parent's rotation about the same axis as a rotor turning at
/// the joint's rate would (a real rotor turns N times faster, so the coupling of a gear ratio N
/// is N times smaller): the controller's model (armature on the diagonal only) differs from
/// this world by that coupling and the disk's transverse inertia.
///
/// locked (joint -> position, the controller's robot.locked_joints) welds each of those joints
/// at that position: its child moves with the parent, and it is none of jointNames.
std::unique_ptr<UrdfMultibody> buildUrdfMultibody(const std::string& urdfPath,
                                                  const std::map<std::string, double>& armature = {},
                                                  const std::map<std::string, double>& locked = {});

}  // namespace ballast::simbody
