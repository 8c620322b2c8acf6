// The plugin's entry symbol (plugins/backend_abi.hpp): the only exported name of
// libballast_backend_simbody.so.
#include "simbody_backend.hpp"

namespace {

ballast::backend::Backend* create() { return new ballast::simbody::SimbodyBackend; }
void destroy(ballast::backend::Backend* backend) { delete backend; }

const ballast::backend::BackendEntry kEntry{
    ballast::backend::kBackendAbiVersion, "simbody",
    "Simbody simulation: the URDF robot on an OctoMap terrain, compliant contact, motor model, "
    "IMU and lidar, pushes; lockstep or real time",
    &create, &destroy};

}  // namespace

extern "C" __attribute__((visibility("default"))) const ballast::backend::BackendEntry*
ballast_backend_entry() {
  return &kEntry;
}
