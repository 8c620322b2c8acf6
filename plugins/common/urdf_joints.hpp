// What a backend needs of the robot's URDF beyond its own section: the joints in file order
// (urdfdom keeps them in a name-sorted map) and, for the movable ones, their limits.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace ballast::plugin {

struct UrdfJoint {
  std::string name;
  bool movable = false;  ///< revolute, continuous or prismatic
  double effort = 0.0;   ///< <limit effort>, 0 if none
  double velocity = 0.0; ///< <limit velocity>, 0 if none
};

/// Joint name -> its position among the <joint> elements of the file.
std::map<std::string, int> jointFileOrder(const std::string& xml);

/// Every joint of the URDF file, in file order. Throws std::runtime_error naming the file when
/// it cannot be read or parsed.
std::vector<UrdfJoint> urdfJoints(const std::string& path);

}  // namespace ballast::plugin
