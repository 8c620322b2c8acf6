// The lock-free single-producer/single-consumer ring the loop talks to its IO threads through
// (plugins/common/spsc_ring.hpp: the plugins use the same one).
#pragma once

#include "common/spsc_ring.hpp"  // plugins/common

namespace ballast::control {
using ballast::SpscRing;
}  // namespace ballast::control
