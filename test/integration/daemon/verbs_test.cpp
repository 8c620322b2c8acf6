// Every verb of the ballast CLI against ballastd in lockstep on the simulation backend (the
// Simbody plugin when it is built, else the fake): exit status, output, and the daemon's
// state after it. Each test leaves the daemon healthy: status answers, no tick overran, and
// SIGTERM stops it with status 0 and no socket left.
#include <octomap/OcTree.h>

#include <cmath>

#include "test/integration/daemon/daemon_harness.hpp"

namespace ballast::test {
namespace {

class Verbs : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = scratchDir();
    daemon_ = std::make_unique<Daemon>(dir_, SIM_PROFILE);
    ASSERT_TRUE(daemon_->running()) << daemon_->log();
    ASSERT_TRUE(daemon_->waitForMode("stand")) << daemon_->log();
  }
  void TearDown() override {
    if (!daemon_ || !daemon_->running()) return;
    const json s = daemon_->status();
    ASSERT_TRUE(s.is_object()) << "status no longer answers\n" << daemon_->log();
    EXPECT_EQ(daemon_->stop(), 0) << daemon_->log();
    EXPECT_FALSE(fs::exists(daemon_->socket()));
    fs::remove_all(dir_);
  }
  Outcome cli(const std::vector<std::string>& args, const std::string& client = "a") {
    return daemon_->cli(args, client);
  }
  fs::path dir_;
  std::unique_ptr<Daemon> daemon_;
};

TEST_F(Verbs, StatusJsonCarriesTheDesignFields) {
  const Outcome r = cli({"status", "--json"});
  ASSERT_EQ(r.status, 0) << r.err;
  const json s = r.parsed();
  EXPECT_EQ(s["mode"], "stand");
  EXPECT_TRUE(s["t"].is_number());
  EXPECT_EQ(s["profile"], fs::path(SIM_PROFILE).stem().string());
  EXPECT_TRUE(s["backend"].is_string());
  EXPECT_EQ(s["fallen"], false);
  for (const char* k : {"position", "velocity", "rpy"}) {
    ASSERT_TRUE(s["base"][k].is_array()) << k;
    EXPECT_EQ(s["base"][k].size(), 3u) << k;
  }
  for (const char* k : {"vx", "vy", "yaw_rate", "ttl", "height", "roll", "pitch", "yaw"})
    EXPECT_TRUE(s["command"][k].is_number()) << k;
  ASSERT_EQ(s["contacts"].size(), 4u);
  for (const auto& c : s["contacts"]) EXPECT_TRUE(c.is_boolean());
  for (const char* k : {"mpc_ms", "wbc_ms", "tick_overruns"})
    EXPECT_TRUE(s["timing"][k].is_number()) << k;
  EXPECT_TRUE(s["faults"].is_array());
  ASSERT_TRUE(s.contains("truth"));  // a simulation backend
  EXPECT_EQ(s["truth"]["base"]["position"].size(), 3u);
  // Standing: all four contact points down, near the nominal height.
  for (const auto& c : s["contacts"]) EXPECT_TRUE(c.get<bool>()) << s.dump();
  EXPECT_NEAR(s["base"]["position"][2].get<double>(), 0.89, 0.03);
}

TEST_F(Verbs, StatusHumanGetAndWatch) {
  Outcome r = cli({"status"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("mode       stand"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("contacts"), std::string::npos);
  r = cli({"status", "--get", "mode"});
  EXPECT_EQ(r.out, "stand\n");
  r = cli({"status", "--get", "base.position"});
  std::istringstream xyz(r.out);
  double x, y, z;
  EXPECT_TRUE(xyz >> x >> y >> z) << r.out;
  r = cli({"status", "--get", "no.such.field"});
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("no field"), std::string::npos);
  r = cli({"--json", "status", "--get", "no.such.field"});  // scripts get the refusal as JSON
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.parsed()["error"]["code"], "no_field") << r.out;
  // --watch: a stream of status objects, one per line, simulated time moving on (0.2 s of wall
  // time between the first and the last: at 50 per second, a host loaded by builds had stalled
  // the loop for all of the 40 ms).
  r = cli({"--json", "status", "--watch", "--rate", "10", "--count", "3"});
  ASSERT_EQ(r.status, 0) << r.err;
  std::istringstream lines(r.out);
  std::vector<double> times;
  for (std::string line; std::getline(lines, line);)
    times.push_back(json::parse(line)["t"].get<double>());
  ASSERT_EQ(times.size(), 3u);
  EXPECT_LE(times[0], times[1]);
  EXPECT_LT(times[0], times[2]);
  r = cli({"status", "--watch", "--count", "1"});
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("mode"), std::string::npos);
  // The rate bounds the stream (wall time): 4 updates at 5 per second span at least 0.6 s.
  const auto start = std::chrono::steady_clock::now();
  r = cli({"--json", "status", "--watch", "--rate", "5", "--count", "4"});
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 4);
  EXPECT_GE(elapsed, 0.55);
}

TEST_F(Verbs, StandWalkAndStop) {
  Outcome r = cli({"stand"});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("mode stand"), std::string::npos);
  const double x0 = daemon_->status()["truth"]["base"]["position"][0].get<double>();
  r = cli({"walk", "--vx", "0.4", "--for", "3s"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("mode walk"), std::string::npos) << r.out;
  EXPECT_TRUE(daemon_->waitFor([&](const json& s) {
    return s["truth"]["base"]["position"][0].get<double>() > x0 + 0.3;
  })) << daemon_->status().dump();
  r = cli({"stop"});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(daemon_->waitFor([](const json& s) {
    return s["mode"] == "stand" && std::abs(s["truth"]["base"]["velocity"][0].get<double>()) < 0.05;
  })) << daemon_->status().dump();
  EXPECT_FALSE(daemon_->status()["fallen"].get<bool>());
  // Beyond the profile's safety.max_vx: refused, the robot keeps standing.
  r = cli({"--json", "walk", "--vx", "5"});
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.parsed()["error"]["code"], "out_of_range");
  EXPECT_EQ(daemon_->status()["mode"], "stand");
}

TEST_F(Verbs, PoseMovesTheBaseWithinTheProfileLimits) {
  Outcome r = cli({"pose", "--height", "0.82", "--pitch", "4deg"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(daemon_->waitFor([](const json& s) {
    return std::abs(s["base"]["position"][2].get<double>() - 0.82) < 0.01 &&
           std::abs(s["base"]["rpy"][1].get<double>() - 4 * M_PI / 180) < 0.02;
  })) << daemon_->status().dump();
  const json s = daemon_->status();
  EXPECT_DOUBLE_EQ(s["command"]["height"].get<double>(), 0.82);
  // Beyond safety.max_pose_height / max_pose_tilt: refused, the pose in force stays.
  r = cli({"--json", "pose", "--height", "1.5"});
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.parsed()["error"]["code"], "out_of_range");
  EXPECT_NE(r.parsed()["error"]["message"].get<std::string>().find("safety.min_pose_height"),
            std::string::npos);
  r = cli({"pose", "--roll", "60deg"});
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("safety.max_pose_tilt"), std::string::npos) << r.err;
  EXPECT_DOUBLE_EQ(daemon_->status()["command"]["height"].get<double>(), 0.82);
  r = cli({"pose", "--height", "0.86", "--yaw", "-6deg"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(daemon_->waitFor([](const json& s) {
    return std::abs(s["truth"]["base"]["rpy"][2].get<double>() + 6 * M_PI / 180) < 0.01;
  })) << daemon_->status().dump();
  r = cli({"pose", "--yaw", "30deg"});  // beyond safety.max_pose_yaw
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("safety.max_pose_yaw"), std::string::npos) << r.err;
  r = cli({"pose"});  // back to nominal (the loop takes the command at its next tick)
  EXPECT_EQ(r.status, 0);
  EXPECT_TRUE(daemon_->waitFor([](const json& s) {
    return std::abs(s["command"]["height"].get<double>() - 0.89) < 0.01 &&
           std::abs(s["base"]["position"][2].get<double>() - 0.89) < 0.01;
  })) << daemon_->status().dump();
}

TEST_F(Verbs, EstopLatchesUntilResetThenStandAgain) {
  Outcome r = cli({"estop"}, "someone-else");  // anyone may, without the lease
  ASSERT_EQ(r.status, 0) << r.err;
  json s = daemon_->status();
  EXPECT_EQ(s["mode"], "damp");
  EXPECT_EQ(s["estop"], true);
  EXPECT_EQ(s["faults"][0]["kind"], "estop");
  r = cli({"stand"});
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("run `ballast reset`"), std::string::npos) << r.err;
  r = cli({"passive"});
  EXPECT_EQ(r.status, 1);
  r = cli({"reset"});
  ASSERT_EQ(r.status, 0) << r.err;
  s = daemon_->status();
  EXPECT_EQ(s["mode"], "passive");
  EXPECT_EQ(s["estop"], false);
  EXPECT_TRUE(s["faults"].empty());
}

TEST_F(Verbs, PassiveThenStandUp) {
  // Passive lets go of the joints; standing up again straight away catches the robot. In
  // lockstep the robot sags at several times real time, so "straight away" is two requests on
  // one connection (with the CLI's lease), not two CLI processes whose start a loaded machine
  // delays by a simulated second (the CLI's passive is in EstopLatchesUntilResetThenStandAgain).
  Outcome r = cli({"lease", "acquire"});
  ASSERT_EQ(r.status, 0) << r.err;
  std::string lease = readFile((dir_ / "lease-a").string());
  lease = lease.substr(0, lease.find('\n'));
  RawClient c(daemon_->socket());
  json reply = c.ask(R"({"cmd":"passive","lease":")" + lease + R"("})");
  ASSERT_TRUE(reply.value("ok", false)) << reply.dump();
  EXPECT_EQ(reply["mode"], "passive") << reply.dump();
  reply = c.ask(R"({"cmd":"stand","lease":")" + lease + R"("})");
  ASSERT_TRUE(reply.value("ok", false)) << reply.dump();
  EXPECT_EQ(reply["mode"], "stand-up") << reply.dump();
  EXPECT_TRUE(daemon_->waitForMode("stand")) << daemon_->status().dump();
  EXPECT_EQ(daemon_->status()["fallen"], false);
}

TEST_F(Verbs, PushIsBoundedByTheProfile) {
  Outcome r = cli({"push", "--force", "15,0,0", "--duration", "100ms"});
  EXPECT_EQ(r.status, 0) << r.err;
  r = cli({"--json", "push", "--force", "900,0,0", "--duration", "1"});
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.parsed()["error"]["code"], "out_of_range");
  r = cli({"--json", "push", "--force", "10,0,0", "--duration", "0.1", "--body", "no_such_link"});
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.parsed()["error"]["code"], "backend_error") << r.out;
}

TEST_F(Verbs, RecordThenPlot) {
  const std::string file = (dir_ / "run.tsv").string(), png = (dir_ / "run.png").string();
  Outcome r = cli({"record", "start", file});
  ASSERT_EQ(r.status, 0) << r.err;
  r = cli({"record", "start", file});
  EXPECT_EQ(r.status, 1);  // one recording at a time
  const double t0 = daemon_->status()["t"].get<double>();
  ASSERT_TRUE(daemon_->waitFor([&](const json& s) { return s["t"].get<double>() > t0 + 0.3; }));
  EXPECT_EQ(daemon_->status()["recording"]["active"], true);
  r = cli({"--json", "record", "stop"});
  ASSERT_EQ(r.status, 0) << r.err;
  const long frames = r.parsed()["frames"].get<long>();
  EXPECT_GT(frames, 300);
  // One line per control tick; standing under the whole-body controller on the plan, the
  // columns the plots and scripts read are all filled.
  const std::string text = readFile(file);
  EXPECT_EQ(text.rfind("# ballast telemetry 1\n# t\tmode\t", 0), 0u);
  // The header: the names, then the humanoid's four limbs (legs and arms, out to each leaf).
  long limbs = 0;
  for (std::size_t at = text.find("\n# limb "); at != std::string::npos;
       at = text.find("\n# limb ", at + 1))
    ++limbs;
  EXPECT_EQ(limbs, 4);
  EXPECT_NE(text.find("\n# limb left_foot left_hip_yaw "), std::string::npos);
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), frames + 2 + limbs);
  std::istringstream lines(text);
  std::string line;
  std::getline(lines, line);
  std::getline(lines, line);
  std::vector<std::string> columns;
  {
    std::istringstream header(line.substr(2));
    for (std::string c; std::getline(header, c, '\t');) columns.push_back(c);
  }
  const std::vector<std::string> wanted = {
      "x", "vz", "yaw", "wx", "wz", "v_fwd", "true_x", "true_wz", "cmd_height", "contact_3",
      "err_p1", "err_p2", "err_p3", "err_p4", "mpc_ms", "wbc_ms", "tick_ms", "lateness_ms", "limb_err",
      "q_left_knee", "tau_right_elbow", "qref_left_shoulder_pitch"};
  std::vector<std::size_t> at;
  for (const auto& w : wanted) {
    const auto it = std::find(columns.begin(), columns.end(), w);
    ASSERT_NE(it, columns.end()) << w;
    at.push_back(static_cast<std::size_t>(it - columns.begin()));
  }
  long rows = 0;
  double mpc = 0, wbc = 0;
  while (std::getline(lines, line)) {
    if (line.rfind("# limb ", 0) == 0) continue;
    std::vector<double> v;
    std::istringstream fields(line);
    for (std::string f; std::getline(fields, f, '\t');) v.push_back(std::strtod(f.c_str(), nullptr));
    ASSERT_EQ(v.size(), columns.size());
    for (std::size_t i = 0; i < wanted.size(); ++i)
      ASSERT_TRUE(std::isfinite(v[at[i]])) << wanted[i] << " in row " << rows;
    mpc = std::max(mpc, v[at[14]]);
    wbc = std::max(wbc, v[at[15]]);
    ++rows;
  }
  EXPECT_EQ(rows, frames);
  EXPECT_GT(mpc, 0.0);
  EXPECT_GT(wbc, 0.0);
  r = cli({"plot", file, "-o", png});
  ASSERT_EQ(r.status, 0) << r.err << r.out;
  const std::string image = readFile(png);
  ASSERT_GT(image.size(), 1000u);
  EXPECT_EQ(image.substr(1, 3), "PNG");
  r = cli({"record", "stop"});
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("not recording"), std::string::npos);
  r = cli({"--json", "plot", (dir_ / "missing.tsv").string(), "-o", png});
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.parsed()["error"]["code"], "bad_recording") << r.out;
}

TEST_F(Verbs, ProfileListShowUse) {
  Outcome r = cli({"profile", "list"});
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* p : {"sim-flat", "sim-stage", "sim-rough", "hardware-example"})
    EXPECT_NE(r.out.find(p), std::string::npos) << p;
  r = cli({"profile", "show"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("rate: 1000"), std::string::npos);
  // A variant with other gains and limits switches in; the robot keeps standing.
  const std::string soft = writeFile(
      dir_ / "soft.yaml",
      "extends: " + std::string(SIM_PROFILE) +
          "\ncontrol:\n  joint_kp: {legs: 280, arms: 60}\nsafety:\n  max_pose_height: 0.9\n");
  r = cli({"profile", "use", soft});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("profile soft in force"), std::string::npos) << r.out;
  EXPECT_EQ(daemon_->status()["profile"], "soft");
  const double t0 = daemon_->status()["t"].get<double>();
  ASSERT_TRUE(daemon_->waitFor([&](const json& s) { return s["t"].get<double>() > t0 + 1.0; }));
  EXPECT_EQ(daemon_->status()["mode"], "stand");
  EXPECT_EQ(daemon_->status()["fallen"], false);
  r = cli({"pose", "--height", "0.92"});  // the new profile's limit is in force
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("0.900"), std::string::npos) << r.err;
  r = cli({"profile", "show", "sim-stage"});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("lab-stage.bt"), std::string::npos);
  // Terrain profiles switch at run time too: the planner's map follows (the simulated world is
  // the world: it stays).
  r = cli({"profile", "use", "sim-stage"});
  if (daemon_->status()["backend"] == "simbody") {
    ASSERT_EQ(r.status, 0) << r.err;
    const json s = daemon_->status();
    EXPECT_EQ(s["profile"], "sim-stage");
    EXPECT_NE(s["map"]["path"].get<std::string>().find("maps/lab-stage.bt"), std::string::npos);
  } else {
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("backend.name"), std::string::npos) << r.err;
  }
}

TEST_F(Verbs, SwitchesWhoseRepliesNobodyReadsLeakNoSettings) {
  // Profile switches from connections that close before the reply (those sent while another
  // is under way are refused as busy, unread): each accepted one's settings are kept for the
  // loop until it lets go of them, then freed; none stays behind (settings_held back to the one
  // in force), and no switch is left pending: the next one, through the CLI, goes through.
  Outcome r = cli({"lease", "acquire"});
  ASSERT_EQ(r.status, 0) << r.err;
  std::string lease = readFile((dir_ / "lease-a").string());
  lease = lease.substr(0, lease.find('\n'));
  std::vector<std::string> profiles;
  for (const char* name : {"soft", "stiff"})
    profiles.push_back(writeFile(dir_ / (std::string(name) + ".yaml"),
                                 "extends: " + std::string(SIM_PROFILE) +
                                     "\ncontrol:\n  joint_kp: {legs: " +
                                     (name[1] == 'o' ? "280" : "320") + ", arms: 80}\n"));
  EXPECT_EQ(daemon_->status()["settings_held"], 1);
  constexpr int kSwitches = 20;
  for (int i = 0; i < kSwitches; ++i) {
    RawClient c(daemon_->socket());
    ASSERT_TRUE(c.connected());
    const json request = {{"cmd", "profile_use"},
                          {"name", profiles[static_cast<std::size_t>(i % 2)]},
                          {"lease", lease}};
    ASSERT_TRUE(c.send(request.dump()));
  }  // each connection closes with its reply unread
  ASSERT_TRUE(daemon_->waitFor(
      [](const json& s) { return s["profile"] != "sim-flat" && s["settings_held"] == 1; }, 60))
      << daemon_->status().dump();
  const std::string other = daemon_->status()["profile"] == "soft" ? profiles[1] : profiles[0];
  r = cli({"profile", "use", other});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(daemon_->waitFor([](const json& s) { return s["settings_held"] == 1; }, 30))
      << daemon_->status().dump();
  EXPECT_EQ(daemon_->status()["mode"], "stand");
  EXPECT_EQ(daemon_->status()["fallen"], false);
}

TEST_F(Verbs, InvalidProfileSwitchKeepsTheRunningOne) {
  const std::string bad = writeFile(dir_ / "bad.yaml", "extends: " + std::string(SIM_PROFILE) +
                                                           "\ncontrol:\n  stand_up_duration: -1\n");
  Outcome r = cli({"--json", "profile", "use", bad});
  EXPECT_EQ(r.status, 1);
  const json e = r.parsed()["error"];
  EXPECT_EQ(e["code"], "invalid_profile");
  EXPECT_NE(e["message"].get<std::string>().find(
                bad + ":3:22: control.stand_up_duration: -1 is out of range"),
            std::string::npos)
      << e;
  EXPECT_EQ(daemon_->status()["profile"], fs::path(SIM_PROFILE).stem().string());
  // A profile that changes a restart key is refused as well, naming the key.
  const std::string rate = writeFile(
      dir_ / "rate.yaml", "extends: " + std::string(SIM_PROFILE) + "\ncontrol:\n  rate: 500\n");
  r = cli({"profile", "use", rate});
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("control.rate"), std::string::npos) << r.err;
  r = cli({"--json", "profile", "use", "no-such-profile"});
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.parsed()["error"]["code"], "not_found");
  EXPECT_EQ(daemon_->status()["profile"], fs::path(SIM_PROFILE).stem().string());
}

TEST_F(Verbs, MapLoadAndInfo) {
  Outcome r = cli({"map", "info"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("file map: none"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("live map: "), std::string::npos) << r.out;
  // sim-flat has no map file: its flat floor is known where the lidar has not looked.
  EXPECT_NE(r.out.find("(elsewhere the profile's flat floor)"), std::string::npos) << r.out;
  octomap::OcTree tree(0.05);
  for (double x = 0; x < 1; x += 0.05)
    for (double y = 0; y < 1; y += 0.05) tree.updateNode(octomap::point3d(x, y, 0.1), true);
  const std::string map = (dir_ / "stage.bt").string();
  ASSERT_TRUE(tree.writeBinaryConst(map));
  r = cli({"--json", "map", "load", map});
  ASSERT_EQ(r.status, 0) << r.err << r.out;
  EXPECT_DOUBLE_EQ(r.parsed()["map"]["resolution"].get<double>(), 0.05);
  // The planner's grid, the live map's: at least a column for each cell of the one-cell-thick
  // slab (the lidar's scans add the floor around it).
  EXPECT_GE(r.parsed()["live"]["heights"]["known"].get<std::size_t>(), tree.getNumLeafNodes());
  r = cli({"map", "info"});
  EXPECT_NE(r.out.find(map), std::string::npos);
  const std::string junk = writeFile(dir_ / "junk.bt", "not an octomap\n");
  r = cli({"--json", "map", "load", junk});
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.parsed()["error"]["message"].get<std::string>().find("the map in use stays"),
            std::string::npos);
  const std::string empty = (dir_ / "empty.bt").string();
  ASSERT_TRUE(octomap::OcTree(0.05).writeBinaryConst(empty));
  r = cli({"--json", "map", "load", empty});
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.parsed()["error"]["message"].get<std::string>().find(
                "map " + empty + ": the map has no occupied cells; the map in use stays"),
            std::string::npos)
      << r.out;
  r = cli({"--json", "map", "load", (dir_ / "none.bt").string()});
  EXPECT_EQ(r.parsed()["error"]["code"], "not_found");
  EXPECT_EQ(daemon_->status()["map"]["path"], map);

  // The live map was seeded with the file (the simulated lidar adds its scans to it as they
  // come): saved, it reads back with at least the slab's columns.
  r = cli({"--json", "map", "info"});
  EXPECT_EQ(r.parsed()["live"]["seeded_from"], map) << r.out;
  EXPECT_EQ(r.parsed()["live"]["heights"]["floor_known"], false) << r.out;  // the file's map
  EXPECT_GE(r.parsed()["live"]["heights"]["known"].get<std::size_t>(), tree.getNumLeafNodes());
  const std::string saved = (dir_ / "saved.bt").string();
  r = cli({"map", "save", saved});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("saved " + saved), std::string::npos) << r.out;
  r = cli({"map", "clear"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("file map: none"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("seeded from"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("flat floor"), std::string::npos) << r.out;  // cleared: nothing known
  r = cli({"--json", "map", "load", saved});
  ASSERT_EQ(r.status, 0) << r.err << r.out;
  EXPECT_GE(r.parsed()["live"]["heights"]["known"].get<std::size_t>(), tree.getNumLeafNodes());
  r = cli({"--json", "map", "save", "relative.bt"});  // the CLI makes it absolute
  EXPECT_EQ(r.status, 0) << r.out;
  fs::remove("relative.bt");
}

TEST_F(Verbs, AMapLoadLeavesTheServerAnswering) {
  // A map of 3.2 million columns: reading it and building its grid takes seconds, on a thread
  // of its own; meanwhile other clients are answered, and what would change the map is refused
  // as busy.
  const std::string big = (dir_ / "big.bt").string();
  const Outcome made = runProgram({MKMAP, "flat", "--extent", "-90", "90", "-90", "90",
                                   "--resolution", "0.1", "-o", big});
  ASSERT_EQ(made.status, 0) << made.err;
  Outcome r = cli({"lease", "acquire"});
  ASSERT_EQ(r.status, 0) << r.err;
  std::string lease = readFile((dir_ / "lease-a").string());
  lease = lease.substr(0, lease.find('\n'));
  RawClient loader(daemon_->socket()), other(daemon_->socket());
  ASSERT_TRUE(loader.send(json({{"id", 1}, {"cmd", "map_load"}, {"path", big}, {"lease", lease}}).dump()));
  const json info = other.ask(R"({"id": 2, "cmd": "map_info"})");
  EXPECT_EQ(info["loading"], big) << info.dump();
  EXPECT_TRUE(info["map"].is_null()) << info.dump();  // not in use before it is in
  const json status = other.ask(R"({"id": 3, "cmd": "status"})");
  EXPECT_EQ(status["status"]["mode"], "stand") << status.dump();
  const json again = other.ask(
      json({{"id", 4}, {"cmd", "map_load"}, {"path", big}, {"lease", lease}}).dump());
  EXPECT_EQ(again["error"]["code"], "busy") << again.dump();
  const json clear = other.ask(json({{"id", 5}, {"cmd", "map_clear"}, {"lease", lease}}).dump());
  EXPECT_EQ(clear["error"]["code"], "busy") << clear.dump();
  const json loaded = loader.next(120);
  ASSERT_EQ(loaded["ok"], true) << loaded.dump();
  EXPECT_EQ(loaded["id"], 1);
  EXPECT_EQ(loaded["map"]["path"], big);
  EXPECT_EQ(loaded["live"]["heights"]["known"], 1800u * 1800u) << loaded["live"].dump();
  EXPECT_FALSE(loaded.contains("loading"));
  EXPECT_EQ(daemon_->status()["map"]["path"], big);
  EXPECT_EQ(daemon_->status()["fallen"], false);
}

TEST_F(Verbs, LeaseAcquireTakeReturn) {
  // Client a holds the lease (acquired by its first motion command).
  ASSERT_EQ(cli({"stop"}, "a").status, 0);
  // Client b may read, not move the robot.
  EXPECT_EQ(cli({"status"}, "b").status, 0);
  Outcome r = cli({"--json", "pose", "--height", "0.85"}, "b");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.parsed()["error"]["code"], "lease_held");
  EXPECT_NE(r.parsed()["error"]["message"].get<std::string>().find("ballast lease take"),
            std::string::npos);
  r = cli({"lease", "acquire"}, "b");
  EXPECT_EQ(r.status, 1);
  // b takes it over; a is now refused.
  r = cli({"lease", "take"}, "b");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(cli({"pose", "--height", "0.85"}, "b").status, 0);
  EXPECT_EQ(cli({"stop"}, "a").status, 1);
  r = cli({"lease", "return"}, "a");
  EXPECT_EQ(r.status, 1);  // a does not hold it
  r = cli({"lease", "return"}, "b");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(daemon_->status()["lease"]["held"], false);
  // Free again: a's next motion command acquires it by itself.
  EXPECT_EQ(cli({"stop"}, "a").status, 0);
  EXPECT_EQ(daemon_->status()["lease"]["held"], true);
}

}  // namespace
}  // namespace ballast::test
