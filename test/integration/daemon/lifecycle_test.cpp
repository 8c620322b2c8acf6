// Starting and stopping ballastd: profile errors refuse the start with file:line:column,
// another daemon on the socket is refused, SIGTERM and SIGINT stop it cleanly (exit 0, no
// socket, telemetry flushed), SIGHUP reloads a valid profile and keeps the running one
// otherwise.
#include <set>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "test/integration/daemon/daemon_harness.hpp"

namespace ballast::test {
namespace {

TEST(Lifecycle, ProfileErrorNamesLineAndColumnAndRefusesToStart) {
  const fs::path dir = scratchDir();
  const std::string bad =
      writeFile(dir / "bad.yaml", "extends: " + std::string(FAKE_PROFILE) +
                                      "\ncontrol:\n  rate: fast\ngait:\n  perod: 1\n");
  Daemon d(dir, bad);
  EXPECT_FALSE(d.running());
  EXPECT_EQ(d.exitStatus(), 1);
  const std::string log = d.log();
  EXPECT_NE(log.find(bad + ":3:9: control.rate: expected a number, got 'fast'"), std::string::npos)
      << log;
  EXPECT_NE(log.find(bad + ":5:3: gait.perod: unknown key (did you mean gait.period?)"),
            std::string::npos)
      << log;
  EXPECT_FALSE(fs::exists(d.socket()));
  fs::remove_all(dir);
}

TEST(Lifecycle, BackendSectionErrorPointsIntoTheProfile) {
  const fs::path dir = scratchDir();
  const std::string bad =
      writeFile(dir / "bad.yaml", "extends: " + std::string(FAKE_PROFILE) +
                                      "\nbackend:\n  fake:\n    base_heigth: 1\n");
  Daemon d(dir, bad);
  EXPECT_FALSE(d.running());
  EXPECT_EQ(d.exitStatus(), 1);
  EXPECT_NE(d.log().find(bad + ":4:5: base_heigth: unknown key"), std::string::npos) << d.log();
  fs::remove_all(dir);
}

TEST(Lifecycle, MissingPluginAndBadUrdfAreNamed) {
  const fs::path dir = scratchDir();
  const std::string nop = writeFile(
      dir / "nop.yaml", "extends: " + std::string(FAKE_PROFILE) + "\nbackend:\n  name: nosuch\n");
  Daemon d(dir, nop);
  EXPECT_EQ(d.exitStatus(), 1);
  EXPECT_NE(
      d.log().find(nop + ":3:9: backend.name: backend 'nosuch': no libballast_backend_nosuch.so"),
      std::string::npos)
      << d.log();
  const std::string urdf = writeFile(
      dir / "u.yaml", "extends: " + std::string(FAKE_PROFILE) + "\nrobot:\n  urdf: missing.urdf\n");
  Daemon e(dir, urdf);
  EXPECT_EQ(e.exitStatus(), 1);
  EXPECT_NE(e.log().find(urdf + ":3:9: robot.urdf:"), std::string::npos) << e.log();
  fs::remove_all(dir);
}

#if HAVE_SIMBODY
/// sim-flat on the generated humanoid without frame links (profiles/vendor-frames.yaml places the
/// contact points and the IMUs), the simulation's lidar at lidarFrame.
std::string vendorProfile(const fs::path& dir, const std::string& lidarFrame) {
  return writeFile(dir / "vendor.yaml", "extends: " + std::string(BALLAST_SOURCE_DIR) +
                                            "/test/integration/daemon/profiles/vendor-frames.yaml"
                                            "\nrobot:\n  urdf: " + std::string(VENDOR_URDF) +
                                            "\nbackend:\n  simbody:\n    lidar:\n      frame: " +
                                            lidarFrame + "\n");
}

// --check validates what a start would, the backend's own section included (through the
// plugin's check, which starts nothing): a lidar link the URDF lacks is found before a start.
TEST(Check, ChecksTheBackendsSectionThroughItsPlugin) {
  const fs::path dir = scratchDir();
  const std::string good = vendorProfile(dir, "{link: head, offset: [0.08, 0, 0.10]}");
  const Outcome ok = runProgram({BALLASTD, "--check", "--profile", good});
  EXPECT_EQ(ok.status, 0) << ok.out << ok.err;
  EXPECT_NE(ok.out.find("backend simbody: its section checked by the plugin"), std::string::npos)
      << ok.out;
  const std::string bad = vendorProfile(dir, "lidar");
  const Outcome refused = runProgram({BALLASTD, "--check", "--profile", bad});
  EXPECT_EQ(refused.status, 1) << refused.out;
  EXPECT_NE(refused.err.find(bad + ":7:7: lidar.frame: "), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("has no link 'lidar'; closest: "), std::string::npos) << refused.err;
  fs::remove_all(dir);
}

// The starter profile --describe-robot prints for a robot with point feet (the 35 kg one, feet
// of a 2 mm sphere each) passes --check as it is saved. (It stands: StarterProfile in
// ballast-daemon-stack-tests.)
TEST(Check, TheStarterProfileOfARobotWithPointFeetPasses) {
  const fs::path dir = scratchDir();
  const Outcome described = runProgram({BALLASTD, "--describe-robot", POINT_FEET_URDF});
  ASSERT_EQ(described.status, 0) << described.err;
  EXPECT_NE(described.out.find("guess (the bottom of the box its inertia would be)"), std::string::npos)
      << described.out;
  const std::string profile = writeFile(dir / "starter.yaml", described.out);
  const Outcome checked = runProgram({BALLASTD, "--check", "--profile", profile});
  EXPECT_EQ(checked.status, 0) << checked.out << checked.err;
  EXPECT_NE(checked.out.find("backend simbody: its section checked by the plugin"), std::string::npos)
      << checked.out;
  fs::remove_all(dir);
}
#endif

// ballast-profile(5) is `ballastd --dump-schema=man`: the daemon's keys and the sections of the
// backend plugins built, each key from its plugin's own table; --dump-schema=yaml is a profile of
// every default with the plugins' sections commented out, which read back as those sections.
TEST(DumpSchema, TheManPageIsBallastdsOutputWithEveryBackendsSection) {
  const Outcome man = runProgram({BALLASTD, "--dump-schema=man"});
  ASSERT_EQ(man.status, 0) << man.err;
  for (const char* backend : {"simbody", "mujoco", "socketcan"})
    if (man.out.find(std::string(".SS backend.") + backend) == std::string::npos)
      GTEST_SKIP() << "the " << backend << " plugin is not built: the page has every backend";
  EXPECT_NE(man.out.find(".B backend.simbody.friction\n"), std::string::npos);
  EXPECT_NE(man.out.find(".SS backend.socketcan"), std::string::npos);
  EXPECT_EQ(man.out, readFile(fs::path(BALLAST_SOURCE_DIR) / "man/ballast-profile.5"))
      << "man/ballast-profile.5 differs from ballastd's: regenerate it with\n"
         "  build/bin/ballastd --dump-schema=man > man/ballast-profile.5";

  const Outcome yaml = runProgram({BALLASTD, "--dump-schema=yaml"});
  ASSERT_EQ(yaml.status, 0) << yaml.err;
  const std::size_t at = yaml.out.find("# backend:\n#   simbody:\n");
  ASSERT_NE(at, std::string::npos) << yaml.out;
  // Uncommented, the simbody block is a profile's backend section.
  std::string section;
  std::istringstream lines(yaml.out.substr(at));
  for (std::string line; std::getline(lines, line) && line.rfind("#", 0) == 0;)
    section += (line.size() > 2 ? line.substr(2) : "") + "\n";
  const YAML::Node node = YAML::Load(section);
  EXPECT_EQ(node["backend"]["simbody"]["friction"].as<double>(), 0.8) << section;
}

TEST(Lifecycle, DaemonAndCliMeetOnTheDefaultSocket) {
  // Neither is told where: both take $XDG_RUNTIME_DIR/ballast/ballastd.sock.
  const fs::path dir = scratchDir();
  const fs::path runtime = dir / "run";
  fs::create_directories(runtime);
  setenv("XDG_RUNTIME_DIR", runtime.c_str(), 1);
  unsetenv("BALLAST_SOCKET");
  unsetenv("BALLAST_LEASE_FILE");
  Daemon d(dir, FAKE_PROFILE, {}, true, /*defaultSocket=*/true);
  ASSERT_TRUE(d.running()) << d.log();
  EXPECT_EQ(d.socket(), (runtime / "ballast" / "ballastd.sock").string());
  EXPECT_TRUE(fs::exists(d.socket()));
  const Outcome r = runProgram({BALLAST, "status", "--get", "mode"});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "passive\n");
  EXPECT_EQ(d.stop(), 0) << d.log();
  EXPECT_FALSE(fs::exists(d.socket()));
  unsetenv("XDG_RUNTIME_DIR");
  fs::remove_all(dir);
}

TEST(Lifecycle, SecondDaemonOnTheSameSocketIsRefused) {
  const fs::path dir = scratchDir();
  Daemon first(dir, FAKE_PROFILE);
  ASSERT_TRUE(first.running()) << first.log();
  const fs::path other = dir / "second";
  fs::create_directories(other);
  Daemon second(other, FAKE_PROFILE, {"--socket", first.socket()});
  EXPECT_EQ(second.waitExit(10), 1);
  EXPECT_NE(second.log().find("another ballastd is already listening"), std::string::npos)
      << second.log();
  EXPECT_TRUE(first.status().is_object());  // the first one is unharmed
  EXPECT_EQ(first.stop(), 0);
  fs::remove_all(dir);
}

TEST(Lifecycle, SigtermAndSigintStopCleanly) {
  for (int sig : {SIGTERM, SIGINT}) {
    const fs::path dir = scratchDir();
    Daemon d(dir, FAKE_PROFILE);
    ASSERT_TRUE(d.running()) << d.log();
    const std::string file = (dir / "t.tsv").string();
    ASSERT_EQ(d.cli({"record", "start", file}).status, 0);
    ASSERT_EQ(d.cli({"stand"}).status, 0);
    ASSERT_TRUE(d.waitForMode("stand"));
    EXPECT_EQ(d.stop(sig), 0) << d.log();
    EXPECT_FALSE(fs::exists(d.socket())) << strsignal(sig);
    // Telemetry flushed: whole lines up to the end, stand-up (1) and stand (2) in the mode column.
    const std::string text = readFile(file);
    ASSERT_FALSE(text.empty());
    EXPECT_EQ(text.back(), '\n');
    std::set<std::string> modes;
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);) {
      if (line[0] == '#') continue;
      const auto a = line.find('\t');
      modes.insert(line.substr(a + 1, line.find('\t', a + 1) - a - 1));
    }
    EXPECT_TRUE(modes.count("1") && modes.count("2")) << testing::PrintToString(modes);
    EXPECT_NE(d.log().find("stopped at t="), std::string::npos);
    fs::remove_all(dir);
  }
}

TEST(Lifecycle, SighupReloadsAValidProfileAndKeepsTheOldOneOtherwise) {
  const fs::path dir = scratchDir();
  const std::string path = (dir / "p.yaml").string();
  const std::string base = "extends: " + std::string(FAKE_PROFILE) + "\n";
  writeFile(path, base + "safety:\n  max_pose_height: 0.93\n");
  Daemon d(dir, path);
  ASSERT_TRUE(d.running()) << d.log();
  ASSERT_EQ(d.cli({"stand"}).status, 0);
  ASSERT_TRUE(d.waitForMode("stand"));
  ASSERT_EQ(d.cli({"pose", "--height", "0.92"}).status, 0);
  // Lower the limit: after SIGHUP the same request is refused.
  writeFile(path, base + "safety:\n  max_pose_height: 0.9\n");
  d.signal(SIGHUP);
  ASSERT_TRUE(d.waitFor(
      [&](const json&) {
        return d.cli({"pose", "--height", "0.92"}).status == 1;
      },
      10))
      << d.log();
  // A broken file: refused with its line and column, the reloaded profile stays in force.
  writeFile(path, base + "safety:\n  max_pose_height: high\n");
  d.signal(SIGHUP);
  ASSERT_TRUE(d.waitFor(
      [&](const json&) {
        return d.log().find(path + ":3:20: safety.max_pose_height: expected a number") !=
               std::string::npos;
      },
      10))
      << d.log();
  EXPECT_EQ(d.cli({"pose", "--height", "0.92"}).status, 1);
  EXPECT_EQ(d.cli({"pose", "--height", "0.88"}).status, 0);
  EXPECT_EQ(d.stop(), 0);
  fs::remove_all(dir);
}

TEST(Lifecycle, RealTimeModeKeepsPace) {
  // Without --lockstep the fake backend paces the loop to the wall clock at 1 kHz.
  const fs::path dir = scratchDir();
  Daemon d(dir, FAKE_PROFILE, {}, /*lockstep=*/false);
  ASSERT_TRUE(d.running()) << d.log();
  const json a = d.status();
  const auto wall0 = std::chrono::steady_clock::now();
  ASSERT_TRUE(d.waitFor(
      [&](const json& s) { return s["t"].get<double>() > a["t"].get<double>() + 0.3; }, 10));
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  const json b = d.status();
  EXPECT_EQ(b["lockstep"], false);
  // Simulated time runs at the wall clock's pace (not hundreds of times faster as in lockstep).
  EXPECT_LT(b["t"].get<double>() - a["t"].get<double>(), 3.0 * wall + 0.2);
  EXPECT_EQ(d.stop(), 0);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ballast::test
