// The verbs' handlers, bound to protocol::kCommands by one table (verbs()), and the robot's
// commands: they go to the control loop through its command ring and are answered when the loop
// has handled them, or with `timeout`.
#include <unistd.h>

#include <algorithm>
#include <cstring>

#include <spdlog/spdlog.h>

#include "common/format.hpp"  // plugins/common
#include "server/server.hpp"
#include "server/server_detail.hpp"

namespace ballast::server {

using control::CommandKind;
using nlohmann::json;
using namespace detail;

const std::vector<Server::Verb>& Server::verbs() {
  // clang-format off
  static const std::vector<Verb> kVerbs = {
      {"version", &Server::version},
      {"status", &Server::statusVerb},
      {"watch", &Server::watch},
      {"unwatch", &Server::unwatch},
      {"stand", &Server::stand},
      {"walk", &Server::walk},
      {"pose", &Server::pose},
      {"stop", &Server::stop},
      {"estop", &Server::estop},
      {"reset", &Server::reset},
      {"passive", &Server::passive},
      {"push", &Server::push},
      {"advance", &Server::advance},
      {"profile_list", &Server::profileList},
      {"profile_show", &Server::profileShow},
      {"profile_use", &Server::profileUse},
      {"map_load", &Server::mapLoad},
      {"map_info", &Server::mapInfo},
      {"map_clear", &Server::mapClear},
      {"map_save", &Server::mapSave},
      {"record_start", &Server::recordStart},
      {"record_stop", &Server::recordStop},
      {"lease_acquire", &Server::leaseAcquire},
      {"lease_take", &Server::leaseTake},
      {"lease_return", &Server::leaseReturn},
  };
  // clang-format on
  return kVerbs;
}

std::vector<std::string> Server::handledVerbs() {
  std::vector<std::string> names;
  for (const Verb& v : verbs()) names.push_back(v.name);
  return names;
}

void Server::version(Client& c, const Request& r) {
  reply(c.fd, r.id,
        {{"version", BALLAST_VERSION}, {"protocol", protocol::kVersion}, {"pid", ::getpid()}});
}

namespace {
control::OperatorCommand command(CommandKind kind) {
  control::OperatorCommand oc;
  oc.kind = kind;
  return oc;
}
}  // namespace

void Server::stand(Client& c, const Request& r) { submit(c, r, command(CommandKind::kStand)); }
void Server::stop(Client& c, const Request& r) { submit(c, r, command(CommandKind::kStop)); }
void Server::reset(Client& c, const Request& r) { submit(c, r, command(CommandKind::kReset)); }
void Server::passive(Client& c, const Request& r) { submit(c, r, command(CommandKind::kPassive)); }

void Server::estop(Client& c, const Request& r) {
  spdlog::warn("estop from uid {} (pid {})", c.uid, c.pid);
  submit(c, r, command(CommandKind::kEstop));
}

void Server::walk(Client& c, const Request& r) {
  control::OperatorCommand oc = command(CommandKind::kWalk);
  oc.vx = r.number("vx", 0.0);
  oc.vy = r.number("vy", 0.0);
  oc.yaw_rate = r.number("yaw_rate", 0.0);
  oc.ttl = r.number("ttl", 0.0);
  submit(c, r, oc);
}

void Server::pose(Client& c, const Request& r) {
  control::OperatorCommand oc = command(CommandKind::kPose);
  oc.height = r.number("height", control::kNaN);
  oc.roll = r.number("roll", 0.0);
  oc.pitch = r.number("pitch", 0.0);
  oc.yaw = r.number("yaw", 0.0);
  submit(c, r, oc);
}

void Server::push(Client& c, const Request& r) {
  control::OperatorCommand oc = command(CommandKind::kPush);
  for (int i = 0; i < 3; ++i) oc.push.force[i] = r.fields["force"][i].get<double>();
  oc.push.duration = r.number("duration", 0.0);
  const std::string body = r.text("body");
  if (body.size() >= sizeof(oc.push.body)) {
    fail(c.fd, r.id, protocol::kOutOfRange,
         "push: body name longer than " + std::to_string(sizeof(oc.push.body) - 1) + " characters");
    return;
  }
  std::strcpy(oc.push.body, body.c_str());
  submit(c, r, oc);
}

void Server::advance(Client& c, const Request& r) {
  control::OperatorCommand oc = command(CommandKind::kAdvance);
  oc.until = r.number("until", 0.0);
  submit(c, r, oc);
}

void Server::recordStart(Client& c, const Request& r) {
  const std::string path = r.text("path");
  std::string error;
  control::RecordingInfo info;
  if (ctx_.model) info = control::recordingInfo(ctx_.profile ? ctx_.profile->name() : "", *ctx_.model);
  if (!ctx_.writer->startRecording(path, error, info)) {
    fail(c.fd, r.id, ctx_.writer->recording() ? protocol::kRefused : protocol::kIoError, error);
    return;
  }
  spdlog::info("recording telemetry to {}", path);
  reply(c.fd, r.id, {{"path", path}});
}

void Server::recordStop(Client& c, const Request& r) {
  std::uint64_t frames = 0;
  std::string path;
  if (!ctx_.writer->stopRecording(frames, path)) {
    fail(c.fd, r.id, protocol::kRefused, "not recording: start with `ballast record start FILE`");
    return;
  }
  spdlog::info("recording stopped: {} frames in {}", frames, path);
  reply(c.fd, r.id, {{"path", path}, {"frames", frames}});
}

// ---- the loop's commands and replies

Server::Pending* Server::enqueue(control::OperatorCommand& command) {
  if (command.sequence == 0) command.sequence = ++sequence_;
  if (!ctx_.loop->submit(command)) {
    if (command.settings) ctx_.keeper.drop(command.settings);
    return nullptr;
  }
  Pending& p = pending_[command.sequence];
  p.deadline = after(config_.reply_timeout);
  if (command.settings) p.settings = *command.settings;
  p.generation = ctx_.loop->status().settings_generation + 1;
  return &p;
}

void Server::submit(Client& c, const Request& r, control::OperatorCommand command) {
  Pending* p = enqueue(command);
  if (!p) {
    fail(c.fd, r.id, protocol::kBusy, "the control loop's command queue is full: try again");
    return;
  }
  p->client = c.fd;
  p->id = r.id;
  p->cmd = r.command.name;
}

void Server::logLoopEvents() {
  control::LoopEvent e;
  while (ctx_.loop->popEvent(e)) {
    if (e.warning)
      spdlog::warn("[t={:.3f}] {}", e.t, e.message);
    else
      spdlog::info("[t={:.3f}] {}", e.t, e.message);
  }
}

void Server::onLoopReplies() {
  std::uint64_t count;
  [[maybe_unused]] const ssize_t n = ::read(ctx_.loop->wakeFd(), &count, sizeof(count));
  logLoopEvents();
  control::CommandReply r;
  while (ctx_.loop->popReply(r)) {
    const auto it = pending_.find(r.sequence);
    if (it == pending_.end()) continue;
    Pending& p = it->second;
    const bool ok = r.refusal == control::Refusal::kNone;
    const bool switching = p.profile != nullptr;
    if (switching) finishSwitch(p, ok, r.message);
    if (!p.answered && clients_.count(p.client)) {
      if (ok) {
        json body = {{"mode", control::modeName(r.mode)}};
        if (r.message[0]) body["message"] = r.message;
        if (switching && ctx_.profile) body["profile"] = ctx_.profile->name();
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

void Server::expirePending() {
  const auto now = Clock::now();
  // A command the loop took whose reply never came (its reply ring was full): a switch is
  // settled from the loop's status, so that it neither blocks later ones nor keeps settings.
  const control::LoopStatus status = ctx_.loop->status();
  for (auto it = pending_.begin(); it != pending_.end();) {
    Pending& p = it->second;
    if (now > p.deadline && it->first <= status.last_command) {
      if (p.profile) finishSwitch(p, status.settings_generation >= p.generation, "its reply was lost");
      if (!p.answered && clients_.count(p.client))
        fail(p.client, p.id, protocol::kTimeout,
             "the control loop's reply was lost: check `ballast status`");
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

}  // namespace ballast::server
