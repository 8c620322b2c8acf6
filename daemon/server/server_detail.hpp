// What the server's files share: the clock, protocol lines, names of the server's own settings.
#pragma once

#include <chrono>
#include <string>

#include <nlohmann/json.hpp>

#include "profile/settings.hpp"
#include "server/server_config.hpp"

namespace ballast::server::detail {

using Clock = std::chrono::steady_clock;

inline double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

inline Clock::time_point after(double seconds) {
  return Clock::now() +
         std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

/// One protocol line. Invalid UTF-8 (a file name, a YAML value) is replaced, never thrown on.
inline std::string line(const nlohmann::json& j) {
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

/// The profile key of one of the server's settings, for messages.
inline const char* keyOf(const ServerConfig& c, const void* field) {
  const char* key = profile::keyOf(c, field);
  return key ? key : "?";
}

}  // namespace ballast::server::detail
