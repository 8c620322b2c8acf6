// The plugin's entry symbol (plugins/backend_abi.hpp): the only exported name of
// libballast_backend_socketcan.so.
#include "socketcan_backend.hpp"

namespace {

ballast::backend::Backend* create() { return new ballast::socketcan::SocketcanBackend; }
void destroy(ballast::backend::Backend* backend) { delete backend; }

const ballast::backend::BackendEntry kEntry{
    ballast::backend::kBackendAbiVersion, "socketcan",
    "SocketCAN hardware: MIT-protocol motors on one or more CAN buses and an IMU on the bus; "
    "candump logs; lockstep on emulated buses",
    &create, &destroy, &ballast::socketcan::SocketcanBackend::check,
    &ballast::socketcan::socketcanSettingsDoc};

}  // namespace

extern "C" __attribute__((visibility("default"))) const ballast::backend::BackendEntry*
ballast_backend_entry() {
  return &kEntry;
}
