// ballastd --describe-robot URDF: what a user bringing up a new robot needs to know of its URDF,
// and a starter profile for it.
//
// The description (mass, the limbs' share of it, the joint table, the joints the URDF locks by
// itself, the limbs found in the tree, the feet) is written as YAML comments above a profile
// that runs the robot in the Simbody simulation, so that
//   ballastd --describe-robot robot.urdf > robot.yaml && ballastd --check --profile robot.yaml
// is the first step. What it guesses and how:
//   - legs: the two limbs (chains from a branching body to a leaf) whose leaves are lowest at the
//     zero posture, left the one at +y; arms: the other limbs; every other movable joint is in
//     a group "torso";
//   - contact points: toe and heel at the front and back of the bottom face of the foot link's
//     largest collision box, on its centre line (no box: 8 cm ahead of and behind the link's
//     origin, said in a comment);
//   - the standing posture: a knee bend of 0.8 rad shared by the leg's first and last pitch
//     joints (axes along y at the zero posture) so the soles stay level, within the limits;
//   - heights: the base's height over the soles in that posture, the pose-height bounds around
//     it; the IMU on the base; the simulated lidar 10 cm above the highest link.
#pragma once

#include <string>

namespace ballast::daemon {

/// The description and starter profile of the robot in `urdfPath`, as YAML text; throws
/// model::ModelError (file:line: element: what) for a URDF the loader refuses.
std::string describeRobot(const std::string& urdfPath);

}  // namespace ballast::daemon
