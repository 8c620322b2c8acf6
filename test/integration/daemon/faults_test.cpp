// Faults from the backend and the sensors damp the robot and stay until reset; falls are
// detected. The fake backend injects them at a given simulated time, so each run is exact.
#include "test/integration/daemon/daemon_harness.hpp"

namespace ballast::test {
namespace {

struct FaultCase {
  const char* name;
  const char* fake_key;  // fake backend option, set to 1.0 s
  const char* kind;      // status faults[0].kind
  const char* says;      // in its message
};

void PrintTo(const FaultCase& c, std::ostream* os) {
  *os << c.name;
}

class Faults : public ::testing::TestWithParam<FaultCase> {};

TEST_P(Faults, DampUntilReset) {
  const FaultCase& f = GetParam();
  const fs::path dir = scratchDir();
  const std::string profile =
      writeFile(dir / "p.yaml", "extends: " + std::string(STANDING_FAKE_PROFILE) +
                                    "\nbackend:\n  fake:\n    " + f.fake_key + ": 1.0\n");
  Daemon d(dir, profile);
  ASSERT_TRUE(d.running()) << d.log();
  ASSERT_TRUE(d.waitFor([](const json& s) { return !s["faults"].empty(); })) << d.log();
  const json s = d.status();
  EXPECT_EQ(s["mode"], "damp");
  EXPECT_EQ(s["faults"][0]["kind"], f.kind) << s["faults"];
  EXPECT_NEAR(s["faults"][0]["t"].get<double>(), 1.0, 0.0021);
  EXPECT_NE(s["faults"][0]["message"].get<std::string>().find(f.says), std::string::npos)
      << s["faults"];
  EXPECT_NE(d.log().find(std::string("fault ") + f.kind), std::string::npos);
  // Damped means damped: stand is refused until reset.
  Outcome r = d.cli({"stand"});
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("ballast reset"), std::string::npos);
  if (std::string(f.kind) != "backend_fault" && std::string(f.kind) != "fall") {
    EXPECT_EQ(d.cli({"reset"}).status, 0);
    EXPECT_EQ(d.status()["mode"], "passive");
    EXPECT_EQ(d.cli({"stand"}).status, 0);
    EXPECT_TRUE(d.waitForMode("stand"));
  }
  EXPECT_TRUE(d.status().is_object());
  EXPECT_EQ(d.stop(), 0) << d.log();
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(
    Backend, Faults,
    ::testing::Values(FaultCase{"fault", "fault_at", "backend_fault",
                                "the fake backend was told to fail"},
                      FaultCase{"stale", "stale_at", "backend_stale", "stale data"},
                      FaultCase{"nan", "nan_at", "nan", "is not a number"},
                      FaultCase{"tilt", "tilt_at", "fall", "base tilted"},
                      FaultCase{"low", "sink_at", "fall", "base height 0.300 m"},
                      FaultCase{"contact", "non_foot_contact_at", "fall", "other than the feet"}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(HeldAdvance, EndsWithTheFaultWhenTheBackendStopsTheClock) {
  // A held lockstep daemon whose backend fails at 1 s cannot run to 3 s: the controller time
  // stops where the backend failed, and `advance` says so instead of waiting for ever.
  const fs::path dir = scratchDir();
  const std::string profile =
      writeFile(dir / "p.yaml", "extends: " + std::string(STANDING_FAKE_PROFILE) +
                                    "\nbackend:\n  fake:\n    fault_at: 1.0\n");
  Daemon d(dir, profile, {"--hold"});
  ASSERT_TRUE(d.running()) << d.log();
  const auto began = std::chrono::steady_clock::now();
  const Outcome r = d.cli({"--json", "advance", "3"});
  const double waited =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
  EXPECT_EQ(r.status, 1) << r.out << r.err;
  EXPECT_EQ(r.parsed()["error"]["code"], "stalled") << r.out;
  const std::string message = r.parsed()["error"]["message"];
  const std::size_t at = message.find("stopped at t = ");
  ASSERT_NE(at, std::string::npos) << message;
  EXPECT_NEAR(std::stod(message.substr(at + 15)), 1.0, 0.0021) << message;
  EXPECT_NE(message.find("the fake backend was told to fail"), std::string::npos) << message;
  EXPECT_LT(waited, 8.0);  // the fault ends the wait, not the 10 s without a tick
  EXPECT_EQ(d.status()["mode"], "damp");
  EXPECT_EQ(d.stop(), 0) << d.log();
  fs::remove_all(dir);
}

TEST(Push, RefusedByABackendWithoutADisturbanceInput) {
  const fs::path dir = scratchDir();
  const std::string profile =
      writeFile(dir / "p.yaml", "extends: " + std::string(STANDING_FAKE_PROFILE) +
                                    "\nbackend:\n  fake:\n    disturbance: false\n");
  Daemon d(dir, profile);
  ASSERT_TRUE(d.running()) << d.log();
  const Outcome r = d.cli({"--json", "push", "--force", "10,0,0", "--duration", "0.1"});
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.parsed()["error"]["code"], "unavailable") << r.out;
  EXPECT_NE(r.parsed()["error"]["message"].get<std::string>().find("simulation only"),
            std::string::npos)
      << r.out;
  EXPECT_TRUE(d.status()["faults"].empty());
  EXPECT_EQ(d.stop(), 0) << d.log();
  fs::remove_all(dir);
}

TEST(FallDetection, OnlyWhileStanding) {
  // Passive robots are not "falling" into damp: the fall shows in status only.
  const fs::path dir = scratchDir();
  const std::string profile =
      writeFile(dir / "p.yaml", "extends: " + std::string(FAKE_PROFILE) +
                                    "\nbackend:\n  fake:\n    tilt_at: 0.5\n");
  Daemon d(dir, profile);
  ASSERT_TRUE(d.running()) << d.log();
  ASSERT_TRUE(d.waitFor([](const json& s) { return s["t"].get<double>() > 1.0; }));
  const json s = d.status();
  EXPECT_EQ(s["mode"], "passive");
  EXPECT_EQ(s["fallen"], true);
  EXPECT_TRUE(s["faults"].empty());
  const Outcome r = d.cli({"stand"});
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("has fallen"), std::string::npos) << r.err;
  EXPECT_EQ(d.stop(), 0);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ballast::test
