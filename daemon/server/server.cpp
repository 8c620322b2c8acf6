#include "server/server.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/eventfd.h>
#include <sys/random.h>
#include <sys/signalfd.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <set>
#include <stdexcept>

#include <spdlog/spdlog.h>

#include "common/format.hpp"  // plugins/common
#include "profile/settings.hpp"
#include "server/protocol.hpp"

namespace ballast::server {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

namespace {

std::string randomToken() {
  unsigned char bytes[16];
  if (getrandom(bytes, sizeof(bytes), 0) != static_cast<ssize_t>(sizeof(bytes)))
    for (auto& b : bytes) b = static_cast<unsigned char>(std::rand());
  static const char* hex = "0123456789abcdef";
  std::string s;
  for (unsigned char b : bytes) s += {hex[b >> 4], hex[b & 15]};
  return s;
}

double seconds(Clock::duration d) {
  return std::chrono::duration<double>(d).count();
}

/// One protocol line. Invalid UTF-8 (a file name, a YAML value) is replaced, never thrown on.
std::string line(const json& j) {
  return j.dump(-1, ' ', false, json::error_handler_t::replace) + "\n";
}

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

double numberOr(const json& r, const char* key, double fallback) {
  return r.contains(key) ? r[key].get<double>() : fallback;
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

namespace {
/// The profile key of one of the configuration's fields, for messages.
const char* keyOf(const ServerConfig& c, const void* field) {
  const char* key = profile::keyOf(c, field);
  return key ? key : "?";
}
}  // namespace

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
    if (fds[0].revents & POLLIN) accept();
    for (std::size_t i = 3; i < fds.size(); ++i) {
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
  if (spec->needs_lease && !checkLease(c, id, request)) return;
  const int fd = c.fd;
  try {
    dispatch(c, id, cmd, request);
  } catch (const std::exception& e) {  // a request never takes the daemon down
    spdlog::error("{}: {}", cmd, e.what());
    fail(fd, id, protocol::kIoError, cmd + " failed: " + e.what() + " (see the daemon's log)");
  }
}

bool Server::leaseExpired() const {
  return lease_ && config_.lease_timeout > 0 &&
         seconds(Clock::now() - lease_->last_used) > config_.lease_timeout;
}

json Server::leaseJson() const {
  if (!lease_ || leaseExpired()) return {{"held", false}};
  const auto now = Clock::now();
  return {{"held", true},
          {"uid", lease_->uid},
          {"pid", lease_->pid},
          {"client", lease_->client},
          {"age_s", seconds(now - lease_->since)},
          {"idle_s", seconds(now - lease_->last_used)}};
}

bool Server::checkLease(Client& c, const json& id, const json& request) {
  if (leaseExpired()) {
    spdlog::info("the command lease of uid {} lapsed ({})", lease_->uid,
                 keyOf(config_, &config_.lease_timeout));
    lease_.reset();
  }
  if (!lease_) {
    fail(c.fd, id, protocol::kNoLease,
         "motion commands need the command lease: run `ballast lease acquire` first (the "
         "ballast CLI acquires it by itself when it is free)");
    return false;
  }
  const std::string token = request.value("lease", std::string());
  if (token != lease_->token) {
    fail(c.fd, id, protocol::kLeaseHeld,
         "the command lease is held by uid " + std::to_string(lease_->uid) + " (pid " +
             std::to_string(lease_->pid) + (lease_->client.empty() ? "" : ", " + lease_->client) +
             ") for " + formatNumber(std::round(seconds(Clock::now() - lease_->since))) +
             " s: wait until it is returned, or take it over with `ballast lease take`");
    return false;
  }
  lease_->last_used = Clock::now();
  return true;
}

void Server::dispatch(Client& c, const json& id, const std::string& cmd, const json& r) {
  using control::CommandKind;
  control::OperatorCommand oc;
  if (cmd == "version") {
    reply(c.fd, id,
          {{"version", BALLAST_VERSION}, {"protocol", protocol::kVersion}, {"pid", ::getpid()}});
  } else if (cmd == "status") {
    reply(c.fd, id, {{"status", status(r.value("joints", false))}});
  } else if (cmd == "watch") {
    const double rate = numberOr(r, "rate", 10.0);
    if (rate > config_.max_watch_rate) {
      fail(c.fd, id, protocol::kOutOfRange,
           "watch: rate " + formatNumber(rate) + " is over " +
               keyOf(config_, &config_.max_watch_rate) + " " + formatNumber(config_.max_watch_rate));
      return;
    }
    c.watch_rate = rate;
    c.watch_joints = r.value("joints", false);
    c.next_watch = Clock::now();
    reply(c.fd, id, {{"rate", rate}});
  } else if (cmd == "unwatch") {
    c.watch_rate = 0.0;
    reply(c.fd, id, json::object());
  } else if (cmd == "lease_acquire" || cmd == "lease_take") {
    if (leaseExpired()) lease_.reset();
    const std::string token = r.value("lease", std::string());
    if (lease_ && token == lease_->token) {
      lease_->last_used = Clock::now();
      reply(c.fd, id, {{"lease", lease_->token}, {"renewed", true}});
      return;
    }
    json previous = nullptr;
    if (lease_) {
      if (cmd == "lease_acquire") {
        checkLease(c, id, r);  // replies lease_held with the holder
        return;
      }
      previous = leaseJson();
      spdlog::warn("uid {} (pid {}) took the command lease from uid {} (pid {})", c.uid, c.pid,
                   lease_->uid, lease_->pid);
    }
    lease_ = std::make_unique<Lease>();
    lease_->token = randomToken();
    lease_->uid = c.uid;
    lease_->pid = c.pid;
    lease_->client = c.name;
    lease_->since = lease_->last_used = Clock::now();
    reply(c.fd, id, {{"lease", lease_->token}, {"taken_from", previous}});
  } else if (cmd == "lease_return") {
    if (!lease_ || leaseExpired() || r.value("lease", std::string()) != lease_->token) {
      fail(c.fd, id, protocol::kNoLease, "you do not hold the command lease: nothing to return");
      return;
    }
    lease_.reset();
    reply(c.fd, id, json::object());
  } else if (cmd == "stand") {
    oc.kind = CommandKind::kStand;
    submit(c, id, cmd, oc);
  } else if (cmd == "walk") {
    oc.kind = CommandKind::kWalk;
    oc.vx = numberOr(r, "vx", 0.0);
    oc.vy = numberOr(r, "vy", 0.0);
    oc.yaw_rate = numberOr(r, "yaw_rate", 0.0);
    oc.ttl = numberOr(r, "ttl", 0.0);
    submit(c, id, cmd, oc);
  } else if (cmd == "pose") {
    oc.kind = CommandKind::kPose;
    oc.height = numberOr(r, "height", control::kNaN);
    oc.roll = numberOr(r, "roll", 0.0);
    oc.pitch = numberOr(r, "pitch", 0.0);
    oc.yaw = numberOr(r, "yaw", 0.0);
    submit(c, id, cmd, oc);
  } else if (cmd == "stop" || cmd == "estop" || cmd == "reset" || cmd == "passive") {
    if (cmd == "estop") spdlog::warn("estop from uid {} (pid {})", c.uid, c.pid);
    oc.kind = cmd == "stop"    ? CommandKind::kStop
              : cmd == "estop" ? CommandKind::kEstop
              : cmd == "reset" ? CommandKind::kReset
                               : CommandKind::kPassive;
    submit(c, id, cmd, oc);
  } else if (cmd == "push") {
    oc.kind = CommandKind::kPush;
    for (int i = 0; i < 3; ++i) oc.push.force[i] = r["force"][i].get<double>();
    oc.push.duration = r["duration"].get<double>();
    const std::string body = r.value("body", std::string());
    if (body.size() >= sizeof(oc.push.body)) {
      fail(c.fd, id, protocol::kOutOfRange,
           "push: body name longer than " + std::to_string(sizeof(oc.push.body) - 1) +
               " characters");
      return;
    }
    std::strcpy(oc.push.body, body.c_str());
    submit(c, id, cmd, oc);
  } else if (cmd == "profile_list") {
    reply(c.fd, id, {{"profiles", profileList()}, {"running", ctx_.profile->name()}});
  } else if (cmd == "profile_show") {
    if (!r.contains("name")) {
      reply(c.fd, id, {{"profile", ctx_.profile->name()}, {"text", ctx_.profile->describe()}});
      return;
    }
    std::vector<std::string> dirs{fs::path(ctx_.profile->path()).parent_path().string()};
    dirs.insert(dirs.end(), ctx_.profile_dirs.begin(), ctx_.profile_dirs.end());
    std::string path;
    try {
      path = profile::resolveProfile(r["name"].get<std::string>(), dirs);
    } catch (const profile::ProfileError& e) {
      fail(c.fd, id, protocol::kNotFound, e.what());
      return;
    }
    try {
      const profile::Profile p = profile::Profile::load(path, ctx_.profile_dirs);
      reply(c.fd, id, {{"profile", p.name()}, {"text", p.describe()}});
    } catch (const profile::ProfileError& e) {
      fail(c.fd, id, protocol::kInvalidProfile, e.what());
    }
  } else if (cmd == "profile_use") {
    switchProfile(&c, id, r["name"].get<std::string>());
  } else if (cmd == "map_load") {
    std::string error;
    const std::string path = r["path"].get<std::string>();
    if (!ctx_.map.load(path, ctx_.settings->ground_height, error)) {
      fail(c.fd, id, access(path.c_str(), R_OK) == 0 ? protocol::kIoError : protocol::kNotFound,
           error + "; the map in use stays");
      return;
    }
    if (ctx_.planner) ctx_.planner->setTerrain(ctx_.map.heights());
    spdlog::info("terrain map {} loaded", path);
    reply(c.fd, id, {{"map", ctx_.map.info()}});
  } else if (cmd == "map_info") {
    reply(c.fd, id, {{"map", ctx_.map.info()}});
  } else if (cmd == "record_start") {
    const std::string path = r["path"].get<std::string>();
    std::string error;
    if (path.empty() || path[0] != '/') {
      fail(c.fd, id, protocol::kOutOfRange,
           "record_start: path must be absolute (the daemon's working directory is not yours)");
      return;
    }
    if (!ctx_.writer->startRecording(path, error)) {
      fail(c.fd, id, ctx_.writer->recording() ? protocol::kRefused : protocol::kIoError, error);
      return;
    }
    spdlog::info("recording telemetry to {}", path);
    reply(c.fd, id, {{"path", path}});
  } else if (cmd == "record_stop") {
    std::uint64_t frames = 0;
    std::string path;
    if (!ctx_.writer->stopRecording(frames, path)) {
      fail(c.fd, id, protocol::kRefused, "not recording: start with `ballast record start FILE`");
      return;
    }
    spdlog::info("recording stopped: {} frames in {}", frames, path);
    reply(c.fd, id, {{"path", path}, {"frames", frames}});
  }
}

void Server::submit(Client& c, const json& id, const std::string& cmd,
                    control::OperatorCommand command, std::unique_ptr<profile::Profile> next,
                    std::unique_ptr<TerrainMap> map) {
  if (command.sequence == 0) command.sequence = ++sequence_;
  if (!ctx_.loop->submit(command)) {
    if (command.settings) ctx_.keeper.drop(command.settings);
    fail(c.fd, id, protocol::kBusy, "the control loop's command queue is full: try again");
    return;
  }
  Pending& p = pending_[command.sequence];
  p.client = c.fd;
  p.id = id;
  p.cmd = cmd;
  p.deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                  std::chrono::duration<double>(config_.reply_timeout));
  p.profile = std::move(next);
  if (command.settings) p.settings = *command.settings;
  p.generation = ctx_.loop->status().settings_generation + 1;
  p.map = std::move(map);
}

void Server::switchProfile(Client* c, const json& id, const std::string& name) {
  const int fd = c ? c->fd : -1;
  auto refuse = [&](const char* code, const std::string& message) {
    if (c)
      fail(fd, id, code, message);
    else
      spdlog::error("profile reload refused, {} stays:\n{}", ctx_.profile->name(), message);
  };
  for (const auto& [seq, p] : pending_)
    if (p.profile) {
      refuse(protocol::kBusy, "another profile switch is in progress: try again");
      return;
    }
  std::vector<std::string> dirs{fs::path(ctx_.profile->path()).parent_path().string()};
  dirs.insert(dirs.end(), ctx_.profile_dirs.begin(), ctx_.profile_dirs.end());
  std::string path;
  try {
    path = profile::resolveProfile(name, dirs);
  } catch (const profile::ProfileError& e) {
    refuse(protocol::kNotFound, e.what());
    return;
  }
  std::unique_ptr<profile::Profile> next;
  std::unique_ptr<profile::Settings> all;
  try {
    next = std::make_unique<profile::Profile>(profile::Profile::load(path, ctx_.profile_dirs));
    all = std::make_unique<profile::Settings>(profile::settingsFor(*next, *ctx_.model));
  } catch (const profile::ProfileError& e) {
    refuse(protocol::kInvalidProfile,
           std::string(e.what()) + "\n(profile " + ctx_.profile->name() + " stays in force)");
    return;
  }
  const auto changed = profile::Profile::restartChanges(*ctx_.profile, *next);
  if (!changed.empty()) {
    std::string list;
    for (const auto& k : changed) list += "\n  " + k;
    refuse(protocol::kRefused,
           "profile " + next->name() + " changes keys that need a restart (ballastd --profile " +
               path + "):" + list + "\n(profile " + ctx_.profile->name() + " stays in force)");
    return;
  }
  // The planner's terrain map (and its height grid), loaded before anything changes.
  std::unique_ptr<TerrainMap> map;
  const std::string m = all->terrain_map;
  const double ground = all->control.ground_height;
  if (m != ctx_.map.path() || ground != ctx_.map.heights()->ground()) {
    map = std::make_unique<TerrainMap>(ground);
    std::string error;
    if (!m.empty() && !map->load(m, ground, error)) {
      refuse(protocol::kInvalidProfile,
             next->problem(profile::keyOf(*all, &all->terrain_map), error) + "\n(profile " +
                 ctx_.profile->name() + " stays in force)");
      return;
    }
  }
  control::OperatorCommand oc;
  oc.kind = control::CommandKind::kSwitchSettings;
  oc.sequence = ++sequence_;
  oc.settings = ctx_.keeper.keep(
      std::make_shared<const control::ControlSettings>(std::move(all->control)), oc.sequence);
  if (c) {
    submit(*c, id, "profile_use", oc, std::move(next), std::move(map));
    if (const auto it = pending_.find(sequence_); it != pending_.end() && it->second.profile)
      it->second.config = serverConfig(*all, config_.socket_path);
    return;
  }
  if (!ctx_.loop->submit(oc)) {
    ctx_.keeper.drop(oc.settings);
    spdlog::error("profile reload: the control loop's command queue is full");
    return;
  }
  Pending& p = pending_[oc.sequence];
  p.cmd = "profile_use";
  p.deadline = Clock::now() + std::chrono::seconds(60);
  p.answered = true;  // nobody to answer
  p.profile = std::move(next);
  p.settings = *oc.settings;
  p.generation = ctx_.loop->status().settings_generation + 1;
  p.map = std::move(map);
  p.config = serverConfig(*all, config_.socket_path);
}

void Server::onLoopReplies() {
  std::uint64_t count;
  [[maybe_unused]] const ssize_t n = ::read(ctx_.loop->wakeFd(), &count, sizeof(count));
  control::LoopEvent e;
  while (ctx_.loop->popEvent(e)) {
    if (e.warning)
      spdlog::warn("[t={:.3f}] {}", e.t, e.message);
    else
      spdlog::info("[t={:.3f}] {}", e.t, e.message);
  }
  control::CommandReply r;
  while (ctx_.loop->popReply(r)) {
    const auto it = pending_.find(r.sequence);
    if (it == pending_.end()) continue;
    Pending& p = it->second;
    const bool ok = r.refusal == control::Refusal::kNone;
    if (p.cmd == "profile_use") finishSwitch(p, ok, r.message);
    if (!p.answered && clients_.count(p.client)) {
      if (ok) {
        json body = {{"mode", control::modeName(r.mode)}};
        if (r.message[0]) body["message"] = r.message;
        if (p.cmd == "profile_use" && ctx_.profile) body["profile"] = ctx_.profile->name();
        reply(p.client, p.id, body);
      } else {
        const char* code = r.refusal == control::Refusal::kUnavailable  ? protocol::kUnavailable
                           : r.refusal == control::Refusal::kOutOfRange ? protocol::kOutOfRange
                           : r.refusal == control::Refusal::kBackend    ? protocol::kBackendError
                                                                        : protocol::kRefused;
        fail(p.client, p.id, code, r.message);
      }
    }
    pending_.erase(it);
  }
}

void Server::finishSwitch(Pending& p, bool applied, const char* message) {
  if (applied) {
    ctx_.settings = p.settings;
    if (ctx_.planner) ctx_.planner->requestSettings(*p.settings);
    if (p.map) {
      ctx_.map = std::move(*p.map);
      if (ctx_.planner) ctx_.planner->setTerrain(ctx_.map.heights());
    }
    spdlog::info("profile {} in force ({})", p.profile->name(), message);
    ctx_.profile = std::move(p.profile);
    config_ = p.config;
  }
  p.settings.reset();  // the keeper frees them once the loop lets go
}

void Server::expirePending() {
  const auto now = Clock::now();
  // A command the loop took whose reply never came (its reply ring was full): a switch is
  // settled from the loop's status, so that it neither blocks later ones nor keeps settings.
  const control::LoopStatus status = ctx_.loop->status();
  for (auto it = pending_.begin(); it != pending_.end();) {
    Pending& p = it->second;
    if (now > p.deadline && it->first <= status.last_command) {
      if (p.cmd == "profile_use")
        finishSwitch(p, status.settings_generation >= p.generation, "its reply was lost");
      if (!p.answered && clients_.count(p.client))
        fail(p.client, p.id, protocol::kTimeout, "the control loop's reply was lost: check `ballast status`");
      it = pending_.erase(it);
    } else {
      ++it;
    }
  }
  ctx_.keeper.collect(status.last_command);
  for (auto& [seq, p] : pending_)
    if (!p.answered && now > p.deadline) {
      p.answered = true;  // the loop's late reply is still applied, just not sent
      if (clients_.count(p.client))
        fail(p.client, p.id, protocol::kTimeout,
             std::string("the control loop did not answer within ") +
                 keyOf(config_, &config_.reply_timeout) + " (" +
                 formatNumber(config_.reply_timeout) +
                 " s): check `ballast status` and the daemon's log");
    }
}

json Server::status(bool joints) {
  extras_.profile = ctx_.profile->name();
  extras_.profile_path = ctx_.profile->path();
  extras_.contact_frames.assign(ctx_.settings->contact_frames.begin(),
                                ctx_.settings->contact_frames.end());
  extras_.lease = leaseJson();
  const control::LoopStatus s = ctx_.loop->status();
  extras_.recording = {
      {"active", ctx_.writer->recording()},
      {"path", ctx_.writer->recording() ? json(ctx_.writer->path()) : json(nullptr)},
      {"frames", s.telemetry_frames},
      {"dropped", s.telemetry_dropped}};
  extras_.map = ctx_.map.info();
  return statusJson(s, extras_, joints);
}

void Server::sendWatches() {
  const auto now = Clock::now();
  json plain, withJoints;
  for (auto& [fd, c] : clients_) {
    if (c.watch_rate <= 0 || now < c.next_watch) continue;
    const auto period = std::chrono::duration_cast<Clock::duration>(
        std::chrono::duration<double>(1.0 / c.watch_rate));
    c.next_watch = std::max(c.next_watch + period, now);
    if (c.out.size() > (1u << 20)) continue;  // a client not reading loses lines, nobody waits
    json& s = c.watch_joints ? withJoints : plain;
    if (s.is_null()) s = status(c.watch_joints);
    send(c, line(json{{"event", "status"}, {"status", s}}));
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

json Server::profileList() {
  std::vector<std::string> dirs{fs::path(ctx_.profile->path()).parent_path().string()};
  dirs.insert(dirs.end(), ctx_.profile_dirs.begin(), ctx_.profile_dirs.end());
  json list = json::array();
  std::set<std::string> seen;
  for (const auto& d : dirs) {
    std::error_code ec;
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(d, ec))
      if (entry.path().extension() == ".yaml") files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
      const std::string name = f.stem().string();
      if (!seen.insert(name).second) continue;
      json item = {
          {"name", name}, {"path", f.string()}, {"running", f == fs::path(ctx_.profile->path())}};
      try {
        const profile::Profile p = profile::Profile::load(f.string(), ctx_.profile_dirs);
        item["description"] = profile::readSettings(p).description;
        item["valid"] = true;
      } catch (const profile::ProfileError& e) {
        item["valid"] = false;
        item["problem"] = e.problems.empty() ? "" : e.problems[0];
      }
      list.push_back(item);
    }
  }
  return list;
}

}  // namespace ballast::server
