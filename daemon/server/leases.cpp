// The command lease: one client at a time may move the robot. A random token names the holder;
// it lapses after the profile's lease timeout unused; `take` moves it to another client.
#include <sys/random.h>

#include <cmath>
#include <cstdlib>

#include <spdlog/spdlog.h>

#include "common/format.hpp"  // plugins/common
#include "server/server.hpp"
#include "server/server_detail.hpp"

namespace ballast::server {

using nlohmann::json;
using namespace detail;

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
}  // namespace

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

bool Server::checkLease(Client& c, const json& id, const std::string& token) {
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

void Server::leaseAcquire(Client& c, const Request& r) { grantLease(c, r, false); }

void Server::leaseTake(Client& c, const Request& r) { grantLease(c, r, true); }

void Server::grantLease(Client& c, const Request& r, bool take) {
  if (leaseExpired()) lease_.reset();
  const std::string token = r.text("lease");
  if (lease_ && token == lease_->token) {
    lease_->last_used = Clock::now();
    reply(c.fd, r.id, {{"lease", lease_->token}, {"renewed", true}});
    return;
  }
  json previous = nullptr;
  if (lease_) {
    if (!take) {
      checkLease(c, r.id, token);  // replies lease_held with the holder
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
  reply(c.fd, r.id, {{"lease", lease_->token}, {"taken_from", previous}});
}

void Server::leaseReturn(Client& c, const Request& r) {
  if (!lease_ || leaseExpired() || r.text("lease") != lease_->token) {
    fail(c.fd, r.id, protocol::kNoLease, "you do not hold the command lease: nothing to return");
    return;
  }
  lease_.reset();
  reply(c.fd, r.id, json::object());
}

}  // namespace ballast::server
