// The socket server's settings (the profile's server section, daemon/profile/schema.cpp).
#pragma once

#include <sys/types.h>

#include <cstddef>
#include <string>
#include <vector>

namespace ballast::server {

struct ServerConfig {
  std::string socket_path;  ///< empty: protocol::defaultSocketPath()
  std::vector<uid_t> allowed_uids;
  double lease_timeout;  ///< s of wall time; 0: never
  std::size_t max_message_bytes;
  int max_clients;
  double max_watch_rate;
  double reply_timeout;  ///< s of wall time
};

}  // namespace ballast::server
