// Status: one object now (`status`), or a stream of them at a client's rate (`watch`).
#include <algorithm>

#include "common/format.hpp"  // plugins/common
#include "server/server.hpp"
#include "server/server_detail.hpp"

namespace ballast::server {

using nlohmann::json;
using namespace detail;

void Server::statusVerb(Client& c, const Request& r) {
  reply(c.fd, r.id, {{"status", status(r.flag("joints"))}});
}

void Server::watch(Client& c, const Request& r) {
  const double rate = r.number("rate", 10.0);
  if (rate > config_.max_watch_rate) {
    fail(c.fd, r.id, protocol::kOutOfRange,
         "watch: rate " + formatNumber(rate) + " is over " +
             keyOf(config_, &config_.max_watch_rate) + " " + formatNumber(config_.max_watch_rate));
    return;
  }
  c.watch_rate = rate;
  c.watch_joints = r.flag("joints");
  c.next_watch = Clock::now();
  reply(c.fd, r.id, {{"rate", rate}});
}

void Server::unwatch(Client& c, const Request& r) {
  c.watch_rate = 0.0;
  reply(c.fd, r.id, json::object());
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
  extras_.settings_held = ctx_.keeper.held();
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

}  // namespace ballast::server
