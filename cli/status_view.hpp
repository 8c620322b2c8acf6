// Human renderings of what the daemon says: the status summary (`status`, `status --watch`),
// and dotted-path lookups in it (`status --get base.position`).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace ballast::cli {

/// The status object as an aligned, multi-line summary.
std::string renderStatus(const nlohmann::json& status);

/// The value at a dotted path ("base.position", "timing.tick_overruns", "contacts.0"), as text:
/// strings bare, numbers in full precision, lists space-separated. False if there is none.
bool lookup(const nlohmann::json& object, const std::string& path, std::string& text);

}  // namespace ballast::cli
