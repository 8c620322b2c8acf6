// Shared by the Simbody and MuJoCo backend tests and the simulation benchmark: the humanoid's
// Config, joint PD gains that hold a posture, and a lidar scan sorted against a stage.
#pragma once

#include <algorithm>
#include <cmath>
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

/// A box stage on a flat floor at z = 0, as maps::stage lays it: top at `height` over
/// x in [x0, x1], |y| <= halfWidth.
struct Stage {
  double height, x0, x1, halfWidth;
};

/// The points of a lidar scan placed in the world by the sensor pose (origin o, rotation R row-major)
/// and sorted against a Stage: those inside its top (`margin` in from every edge) and those on the
/// floor (`margin` out from it, with x in [floorX0, floorX1]), each with the largest height error
/// among them and where it was.
struct StageScan {
  int onStage = 0, onFloor = 0;
  double stageError = 0, floorError = 0;
  double worst[3] = {0, 0, 0};
};

inline StageScan sortScanOnStage(const backend::PointCloudView& scan, const double o[3], const double R[9],
                                 const Stage& stage, double margin, double floorX0,
                                 double floorX1) {
  StageScan out;
  double worstError = -1;
  for (int i = 0; i < scan.count; ++i) {
    const float* s = scan.xyz + 3 * i;
    double p[3];
    for (int k = 0; k < 3; ++k) p[k] = o[k] + R[3 * k] * s[0] + R[3 * k + 1] * s[1] + R[3 * k + 2] * s[2];
    double error;
    if (p[0] > stage.x0 + margin && p[0] < stage.x1 - margin && std::abs(p[1]) < stage.halfWidth - margin) {
      ++out.onStage;
      error = std::abs(p[2] - stage.height);
      out.stageError = std::max(out.stageError, error);
    } else if ((p[0] < stage.x0 - margin || p[0] > stage.x1 + margin) && p[0] > floorX0 &&
               p[0] < floorX1) {
      ++out.onFloor;
      error = std::abs(p[2]);
      out.floorError = std::max(out.floorError, error);
    } else {
      continue;
    }
    if (error > worstError) worstError = error, std::copy(p, p + 3, out.worst);
  }
  return out;
}

}  // namespace ballast::simbody::test
