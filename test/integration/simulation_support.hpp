// Shared by the closed-loop integration tests (balance, estimation, walking): the humanoid in
// the Simbody backend, through the plugin ABI only, in lockstep at 1 kHz.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "backend/plugin_loader.hpp"
#include "model/model.hpp"

namespace ballast::test {

/// The contact points, in the order the tests and the daemon use (left toe, left heel, right
/// toe, right heel).
inline const char* const kContactFrames[] = {"left_toe", "left_heel", "right_toe", "right_heel"};

/// A configured and started simulation of urdf/humanoid.urdf with the backend section
/// `sectionYaml` (reported as coming from `origin`). Throws std::runtime_error with the
/// backend's message when it refuses.
inline backend::BackendPtr startHumanoidSimulation(const backend::Plugin& plugin,
                                                   const std::string& sectionYaml,
                                                   const char* origin, std::uint64_t seed) {
  backend::BackendPtr sim = plugin.create();
  const std::string urdf = std::string(BALLAST_SOURCE_DIR) + "/urdf/humanoid.urdf";
  backend::Config config;
  config.section_yaml = sectionYaml.c_str();
  config.section_origin = origin;
  config.urdf_path = urdf.c_str();
  config.contact_frames = kContactFrames;
  config.num_contacts = 4;
  config.period = 0.001;
  config.lockstep = true;
  config.seed = seed;
  backend::Error error;
  if (!sim->configure(config, error) || !sim->start(error))
    throw std::runtime_error(std::string("simbody backend: ") + error.message);
  return sim;
}

/// Backend joint k <-> model joint (0-based, model order) result[k].
inline std::vector<int> modelJointOfBackendJoint(const model::Model& m,
                                                 const backend::Capabilities& caps) {
  std::vector<int> joint;
  for (int k = 0; k < caps.num_joints; ++k) joint.push_back(m.jointId(caps.joint_names[k]));
  return joint;
}

}  // namespace ballast::test
