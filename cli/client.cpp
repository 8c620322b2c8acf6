#include "cli/client.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "server/protocol.hpp"

namespace ballast::cli {

using nlohmann::json;

std::string socketPath(const std::string& option) {
  if (!option.empty()) return option;
  if (const char* env = std::getenv("BALLAST_SOCKET"); env && *env) return env;
  return protocol::defaultSocketPath();
}

std::string leaseFile(const std::string& option, const std::string& socket) {
  if (!option.empty()) return option;
  if (const char* env = std::getenv("BALLAST_LEASE_FILE"); env && *env) return env;
  const char* runtime = std::getenv("XDG_RUNTIME_DIR");
  const std::string dir = runtime && *runtime ? std::string(runtime) + "/ballast"
                                              : "/tmp/ballast-" + std::to_string(getuid());
  // FNV-1a of the socket's absolute path: one lease file per daemon.
  std::uint64_t h = 1469598103934665603ull;
  for (char c : std::filesystem::absolute(socket).lexically_normal().string())
    h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ull;
  char name[32];
  std::snprintf(name, sizeof(name), "lease-%016llx", static_cast<unsigned long long>(h));
  return dir + "/" + name;
}

Connection::~Connection() {
  if (fd_ >= 0) ::close(fd_);
}

bool Connection::open(const std::string& path, std::string& error) {
  path_ = path;
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  if (path.size() >= sizeof(addr.sun_path)) {
    error = "socket path " + path + " is too long";
    return false;
  }
  std::memcpy(addr.sun_path, path.c_str(), path.size() + 1);
  fd_ = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (::connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) == 0) return true;
  const int e = errno;
  ::close(fd_);
  fd_ = -1;
  if (e == ENOENT)
    error = "no ballastd at " + path +
            ": start one (ballastd --profile FILE), or point at it with --socket PATH or "
            "BALLAST_SOCKET";
  else if (e == ECONNREFUSED)
    error = "nothing listens on " + path +
            " (left behind by a ballastd that died?): start ballastd again";
  else if (e == EACCES)
    error = "permission denied on " + path +
            ": join the socket's group, and ask the operator to list your uid in "
            "server.allowed_uids";
  else
    error = "cannot connect to " + path + ": " + std::strerror(e);
  return false;
}

bool Connection::send(const std::string& line, std::string& error) {
  std::size_t done = 0;
  while (done < line.size()) {
    const ssize_t n = ::send(fd_, line.data() + done, line.size() - done, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      error = "lost the connection to ballastd at " + path_ + ": " + std::strerror(errno) +
              " (is it still running? try `ballast status`)";
      return false;
    }
    done += static_cast<std::size_t>(n);
  }
  return true;
}

bool Connection::readLine(json& line, std::string& error, int timeout_ms) {
  error.clear();
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    if (const auto nl = buffer_.find('\n'); nl != std::string::npos) {
      const std::string text = buffer_.substr(0, nl);
      buffer_.erase(0, nl + 1);
      try {
        line = json::parse(text);
        return true;
      } catch (const json::parse_error&) {
        error = "ballastd sent a line that is not JSON: " + text.substr(0, 200);
        return false;
      }
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                          deadline - std::chrono::steady_clock::now())
                          .count();
    if (left <= 0) return false;
    pollfd p{fd_, POLLIN, 0};
    const int r = ::poll(&p, 1, static_cast<int>(left));
    if (r < 0 && errno == EINTR) continue;
    if (r == 0) return false;
    char buf[65536];
    const ssize_t n = ::recv(fd_, buf, sizeof(buf), 0);
    if (n <= 0) {
      error = "ballastd at " + path_ + " closed the connection (did it stop? try `ballast status`)";
      return false;
    }
    buffer_.append(buf, static_cast<std::size_t>(n));
  }
}

bool Connection::request(json request, json& reply, std::string& error, double timeout_s) {
  const long id = next_id_++;
  request["id"] = id;
  request["client"] = "ballast";
  if (!send(request.dump() + "\n", error)) return false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                          deadline - std::chrono::steady_clock::now())
                          .count();
    if (left <= 0 || !readLine(reply, error, static_cast<int>(left))) {
      if (error.empty())
        error = "ballastd at " + path_ + " did not answer within " + std::to_string(timeout_s) +
                " s: it may be stuck; check its log";
      return false;
    }
    if (reply.contains("event")) continue;  // a watch line, not our answer
    if (reply.value("id", json()) == json(id) || reply.value("id", json()).is_null()) return true;
  }
}

}  // namespace ballast::cli
