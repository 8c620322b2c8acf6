// Shared by the Simbody backend tests and the simulation benchmark: the humanoid's Config and
// joint PD gains that hold a posture.
#pragma once

#include <cstdint>
#include <string>

#include "backend_abi.hpp"

namespace ballast::simbody::test {

inline const char* const kContactFrames[] = {"left_toe", "left_heel", "right_toe", "right_heel"};

inline std::string humanoidUrdfPath() { return std::string(BALLAST_SOURCE_DIR) + "/urdf/humanoid.urdf"; }

/// A backend::Config for the humanoid; the strings must outlive it.
struct SimConfig {
  std::string yaml;
  std::string origin = "test.yaml:1";
  std::string urdf = humanoidUrdfPath();
  std::string map;
  std::uint64_t seed = 1;
  bool lockstep = true;
  double period = 0.001;

  backend::Config config() const {
    backend::Config c;
    c.section_yaml = yaml.c_str();
    c.section_origin = origin.c_str();
    c.urdf_path = urdf.c_str();
    c.terrain_map = map.c_str();
    c.contact_frames = kContactFrames;
    c.num_contacts = 4;
    c.period = period;
    c.lockstep = lockstep;
    c.seed = seed;
    return c;
  }
};

inline bool contains(const char* name, const char* part) {
  return std::string(name).find(part) != std::string::npos;
}

/// Joint-space PD on q_des (no feed-forward): stiff legs, softer arms and wrists.
inline void holdPosture(const backend::Capabilities& caps, const double* qDes,
                        backend::Commands& commands) {
  commands.num_joints = caps.num_joints;
  for (int j = 0; j < caps.num_joints; ++j) {
    const char* name = caps.joint_names[j];
    backend::JointCommand& c = commands.joint[j];
    c = backend::JointCommand{};
    c.q_des = qDes[j];
    if (contains(name, "wrist")) {
      c.kp = 20, c.kd = 0.5;
    } else if (contains(name, "shoulder") || contains(name, "elbow")) {
      c.kp = 100, c.kd = 2;
    } else if (contains(name, "ankle")) {
      c.kp = 800, c.kd = 8;
    } else {  // hips and knees
      c.kp = 2000, c.kd = 30;
    }
  }
}

}  // namespace ballast::simbody::test
