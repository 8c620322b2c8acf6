// The plugin's entry symbol (plugins/backend_abi.hpp): the only exported name of
// libballast_backend_simbody.so.
#include "simbody_backend.hpp"

namespace {

ballast::backend::Backend* create() { return new ballast::simbody::SimbodyBackend; }
void destroy(ballast::backend::Backend* backend) { delete backend; }

/// Everything configure() checks is what building the world checks (the URDF as Simbody reads
/// it, the links the frames name, the terrain map), so a check builds it and lets it go: tens of
/// milliseconds, nothing started.
bool check(const ballast::backend::Config& config, ballast::backend::Error& error) {
  ballast::simbody::SimbodyBackend backend;
  return backend.configure(config, error);
}

const ballast::backend::BackendEntry kEntry{
    ballast::backend::kBackendAbiVersion, "simbody",
    "Simbody simulation: the URDF robot on an OctoMap terrain, compliant contact, motor model, "
    "IMU and lidar, pushes; lockstep or real time",
    &create, &destroy, &check, &ballast::simbody::simSettingsDoc};

}  // namespace

extern "C" __attribute__((visibility("default"))) const ballast::backend::BackendEntry*
ballast_backend_entry() {
  return &kEntry;
}
