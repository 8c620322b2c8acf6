// The status object's field names (DESIGN.md: scripts rely on them) and the server's settings
// from a profile, without a daemon.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "profile/profile.hpp"
#include "server/protocol.hpp"
#include "server/server.hpp"
#include "server/status_json.hpp"
#include "test/unit/test_support.hpp"

namespace ballast::server {
namespace {

TEST(StatusJson, CarriesTheDesignNames) {
  control::LoopStatus s;
  s.t = 1.5;
  s.mode = control::Mode::kStand;
  s.base.position[2] = 0.89;
  s.base.rpy[1] = 0.1;
  s.command.velocity_active = true;
  s.command.expires_at = 2.0;
  s.contacts[0] = true;
  s.tick_overruns = 3;
  s.faults.add(control::FaultKind::kFall, 1.2, "base tilted 0.90 rad");
  StatusExtras x;
  x.profile = "sim-flat";
  x.backend = "simbody";
  nlohmann::json j = statusJson(s, x);
  EXPECT_EQ(j["mode"], "stand");
  EXPECT_EQ(j["t"], 1.5);
  EXPECT_EQ(j["profile"], "sim-flat");
  EXPECT_EQ(j["backend"], "simbody");
  EXPECT_EQ(j["fallen"], false);
  EXPECT_EQ(j["base"]["position"][2], 0.89);
  EXPECT_EQ(j["base"]["velocity"].size(), 3u);
  EXPECT_EQ(j["base"]["rpy"][1], 0.1);
  EXPECT_DOUBLE_EQ(j["command"]["ttl"].get<double>(), 0.5);  // time left, not the deadline
  EXPECT_EQ(j["contacts"], nlohmann::json({true, false, false, false}));
  EXPECT_EQ(j["timing"]["tick_overruns"], 3);
  EXPECT_TRUE(j["timing"].contains("mpc_ms"));
  EXPECT_TRUE(j["timing"].contains("wbc_ms"));
  EXPECT_EQ(j["faults"][0]["kind"], "fall");
  EXPECT_EQ(j["faults"][0]["message"], "base tilted 0.90 rad");
  EXPECT_FALSE(j.contains("truth"));  // no ground truth on hardware
  s.has_truth = true;
  s.truth.position[0] = std::nan("");
  j = statusJson(s, x, true);
  // NaN goes out as null (JSON has no NaN).
  EXPECT_TRUE(nlohmann::json::parse(j.dump())["truth"]["base"]["position"][0].is_null());
  EXPECT_TRUE(j["joints"].contains("q"));
}

// The server dispatches through one table bound to the protocol's: a verb without a handler, or a
// handler for no verb, fails here.
TEST(Protocol, EveryVerbHasOneHandlerAndEveryHandlerAVerb) {
  std::vector<std::string> verbs;
  for (const auto& c : protocol::kCommands) verbs.push_back(c.name);
  std::vector<std::string> handled = Server::handledVerbs();
  std::sort(verbs.begin(), verbs.end());
  std::sort(handled.begin(), handled.end());
  EXPECT_EQ(std::adjacent_find(handled.begin(), handled.end()), handled.end()) << "a verb twice";
  EXPECT_EQ(handled, verbs);
}

// ballastd(8) lists the commands as the protocol table does.
TEST(Protocol, TheManPageListsTheTable) {
  const std::string man = test::sourceFile("man/ballastd.8");
  const auto intro = man.find("Commands (fields in brackets are optional");
  ASSERT_NE(intro, std::string::npos);
  const auto begin = man.find(".nf\n", intro) + 4, end = man.find(".fi\n", begin);
  EXPECT_EQ(man.substr(begin, end - begin), protocol::commandSynopsis())
      << "man/ballastd.8's command list differs from daemon/server/protocol.hpp's table";
}

TEST(Protocol, EveryCommandIsFoundAndMotionNeedsTheLease) {
  for (const auto& c : protocol::kCommands) EXPECT_EQ(protocol::findCommand(c.name), &c);
  EXPECT_EQ(protocol::findCommand("dance"), nullptr);
  EXPECT_FALSE(protocol::findCommand("estop")->needs_lease);
  EXPECT_FALSE(protocol::findCommand("status")->needs_lease);
  for (const char* motion :
       {"stand", "walk", "pose", "stop", "reset", "passive", "push", "profile_use"})
    EXPECT_TRUE(protocol::findCommand(motion)->needs_lease) << motion;
}

TEST(ServerConfig, FromTheProfileAndTheCommandLine) {
  const profile::Profile p =
      profile::Profile::load(std::string(BALLAST_SOURCE_DIR) + "/profiles/hardware-example.yaml");
  ServerConfig c = serverConfig(p, "");
  EXPECT_EQ(c.socket_path, "/run/ballast/ballastd.sock");
  EXPECT_DOUBLE_EQ(c.lease_timeout, 120.0);
  EXPECT_EQ(c.max_message_bytes, 65536u);
  c = serverConfig(p, "/tmp/x.sock");
  EXPECT_EQ(c.socket_path, "/tmp/x.sock");
  const profile::Profile flat =
      profile::Profile::load(std::string(BALLAST_SOURCE_DIR) + "/profiles/sim-flat.yaml");
  EXPECT_EQ(serverConfig(flat, "").socket_path, protocol::defaultSocketPath());
}

}  // namespace
}  // namespace ballast::server
