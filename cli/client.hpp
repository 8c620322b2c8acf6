// A connection to ballastd: one JSON request, one reply line; or a stream of lines (watch).
// Every failure to talk to the daemon comes back as a message saying what to do.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace ballast::cli {

/// --socket, else $BALLAST_SOCKET, else the protocol's default path.
std::string socketPath(const std::string& option);

/// Where the CLI keeps the command lease token for a socket: --lease-file, else
/// $BALLAST_LEASE_FILE, else a file per socket in $XDG_RUNTIME_DIR/ballast (or /tmp/ballast-UID).
std::string leaseFile(const std::string& option, const std::string& socket);

class Connection {
 public:
  ~Connection();
  /// False (error says why and what to do) if no daemon answers on path.
  bool open(const std::string& path, std::string& error);
  /// Sends request (an "id" is added) and waits up to timeout_s for its reply.
  bool request(nlohmann::json request, nlohmann::json& reply, std::string& error, double timeout_s);
  /// Next line from the daemon (for watch); false on timeout (error empty) or a lost connection.
  bool readLine(nlohmann::json& line, std::string& error, int timeout_ms);

 private:
  bool send(const std::string& line, std::string& error);
  int fd_ = -1;
  std::string path_, buffer_;
  long next_id_ = 1;
};

}  // namespace ballast::cli
