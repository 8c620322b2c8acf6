// The server's transport: the listening socket, its clients and their lines, signals, and the
// poll loop that serves them. A line is a request when it is a JSON object whose "cmd" and
// fields fit protocol::kCommands; it then goes to its verb's handler (verbs()).
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/signalfd.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include <spdlog/spdlog.h>

#include "common/format.hpp"  // plugins/common
#include "server/server.hpp"
#include "server/server_detail.hpp"

namespace ballast::server {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace detail;

namespace {

/// A client that reads nothing while asking for more is dropped past this backlog.
constexpr std::size_t kMaxBacklog = 16u << 20;

std::string fieldList(const protocol::Command& c) {
  std::string s;
  for (std::size_t i = 0; i < c.num_fields; ++i)
    s += (i ? ", " : "") + std::string(c.fields[i].name);
  return s.empty() ? "none" : s;
}

std::string commandList() {
  std::string s;
  for (const auto& c : protocol::kCommands) s += (s.empty() ? "" : ", ") + std::string(c.name);
  return s;
}

/// Checks a request's fields against its command; "" if fine, else the message (code set).
std::string validate(const protocol::Command& spec, const json& request, const char*& code) {
  for (const auto& [key, value] : request.items()) {
    if (key == "id") {
      if (!value.is_number() && !value.is_string() && !value.is_null()) {
        code = protocol::kBadType;
        return "id must be a number or a string";
      }
      continue;
    }
    if (key == "cmd") continue;
    if (key == "lease" || key == "client") {
      if (!value.is_string()) {
        code = protocol::kBadType;
        return key + " must be a string";
      }
      continue;
    }
    const protocol::Field* field = nullptr;
    for (std::size_t i = 0; i < spec.num_fields; ++i)
      if (key == spec.fields[i].name) field = &spec.fields[i];
    if (!field) {
      code = protocol::kUnknownField;
      return std::string("unknown field '") + key + "' for " + spec.name +
             " (its fields: " + fieldList(spec) + ")";
    }
    auto wrongType = [&] {
      code = protocol::kBadType;
      return std::string(spec.name) + ": " + key + " must be " +
             protocol::fieldTypeName(field->type);
    };
    auto inRange = [&](double v) -> std::string {
      if (v >= field->min && v <= field->max) return "";
      code = protocol::kOutOfRange;
      return std::string(spec.name) + ": " + key + " " + formatNumber(v) + " is out of range [" +
             formatNumber(field->min) + ", " + formatNumber(field->max) + "]";
    };
    switch (field->type) {
      case protocol::FieldType::kNumber:
        if (!value.is_number()) return wrongType();
        if (auto e = inRange(value.get<double>()); !e.empty()) return e;
        break;
      case protocol::FieldType::kInteger:
        if (!value.is_number_integer()) return wrongType();
        if (auto e = inRange(value.get<double>()); !e.empty()) return e;
        break;
      case protocol::FieldType::kString:
        if (!value.is_string()) return wrongType();
        break;
      case protocol::FieldType::kPath:
        if (!value.is_string()) return wrongType();
        if (value.get<std::string>().empty() || value.get<std::string>()[0] != '/') {
          code = protocol::kOutOfRange;
          return std::string(spec.name) + ": " + key + " must be absolute (the daemon's working " +
                 "directory is not yours), got '" + value.get<std::string>() + "'";
        }
        break;
      case protocol::FieldType::kBool:
        if (!value.is_boolean()) return wrongType();
        break;
      case protocol::FieldType::kVector3:
        if (!value.is_array() || value.size() != 3) return wrongType();
        for (const auto& v : value) {
          if (!v.is_number()) return wrongType();
          if (auto e = inRange(v.get<double>()); !e.empty()) return e;
        }
        break;
    }
  }
  for (std::size_t i = 0; i < spec.num_fields; ++i)
    if (spec.fields[i].required && !request.contains(spec.fields[i].name)) {
      code = protocol::kMissingField;
      return std::string(spec.name) + " needs " + spec.fields[i].name + " (" + spec.fields[i].doc +
             ")";
    }
  return "";
}

}  // namespace

ServerConfig serverConfig(const profile::Settings& settings, const std::string& socket_override) {
  ServerConfig c = settings.server;
  if (!socket_override.empty())
    c.socket_path = socket_override;
  else if (c.socket_path.empty())
    c.socket_path = protocol::defaultSocketPath();
  return c;
}


Server::Server(DaemonContext& context, ServerConfig config)
    : ctx_(context), config_(std::move(config)) {
  extras_.backend = ctx_.backend_name;
  extras_.simulation = ctx_.simulation;
  extras_.joint_names = ctx_.loop->jointNames();
}

Server::~Server() {
  close();
}

void Server::open() {
  const std::string& path = config_.socket_path;
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  if (path.size() >= sizeof(addr.sun_path))
    throw std::runtime_error("socket path " + path + " is longer than " +
                             std::to_string(sizeof(addr.sun_path) - 1) +
                             " characters: choose a shorter --socket or " +
                             keyOf(config_, &config_.socket_path));
  std::memcpy(addr.sun_path, path.c_str(), path.size() + 1);

  const fs::path dir = fs::path(path).parent_path();
  std::error_code ec;
  if (!dir.empty() && !fs::exists(dir)) {
    fs::create_directories(dir, ec);
    if (ec)
      throw std::runtime_error("cannot create the socket directory " + dir.string() + ": " +
                               ec.message());
    ::chmod(dir.c_str(), 0750);
  }
  if (fs::exists(fs::symlink_status(path))) {
    const int probe = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    const bool alive = ::connect(probe, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) == 0;
    ::close(probe);
    if (alive)
      throw std::runtime_error("another ballastd is already listening on " + path +
                               ": stop it first (ballast --socket " + path +
                               " status), or choose another --socket");
    ::unlink(path.c_str());  // a stale socket from a daemon that died
  }
  listen_fd_ = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (listen_fd_ < 0) throw std::runtime_error(std::string("socket(): ") + std::strerror(errno));
  const mode_t old = ::umask(0117);  // the socket file is born 0660
  const int bound = ::bind(listen_fd_, reinterpret_cast<sockaddr*>(&addr), sizeof(addr));
  const int bindErrno = errno;
  ::umask(old);
  if (bound != 0) throw std::runtime_error("cannot bind " + path + ": " + std::strerror(bindErrno));
  ::chmod(path.c_str(), 0660);
  if (::listen(listen_fd_, 16) != 0)
    throw std::runtime_error("listen on " + path + ": " + std::strerror(errno));

  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGHUP);
  signal_fd_ = ::signalfd(-1, &set, SFD_NONBLOCK | SFD_CLOEXEC);
  if (signal_fd_ < 0) throw std::runtime_error(std::string("signalfd(): ") + std::strerror(errno));
  spdlog::info("listening on {} (mode 0660)", path);
}

void Server::close() {
  waitForMapLoad();
  if (map_load_fd_ >= 0) {
    ::close(map_load_fd_);
    map_load_fd_ = -1;
  }
  for (auto& [fd, c] : clients_) ::close(fd);
  clients_.clear();
  if (listen_fd_ >= 0) {
    ::close(listen_fd_);
    listen_fd_ = -1;
    ::unlink(config_.socket_path.c_str());
  }
  if (signal_fd_ >= 0) {
    ::close(signal_fd_);
    signal_fd_ = -1;
  }
}

void Server::run() {
  while (!stop_) {
    std::vector<pollfd> fds;
    fds.push_back({listen_fd_, POLLIN, 0});
    fds.push_back({signal_fd_, POLLIN, 0});
    fds.push_back({ctx_.loop->wakeFd(), POLLIN, 0});
    fds.push_back({map_load_fd_, POLLIN, 0});  // ignored by poll while -1
    for (auto& [fd, c] : clients_)
      fds.push_back({fd, static_cast<short>(POLLIN | (c.out.empty() ? 0 : POLLOUT)), 0});

    // Wake for the next watch line or pending deadline, at least every 200 ms.
    auto next = Clock::now() + std::chrono::milliseconds(200);
    for (auto& [fd, c] : clients_)
      if (c.watch_rate > 0) next = std::min(next, c.next_watch);
    for (auto& [seq, p] : pending_)
      if (!p.answered) next = std::min(next, p.deadline);
    const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(next - Clock::now());
    const int timeout = static_cast<int>(std::max<long>(0, wait.count()));
    if (::poll(fds.data(), fds.size(), timeout) < 0 && errno != EINTR)
      throw std::runtime_error(std::string("poll(): ") + std::strerror(errno));

    if (fds[1].revents & POLLIN) onSignal();
    if (fds[2].revents & POLLIN) onLoopReplies();
    if (fds[3].revents & POLLIN) finishMapLoad();
    if (fds[0].revents & POLLIN) accept();
    for (std::size_t i = 4; i < fds.size(); ++i) {
      const int fd = fds[i].fd;
      if (!clients_.count(fd)) continue;
      if (fds[i].revents & (POLLIN | POLLHUP | POLLERR)) readFrom(clients_.at(fd));
      if (clients_.count(fd) && (fds[i].revents & POLLOUT)) flush(clients_.at(fd));
    }
    onLoopReplies();  // replies that arrived while we served clients
    sendWatches();
    expirePending();
  }
  spdlog::info("stopping: {} client(s) disconnected", clients_.size());
}

void Server::onSignal() {
  signalfd_siginfo info;
  while (::read(signal_fd_, &info, sizeof(info)) == static_cast<ssize_t>(sizeof(info))) {
    if (info.ssi_signo == SIGHUP) {
      spdlog::info("SIGHUP: reloading {}", ctx_.profile->path());
      switchProfile(nullptr, nullptr, ctx_.profile->path());
    } else {
      spdlog::info("{}: shutting down", info.ssi_signo == SIGTERM ? "SIGTERM" : "SIGINT");
      stop_ = true;
    }
  }
}

void Server::accept() {
  for (;;) {
    const int fd = ::accept4(listen_fd_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) return;
    ucred cred{};
    socklen_t len = sizeof(cred);
    if (::getsockopt(fd, SOL_SOCKET, SO_PEERCRED, &cred, &len) != 0) {
      ::close(fd);
      continue;
    }
    auto refuse = [&](const char* code, const std::string& message) {
      const std::string text = line(
          json{{"id", nullptr}, {"ok", false}, {"error", {{"code", code}, {"message", message}}}});
      [[maybe_unused]] const ssize_t n = ::send(fd, text.data(), text.size(), MSG_NOSIGNAL);
      ::close(fd);
    };
    const bool allowed = cred.uid == ::getuid() ||
                         std::find(config_.allowed_uids.begin(), config_.allowed_uids.end(),
                                   cred.uid) != config_.allowed_uids.end();
    if (!allowed) {
      spdlog::warn("refused a connection from uid {} (pid {}): not in {}", cred.uid, cred.pid,
                   keyOf(config_, &config_.allowed_uids));
      refuse(protocol::kPermissionDenied,
             "uid " + std::to_string(cred.uid) +
                 " may not use this ballastd: ask its operator to add it to " +
                 keyOf(config_, &config_.allowed_uids));
      continue;
    }
    if (static_cast<int>(clients_.size()) >= config_.max_clients) {
      refuse(protocol::kTooManyClients, "ballastd serves at most " +
                                            std::to_string(config_.max_clients) +
                                            " clients (" + keyOf(config_, &config_.max_clients) +
                                            "): try again later");
      continue;
    }
    Client& c = clients_[fd];
    c.fd = fd;
    c.uid = cred.uid;
    c.pid = cred.pid;
    spdlog::debug("client connected: fd {} uid {} pid {}", fd, c.uid, c.pid);
  }
}

void Server::drop(int fd) {
  spdlog::debug("client disconnected: fd {}", fd);
  ::close(fd);
  clients_.erase(fd);
  // What it waits for is answered to nobody, not to a client that gets the same fd later.
  for (auto& [seq, p] : pending_)
    if (p.client == fd) p.client = -1;
  if (map_load_ && map_load_->client == fd) map_load_->client = -1;
}

void Server::readFrom(Client& c) {
  char buf[65536];
  for (;;) {
    const ssize_t n = ::recv(c.fd, buf, sizeof(buf), 0);
    if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) {
      drop(c.fd);
      return;
    }
    if (n < 0) return;
    c.in.append(buf, static_cast<std::size_t>(n));
    // Complete lines; an overlong one is answered once and skipped up to its newline.
    const int fd = c.fd;
    for (std::size_t nl; (nl = c.in.find('\n')) != std::string::npos;) {
      std::string line = c.in.substr(0, nl);
      c.in.erase(0, nl + 1);
      if (c.discarding) {
        c.discarding = false;
        continue;
      }
      if (line.size() > config_.max_message_bytes) {
        fail(fd, nullptr, protocol::kTooLarge,
             "request of " + std::to_string(line.size()) + " bytes is over the limit of " +
                 std::to_string(config_.max_message_bytes) + " (" +
                 keyOf(config_, &config_.max_message_bytes) + ")");
        continue;
      }
      handleLine(c, line);
      if (!clients_.count(fd)) return;
    }
    if (c.in.size() > config_.max_message_bytes) {
      fail(fd, nullptr, protocol::kTooLarge,
           "request is over the limit of " + std::to_string(config_.max_message_bytes) +
               " bytes (" + keyOf(config_, &config_.max_message_bytes) +
               "); it is skipped up to its end of line");
      c.in.clear();
      c.discarding = true;
    }
  }
}

void Server::handleLine(Client& c, const std::string& line) {
  if (line.find_first_not_of(" \t\r") == std::string::npos) return;
  json request;
  try {
    request = json::parse(line);
  } catch (const json::parse_error& e) {
    std::string why = e.what();
    if (const auto p = why.find("parse error"); p != std::string::npos) why = why.substr(p);
    fail(c.fd, nullptr, protocol::kBadJson, "not JSON: " + why);
    return;
  }
  if (!request.is_object()) {
    fail(c.fd, nullptr, protocol::kBadJson, "a request is a JSON object: {\"cmd\": ...}");
    return;
  }
  const json id = request.contains("id") ? request["id"] : json(nullptr);
  if (!request.contains("cmd")) {
    fail(c.fd, id, protocol::kMissingField,
         "a request needs \"cmd\" (one of " + commandList() + ")");
    return;
  }
  if (!request["cmd"].is_string()) {
    fail(c.fd, id, protocol::kBadType, "cmd must be a string");
    return;
  }
  const std::string cmd = request["cmd"].get<std::string>();
  const protocol::Command* spec = protocol::findCommand(cmd);
  if (!spec) {
    fail(c.fd, id, protocol::kUnknownCommand,
         "unknown command '" + cmd + "' (commands: " + commandList() + ")");
    return;
  }
  const char* code = protocol::kBadJson;
  if (const std::string why = validate(*spec, request, code); !why.empty()) {
    fail(c.fd, id, code, why);
    return;
  }
  if (request.contains("client")) c.name = request["client"].get<std::string>();
  if (spec->needs_lease && !checkLease(c, id, request.value("lease", std::string()))) return;
  const int fd = c.fd;
  const auto verb = std::find_if(verbs().begin(), verbs().end(),
                                 [&](const Verb& v) { return cmd == v.name; });
  try {
    (this->*verb->handle)(c, Request{*spec, id, request});
  } catch (const std::exception& e) {  // a request never takes the daemon down
    spdlog::error("{}: {}", cmd, e.what());
    fail(fd, id, protocol::kIoError, cmd + " failed: " + e.what() + " (see the daemon's log)");
  }
}

void Server::reply(int client, const json& id, json body) {
  const auto it = clients_.find(client);
  if (it == clients_.end()) return;
  json answer = {{"id", id}, {"ok", true}};
  answer.update(body);
  send(it->second, line(answer));
}

void Server::fail(int client, const json& id, const char* code, const std::string& message) {
  const auto it = clients_.find(client);
  if (it == clients_.end()) return;
  send(it->second,
       line(json{{"id", id}, {"ok", false}, {"error", {{"code", code}, {"message", message}}}}));
}

void Server::send(Client& c, const std::string& text) {
  // The log is never behind an answer: the loop pushed its events before it published the
  // state an answer shows, so a client that reads a mode or a flag finds its log line written.
  logLoopEvents();
  if (c.out.size() > kMaxBacklog) {
    spdlog::warn("client fd {} (uid {}) reads nothing back: disconnected", c.fd, c.uid);
    drop(c.fd);
    return;
  }
  c.out += text;
  flush(c);
}

void Server::flush(Client& c) {
  while (!c.out.empty()) {
    const ssize_t n = ::send(c.fd, c.out.data(), c.out.size(), MSG_NOSIGNAL);
    if (n < 0) {
      if (errno == EAGAIN || errno == EWOULDBLOCK) return;
      if (errno == EINTR) continue;
      drop(c.fd);
      return;
    }
    c.out.erase(0, static_cast<std::size_t>(n));
  }
}

}  // namespace ballast::server
