// The terrain map's verbs: `map load`, `map clear`, `map save`, `map info`.
//
// A map load reads the file, checks it and builds the live map's height grid from it: seconds
// of CPU for a building at a few centimetres (a 21-million-node file takes 2 s of CPU, 6.6 s of
// wall time on a loaded host). It runs on a thread of its own, so that the IO thread keeps
// answering every client meanwhile (an estop above all); its end wakes the IO thread through
// an eventfd and the reply goes out from there. One load at a time, and not beside a profile
// switch that changes the map: either would leave it unclear which map is in use, so the second
// is refused as busy.
#include <sys/eventfd.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include <spdlog/spdlog.h>

#include "control/terrain_mapper.hpp"
#include "server/server.hpp"
#include "server/server_detail.hpp"

namespace ballast::server {

using nlohmann::json;

void Server::mapLoad(Client& c, const Request& r) {
  if (map_load_) {
    fail(c.fd, r.id, protocol::kBusy,
         "map load: " + map_load_->path + " is still loading: try again when it is in");
    return;
  }
  for (const auto& [seq, p] : pending_)
    if (p.map) {
      fail(c.fd, r.id, protocol::kBusy, "map load: a profile switch is changing the map: try again");
      return;
    }
  if (map_load_fd_ < 0) {
    map_load_fd_ = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
    if (map_load_fd_ < 0) {
      fail(c.fd, r.id, protocol::kIoError, std::string("map load: eventfd(): ") + std::strerror(errno));
      return;
    }
  }
  auto job = std::make_unique<MapLoad>();
  job->client = c.fd;
  job->id = r.id;
  job->path = r.text("path");
  const double ground = ctx_.settings->ground_height;
  const terrain::GroundRule rule = ctx_.mapper->settings().map.rule;
  control::TerrainMapper* mapper = ctx_.mapper;
  const int wake = map_load_fd_;
  MapLoad* j = job.get();
  try {
    job->thread = std::thread([j, ground, rule, mapper, wake] {
      std::string error;
      if (!j->map.load(j->path, ground, rule, error)) {
        j->code = ::access(j->path.c_str(), R_OK) == 0 ? protocol::kIoError : protocol::kNotFound;
        j->error = error + "; the map in use stays";
      } else {
        try {
          j->map.handTo(*mapper);  // hands the planner its grid
        } catch (const std::exception& e) {
          j->code = protocol::kIoError;
          j->error = std::string(e.what()) + "; the map in use stays";
        }
      }
      const std::uint64_t one = 1;
      [[maybe_unused]] const ssize_t n = ::write(wake, &one, sizeof(one));
    });
  } catch (const std::system_error& e) {
    fail(c.fd, r.id, protocol::kIoError, std::string("map load: no thread to load it: ") + e.what());
    return;
  }
  map_load_ = std::move(job);
}

void Server::finishMapLoad() {
  std::uint64_t count;
  if (::read(map_load_fd_, &count, sizeof(count)) != static_cast<ssize_t>(sizeof(count)) || !map_load_)
    return;
  std::unique_ptr<MapLoad> job = std::move(map_load_);
  job->thread.join();
  if (job->code) {
    spdlog::warn("map load {} refused: {}", job->path, job->error);
    fail(job->client, job->id, job->code, job->error);
    return;
  }
  ctx_.map = std::move(job->map);
  spdlog::info("terrain map {} loaded", job->path);
  reply(job->client, job->id, mapReply());
}

void Server::waitForMapLoad() {
  if (map_load_ && map_load_->thread.joinable()) map_load_->thread.join();
  map_load_.reset();
}

void Server::mapClear(Client& c, const Request& r) {
  if (map_load_) {
    fail(c.fd, r.id, protocol::kBusy,
         "map clear: " + map_load_->path + " is loading: try again when it is in");
    return;
  }
  ctx_.map = TerrainMap(ctx_.settings->ground_height);
  ctx_.mapper->clear(ctx_.map.ground());
  spdlog::info("terrain map cleared");
  reply(c.fd, r.id, mapReply());
}

void Server::mapSave(Client& c, const Request& r) {
  const std::string path = r.text("path");
  std::string error;
  if (!ctx_.mapper->save(path, error)) {
    fail(c.fd, r.id, protocol::kIoError, error);
    return;
  }
  spdlog::info("terrain map saved to {}", path);
  json j = mapReply();
  j["saved"] = path;
  reply(c.fd, r.id, j);
}

json Server::mapReply() {
  json j = {{"map", ctx_.map.info()}, {"live", ctx_.mapper->info()}};
  if (map_load_) j["loading"] = map_load_->path;
  return j;
}

void Server::mapInfo(Client& c, const Request& r) { reply(c.fd, r.id, mapReply()); }

}  // namespace ballast::server
