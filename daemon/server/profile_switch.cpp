// Profiles at run time: list, show, and switch (`profile_use`, SIGHUP). A switch loads and
// validates the new profile against the robot model first, refuses one that changes a restart
// key, loads its terrain map, and only then hands its settings to the loop; the running profile
// stays until the loop has taken them.
#include <algorithm>
#include <filesystem>
#include <set>

#include <spdlog/spdlog.h>

#include "server/server.hpp"
#include "server/server_detail.hpp"

namespace ballast::server {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace detail;

std::vector<std::string> Server::profileDirs() const {
  std::vector<std::string> dirs{fs::path(ctx_.profile->path()).parent_path().string()};
  dirs.insert(dirs.end(), ctx_.profile_dirs.begin(), ctx_.profile_dirs.end());
  return dirs;
}

void Server::profileList(Client& c, const Request& r) {
  json list = json::array();
  std::set<std::string> seen;
  for (const auto& d : profileDirs()) {
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
  reply(c.fd, r.id, {{"profiles", list}, {"running", ctx_.profile->name()}});
}

void Server::profileShow(Client& c, const Request& r) {
  if (!r.fields.contains("name")) {
    reply(c.fd, r.id, {{"profile", ctx_.profile->name()}, {"text", ctx_.profile->describe()}});
    return;
  }
  std::string path;
  try {
    path = profile::resolveProfile(r.text("name"), profileDirs());
  } catch (const profile::ProfileError& e) {
    fail(c.fd, r.id, protocol::kNotFound, e.what());
    return;
  }
  try {
    const profile::Profile p = profile::Profile::load(path, ctx_.profile_dirs);
    reply(c.fd, r.id, {{"profile", p.name()}, {"text", p.describe()}});
  } catch (const profile::ProfileError& e) {
    fail(c.fd, r.id, protocol::kInvalidProfile, e.what());
  }
}

void Server::profileUse(Client& c, const Request& r) { switchProfile(&c, r.id, r.text("name")); }

void Server::switchProfile(Client* c, const json& id, const std::string& name) {
  auto refuse = [&](const char* code, const std::string& message) {
    if (c)
      fail(c->fd, id, code, message);
    else
      spdlog::error("profile reload refused, {} stays:\n{}", ctx_.profile->name(), message);
  };
  for (const auto& [seq, p] : pending_)
    if (p.profile) {
      refuse(protocol::kBusy, "another profile switch is in progress: try again");
      return;
    }
  std::string path;
  try {
    path = profile::resolveProfile(name, profileDirs());
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
  const std::string& m = all->terrain_map;
  const double ground = all->control.ground_height;
  if (m != ctx_.map.path() || ground != ctx_.map.ground()) {
    if (map_load_) {
      refuse(protocol::kBusy, "profile " + next->name() + " changes the terrain map while " +
                                  map_load_->path + " is loading: try again when it is in");
      return;
    }
    map = std::make_unique<TerrainMap>(ground);
    std::string error;
    if (!m.empty() && !map->load(m, ground, all->mapping.map.rule, error)) {
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
      std::make_shared<const control::ControlSettings>(all->control), oc.sequence);
  Pending* p = enqueue(oc);
  if (!p) {
    refuse(protocol::kBusy, "the control loop's command queue is full: try again");
    return;
  }
  p->cmd = "profile_use";
  if (c) {
    p->client = c->fd;
    p->id = id;
  } else {
    p->deadline = after(60.0);
    p->answered = true;  // nobody to answer
  }
  p->profile = std::move(next);
  p->map = std::move(map);
  p->config = serverConfig(*all, config_.socket_path);
}

void Server::finishSwitch(Pending& p, bool applied, const char* message) {
  if (applied) {
    ctx_.settings = p.settings;
    if (ctx_.planner) ctx_.planner->requestSettings(p.settings);
    if (p.map) {
      ctx_.map = std::move(*p.map);
      try {
        ctx_.map.handTo(*ctx_.mapper);
      } catch (const std::exception& e) {  // the tree was read and checked already
        spdlog::error("profile {}: the live map keeps its terrain: {}", p.profile->name(), e.what());
      }
    }
    spdlog::info("profile {} in force ({})", p.profile->name(), message);
    ctx_.profile = std::move(p.profile);
    config_ = p.config;
  }
  p.profile.reset();
  p.settings.reset();  // the keeper frees them once the loop lets go
}

}  // namespace ballast::server
