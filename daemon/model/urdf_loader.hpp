// URDF -> Model (model.hpp), through urdfdom.
//
// The root link becomes the floating base (a massless root whose only child joint is
// `floating` is skipped, the usual "world" dummy). Revolute, continuous and prismatic joints
// become bodies; fixed joints are merged into their parent body (inertia added, link kept as a
// frame). Bodies are ordered depth first, children in the order their joints appear in the file,
// so joint indices read like the file.
//
// Every defect raises ModelError with "file:line:column: element: what is wrong": a file that
// cannot be read, XML errors, anything urdfdom rejects (not a tree, no root, dangling links),
// unsupported joint types, non-physical inertia (negative mass, not positive semi-definite,
// principal moments against the triangle inequality), limits that are missing, inverted or not
// positive, a zero axis. Elements the model has no use for (<gazebo>, <transmission>, <mujoco>,
// meshes) are ignored; CRLF line endings read as LF.
//
// Locked joints are fixed at a position: merged like fixed joints, the child placed where the
// joint at that position puts it; they are not the model's joints and Model::lockedJoints lists
// them with the reason. They are the caller's (UrdfOptions::locked, the profile's: a name
// that is not a movable joint, or a position outside its limits, is a LockedJointError naming
// the joint), and two kinds the URDF itself cannot actuate: mimic joints (held where their
// leader's locked position, else zero, puts them) and joints that move no inertia (a link
// without <inertial> or of zero mass, and everything below it: a sensor, a frame; held at zero).
// A massless link that carries moving links is a body of zero inertia.
#pragma once

#include <map>
#include <string>

#include "model/model.hpp"

namespace ballast::model {

/// A locked joint the URDF cannot lock (the profile reports it at that entry).
struct LockedJointError : ModelError {
  LockedJointError(const std::string& message, std::string name)
      : ModelError(message), joint(std::move(name)) {}
  std::string joint;
};

struct UrdfOptions {
  std::map<std::string, double> locked;  ///< joint -> position (rad or m) it is fixed at
  std::string lockedReason = "locked on request";  ///< LockedJoint::reason for those
};

Model loadUrdfFile(const std::string& path, const UrdfOptions& options = {});
/// Same, from text; sourceName stands for the file in messages.
Model loadUrdfString(const std::string& xml, const std::string& sourceName,
                     const UrdfOptions& options = {});

}  // namespace ballast::model
