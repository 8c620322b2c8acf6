// The kinematic tree of a floating-base robot: constant after loading.
//
// Bodies are numbered in depth-first order (parent[i] < i), body 0 is the floating base.
// Every other body is attached to its parent by a one-degree-of-freedom joint (revolute or
// prismatic); URDF fixed joints are merged into their parent body and survive as frames.
//
// Configuration and velocity (Pinocchio's free-flyer convention):
//   q = [p (3, base origin in world), quaternion (x, y, z, w) of the base, q_j (nj)]  nq = 7 + nj
//   v = [v_b (3, base origin velocity in base frame), ω_b (3, base frame), q̇_j (nj)] nv = 6 + nj
// Joint j (0-based, actuated) is body j + 1, with q index 7 + j and v index 6 + j.
// See base_conventions.hpp for the paper's ZYX-Euler base coordinates and their maps.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "model/spatial.hpp"

namespace ballast::model {

enum class JointType { FreeFlyer, Revolute, Prismatic };

/// A named frame rigidly attached to a body (a URDF link, merged or not, e.g. a contact point).
struct Frame {
  std::string name;
  int body = 0;                  ///< body the frame moves with
  SE3<double> placement;         ///< frame pose in the body frame
};

/// Raised for a model that cannot be built; the message names the file and the element.
struct ModelError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A URDF joint the model holds at a position (merged into its parent body like a fixed joint)
/// and why: the profile locked it, it mimics another joint, or it moves nothing with inertia.
struct LockedJoint {
  std::string name;
  double position = 0.0;  ///< rad, or m for a prismatic joint
  bool prismatic = false;
  std::string reason;     ///< for people: the caller's reason, "mimics joint 'x'", ...
};

struct Model {
  std::string name;        ///< the URDF robot name
  std::string sourceFile;  ///< where it was loaded from (for messages)

  int nq = 7;
  int nv = 6;

  // Per body (size nbodies()).
  std::vector<std::string> bodyName;        ///< URDF link name of the body
  std::vector<std::string> jointName;       ///< URDF joint that moves it ("" for the base)
  std::vector<int> parent;                  ///< parent body, -1 for the base
  std::vector<JointType> jointType;
  std::vector<Vec3<double>> jointAxis;      ///< unit axis in the body frame
  std::vector<SE3<double>> jointPlacement;  ///< joint frame at q = 0 in the parent body frame
  std::vector<Inertia<double>> inertia;     ///< body inertia in the body frame (merged links included)

  // Per actuated joint (size nj()).
  VecX<double> lowerPositionLimit;
  VecX<double> upperPositionLimit;
  VecX<double> velocityLimit;
  VecX<double> effortLimit;
  /// Reflected rotor inertia (kg·m², kg for a prismatic joint): the motor's rotor inertia times
  /// the gear ratio squared, added to the joint's own entry of M (Pinocchio's and MuJoCo's
  /// armature). Zero unless the profile gives it (robot.armature); the URDF has no element for it.
  VecX<double> armature;

  std::vector<Frame> frames;  ///< one per URDF link (base and merged ones included)
  /// The URDF's movable joints that are not the model's, in file order; a simulation welds them
  /// at their positions so that it simulates the robot the controller models.
  std::vector<LockedJoint> lockedJoints;

  Vec3<double> gravity{0.0, 0.0, -9.81};

  int nbodies() const { return static_cast<int>(parent.size()); }
  int nj() const { return nv - 6; }
  static int qIndexOfJoint(int j) { return 7 + j; }
  static int vIndexOfJoint(int j) { return 6 + j; }

  double totalMass() const {
    double m = 0.0;
    for (const auto& I : inertia) m += I.mass;
    return m;
  }

  /// Index of the actuated joint with this URDF name, -1 if none.
  int findJoint(const std::string& name) const {
    for (int i = 1; i < nbodies(); ++i)
      if (jointName[i] == name) return i - 1;
    return -1;
  }
  /// Index of the frame with this name, -1 if none.
  int findFrame(const std::string& name) const {
    for (int i = 0; i < static_cast<int>(frames.size()); ++i)
      if (frames[i].name == name) return i;
    return -1;
  }
  /// Index of the frame with this name; throws ModelError naming the model file if absent.
  int frameId(const std::string& name) const {
    const int f = findFrame(name);
    if (f < 0) throw ModelError(sourceFile + ": no link or frame named '" + name + "'");
    return f;
  }
  /// Index of the actuated joint with this name; throws ModelError naming the model if absent.
  int jointId(const std::string& name) const {
    const int j = findJoint(name);
    if (j < 0) throw ModelError(sourceFile + ": no movable joint named '" + name + "'");
    return j;
  }
};

}  // namespace ballast::model
