// What a simulation backend builds its robot from besides the URDF, read once from
// backend::Config: the contact points (name, URDF link, position on it) and, per joint, the
// armature and the position of a joint the controller's model holds (the simulation welds it),
// and the IMU's frame.
// Throws std::runtime_error naming the Config field that is wrong.
#pragma once

#include <array>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "backend_abi.hpp"
#include "settings_schema.hpp"

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
  /// Config::imu_frame (the controller's IMU); link "" when not given.
  struct Frame {
    std::string link;
    std::array<double, 3> position{0, 0, 0}, rpy{0, 0, 0};
  } imu;
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
  if (config.imu_frame) {
    const backend::SensorFrame& f = *config.imu_frame;
    if (!f.link || !*f.link) throw std::runtime_error("Config::imu_frame has no link");
    robot.imu.link = f.link;
    for (std::size_t k = 0; k < 3; ++k) robot.imu.position[k] = f.position[k], robot.imu.rpy[k] = f.rpy[k];
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

/// A simulation's IMU where the controller's is (Config::imu_frame), unless its section's
/// imu.frame places it elsewhere (a mounting error to simulate): settings `s` with imu_frame.
template <typename Settings>
void placeImuAsTheRobotsUnlessGiven(Settings& s, const SimulatedRobot& robot) {
  if (robot.imu.link.empty() || s.location.count("imu.frame")) return;
  s.imu_frame.link = robot.imu.link;
  s.imu_frame.offset = robot.imu.position;
  s.imu_frame.rpy = robot.imu.rpy;
}

}  // namespace ballast::plugin
