// The plugin's entry symbol (plugins/backend_abi.hpp): the only exported name of
// libballast_backend_mujoco.so.
#include "mujoco_backend.hpp"

namespace {

ballast::backend::Backend* create() { return new ballast::mujoco::MujocoBackend; }
void destroy(ballast::backend::Backend* backend) { delete backend; }

const ballast::backend::BackendEntry kEntry{
    ballast::backend::kBackendAbiVersion, "mujoco",
    "MuJoCo 2.2.2 simulation: the URDF robot on an OctoMap terrain, MuJoCo's soft contact, motor "
    "model, IMU and lidar, pushes; lockstep or real time",
    &create, &destroy, nullptr,  // no check yet: ballastd --check says so
    &ballast::mujoco::mujocoSettingsDoc};

}  // namespace

extern "C" __attribute__((visibility("default"))) const ballast::backend::BackendEntry*
ballast_backend_entry() {
  return &kEntry;
}
