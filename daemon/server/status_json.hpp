// The status object: what `status` replies and `watch` streams. DESIGN.md fixes the names
// scripts rely on (mode, t, profile, backend, fallen, base.position, base.velocity, base.rpy,
// command, contacts, timing.mpc_ms/wbc_ms/tick_overruns, faults, truth on a simulation);
// ballastd(8) documents every field. Fields may be added; none may be renamed.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "control/types.hpp"

namespace ballast::server {

/// What the IO side adds to the loop's status.
struct StatusExtras {
  std::string profile, profile_path, backend;
  bool simulation = false;
  std::vector<std::string> contact_frames;
  std::vector<std::string> joint_names;
  nlohmann::json lease = nullptr, recording = nullptr, map = nullptr;
  std::size_t settings_held = 0;  ///< control::SettingsKeeper::held()
};

nlohmann::json statusJson(const control::LoopStatus& s, const StatusExtras& extras,
                          bool joints = false);

}  // namespace ballast::server
