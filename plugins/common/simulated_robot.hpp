// What a simulation backend builds its robot from besides the URDF, read once from
// backend::Config: the contact points (name, URDF link, position on it) and, per joint, the
// armature and the position of a joint the controller's model holds (the simulation welds it).
// Throws std::runtime_error naming the Config field that is wrong.
#pragma once

#include <array>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "backend_abi.hpp"

namespace ballast::plugin {

struct SimulatedRobot {
  /// A contact point: its name (Config::contact_frames) on a URDF link at a position in that
  /// link's frame (Config::contact_points; the link's own origin when the profile names a link).
  struct ContactPoint {
    std::string name, link;
    std::array<double, 3> position{0, 0, 0};  ///< m
  };
  std::vector<ContactPoint> contacts;       ///< Config::contact_frames order
  std::map<std::string, double> armature;   ///< joint -> kg·m² (kg for a prismatic joint)
  std::map<std::string, double> locked;     ///< joint -> position it is welded at (rad or m)
};

inline SimulatedRobot simulatedRobot(const backend::Config& config) {
  SimulatedRobot robot;
  for (int i = 0; i < config.num_contacts; ++i) {
    if (!config.contact_frames || !config.contact_frames[i])
      throw std::runtime_error("Config::contact_frames[" + std::to_string(i) + "] is missing");
    SimulatedRobot::ContactPoint c;
    c.name = c.link = config.contact_frames[i];
    if (config.contact_points) {
      const backend::ContactPoint& p = config.contact_points[i];
      if (!p.link || !*p.link)
        throw std::runtime_error("Config::contact_points[" + std::to_string(i) + "] has no link");
      c.link = p.link;
      c.position = {p.position[0], p.position[1], p.position[2]};
    }
    robot.contacts.push_back(c);
  }
  for (int i = 0; i < config.num_joint_models; ++i) {
    if (!config.joints || !config.joints[i].name) continue;
    const backend::JointModel& j = config.joints[i];
    if (j.armature < 0.0 || !std::isfinite(j.armature))
      throw std::runtime_error(std::string("Config::joints: joint ") + j.name +
                               ": armature must be finite and >= 0");
    robot.armature[j.name] = j.armature;
    if (j.locked) robot.locked[j.name] = j.locked_position;
  }
  return robot;
}

}  // namespace ballast::plugin
