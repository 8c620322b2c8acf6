// Bad input on the socket and on the command line: each gets its error, and the connection,
// the daemon and the robot carry on (a status request on the same connection still answers,
// the loop never overran, the mode did not change). Also who may connect.
#include "test/integration/daemon/daemon_harness.hpp"

namespace ballast::test {
namespace {

class Protocol : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = scratchDir();
    daemon_ = std::make_unique<Daemon>(dir_, SIM_PROFILE);
    ASSERT_TRUE(daemon_->running()) << daemon_->log();
    ASSERT_TRUE(daemon_->waitForMode("stand")) << daemon_->log();
  }
  void TearDown() override {
    if (daemon_ && daemon_->running()) {
      EXPECT_EQ(daemon_->stop(), 0);
    }
    fs::remove_all(dir_);
  }
  fs::path dir_;
  std::unique_ptr<Daemon> daemon_;
};

TEST_F(Protocol, EveryBadRequestGetsItsErrorAndNothingElseChanges) {
  RawClient c(daemon_->socket());
  ASSERT_TRUE(c.connected());
  const json free = c.ask(R"({"id": 0, "cmd": "pose", "height": 0.8})");
  EXPECT_EQ(free["error"]["code"], "no_lease") << free;
  EXPECT_NE(
      free["error"]["message"].get<std::string>().find("motion commands need the command lease"),
      std::string::npos);
  const json lease = c.ask(R"({"id":1,"cmd":"lease_acquire"})");
  ASSERT_EQ(lease["ok"], true) << lease;
  const std::string token = lease["lease"];
  struct Case {
    std::string line, code, says;
  };
  const std::vector<Case> cases = {
      {"this is not json", "bad_json", "not JSON"},
      {"[1, 2, 3]", "bad_json", "a request is a JSON object"},
      {R"({"id": 2})", "missing_field", "needs \"cmd\""},
      {R"({"id": 3, "cmd": 42})", "bad_type", "cmd must be a string"},
      {R"({"id": 4, "cmd": "dance"})", "unknown_command", "unknown command 'dance'"},
      {R"({"id": 5, "cmd": "status", "verbose": true})", "unknown_field",
       "unknown field 'verbose'"},
      {R"({"id": 6, "cmd": "walk", "vx": "fast"})", "bad_type", "vx must be a number"},
      {R"({"id": 7, "cmd": "walk", "vx": 99})", "out_of_range", "vx 99 is out of range"},
      {R"({"id": 8, "cmd": "push", "force": [1, 2]})", "bad_type",
       "force must be a list of 3 numbers"},
      {R"({"id": 9, "cmd": "push", "force": [1, 2, 3]})", "missing_field", "push needs duration"},
      {R"({"id": 10, "cmd": "pose", "height": 0.8})", "lease_held", "held by uid"},
      {R"({"id": 11, "cmd": "pose", "height": 0.8, "lease": "forged"})", "lease_held",
       "held by uid"},
      {R"({"id": 12, "cmd": "pose", "height": 2.5, "lease": ")" + token + R"("})", "out_of_range",
       "safety.min_pose_height"},
      {R"({"id": 13, "cmd": "watch", "rate": 5000})", "out_of_range", "rate 5000 is out of range"},
      {R"({"id": 14, "cmd": "record_start", "path": "relative.tsv"})", "out_of_range",
       "must be absolute"},
      {R"({"id": "x", "cmd": "profile_use", "name": "nope", "lease": ")" + token + R"("})",
       "not_found", "no nope.yaml"},
      {R"({"id": [1], "cmd": "status"})", "bad_type", "id must be a number or a string"},
      {"{\"id\": 15, \"cmd\": \"st\xff\xfe"
       "atus\"}",
       "bad_json", "not JSON"},
  };
  for (const Case& k : cases) {
    SCOPED_TRACE(k.line);
    const json r = c.ask(k.line);
    ASSERT_TRUE(r.is_object()) << "no reply";
    EXPECT_EQ(r["ok"], false);
    EXPECT_EQ(r["error"]["code"], k.code);
    EXPECT_NE(r["error"]["message"].get<std::string>().find(k.says), std::string::npos) << r;
  }
  // A profile whose bytes are not UTF-8: refused, and the reply is still valid JSON.
  const std::string junk = writeFile(dir_ / "junk.yaml", "extends: " + std::string(SIM_PROFILE) +
                                                             "\ngait:\n  per\xff\xfeiod: 1\n");
  const json j = c.ask(R"({"id": 16, "cmd": "profile_use", "lease": ")" + token +
                       R"(", "name": ")" + junk + "\"}");
  EXPECT_EQ(j["error"]["code"], "invalid_profile") << j;
  // Ids are echoed, numbers or strings.
  EXPECT_EQ(c.ask(R"({"id": 99, "cmd": "version"})")["id"], 99);
  EXPECT_EQ(c.ask(R"({"id": "abc", "cmd": "version"})")["id"], "abc");
  // An overlong line: one error, then the connection goes on.
  const json big = c.ask(R"({"cmd":"status","pad":")" + std::string(100000, 'x') + "\"}");
  EXPECT_EQ(big["error"]["code"], "too_large") << big;
  const json after = c.ask(R"({"id": 100, "cmd": "status"})");
  ASSERT_EQ(after["ok"], true) << after;
  EXPECT_EQ(after["id"], 100);
  EXPECT_EQ(after["status"]["mode"], "stand");
  EXPECT_EQ(after["status"]["fallen"], false);
  EXPECT_TRUE(after["status"]["faults"].empty());
}

TEST_F(Protocol, WatchStreamsUntilUnwatch) {
  RawClient c(daemon_->socket());
  const json ok = c.ask(R"({"id":1,"cmd":"watch","rate":100})");
  ASSERT_EQ(ok["ok"], true) << ok;
  double last = -1;
  for (int i = 0; i < 5; ++i) {
    const json e = c.next();
    ASSERT_EQ(e["event"], "status") << e;
    EXPECT_GE(e["status"]["t"].get<double>(), last);
    last = e["status"]["t"].get<double>();
  }
  // Requests still get answered in between the stream's lines.
  json r;
  do r = c.ask(R"({"id":2,"cmd":"unwatch"})");
  while (r.contains("event"));
  EXPECT_EQ(r["ok"], true);
}

TEST_F(Protocol, CommandLineMistakesAreUsageErrors) {
  for (const std::vector<std::string>& args :
       std::vector<std::vector<std::string>>{{"dance"},
                                             {"walk", "--vx", "fast"},
                                             {"walk", "--for", "soon"},
                                             {"pose", "--pitch", "5degrees"},
                                             {"push", "--force", "1,2", "--duration", "1"},
                                             {"push", "--duration", "1"},
                                             {"profile"},
                                             {"status", "--rate", "0"}}) {
    const Outcome r = daemon_->cli(args);
    EXPECT_EQ(r.status, 2) << testing::PrintToString(args) << r.err;
    EXPECT_FALSE(r.err.empty());
  }
  // No daemon: exit 3, saying how to start one.
  const Outcome r = runProgram({BALLAST, "--socket", (dir_ / "nobody.sock").string(), "status"});
  EXPECT_EQ(r.status, 3);
  EXPECT_NE(r.err.find("start one"), std::string::npos) << r.err;
  const Outcome j =
      runProgram({BALLAST, "--json", "--socket", (dir_ / "nobody.sock").string(), "stand"});
  EXPECT_EQ(j.status, 3);
  EXPECT_EQ(j.parsed()["error"]["code"], "no_daemon");
}

/// A scratch directory every uid can reach (/tmp may be private), or "" if there is none.
fs::path sharedScratchDir() {
  for (const char* base : {"/dev/shm", "/var/tmp", "/tmp"}) {
    struct stat st;
    if (stat(base, &st) != 0 || !(st.st_mode & S_IXOTH)) continue;
    const fs::path d =
        fs::path(base) / ("ballast-it-" + std::to_string(getpid()) + "-" + testName());
    fs::create_directories(d);
    chmod(d.c_str(), 0755);
    return d;
  }
  return {};
}

TEST_F(Protocol, SocketIsGroupOnlyAndOtherUidsAreRefused) {
  struct stat st;
  ASSERT_EQ(stat(daemon_->socket().c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0660u);
  if (getuid() != 0) GTEST_SKIP() << "checking another uid needs root";
  const fs::path shared = sharedScratchDir();
  if (shared.empty()) GTEST_SKIP() << "no directory other uids can reach";
  daemon_->stop();
  daemon_ = std::make_unique<Daemon>(shared, SIM_PROFILE);
  ASSERT_TRUE(daemon_->running()) << daemon_->log();
  // Open the file to everyone so that the daemon's own uid check is what refuses.
  chmod(daemon_->socket().c_str(), 0666);
  const pid_t child = fork();
  if (child == 0) {
    if (setuid(65534) != 0) _exit(10);
    RawClient c(daemon_->socket());
    if (!c.connected()) _exit(11);
    const json r = c.next(5);
    _exit(r.is_object() && r["error"]["code"] == "permission_denied" ? 0 : 12);
  }
  int status = 0;
  waitpid(child, &status, 0);
  EXPECT_EQ(WEXITSTATUS(status), 0);
  EXPECT_NE(daemon_->log().find("refused a connection from uid 65534"), std::string::npos);
  EXPECT_EQ(daemon_->stop(), 0);
  fs::remove_all(shared);
}

TEST(ProtocolAllowedUids, ListedUidIsServed) {
  if (getuid() != 0) GTEST_SKIP() << "connecting as another uid needs root";
  const fs::path dir = sharedScratchDir();
  if (dir.empty()) GTEST_SKIP() << "no directory other uids can reach";
  const std::string profile = writeFile(dir / "p.yaml", "extends: " + std::string(SIM_PROFILE) +
                                                            "\nserver:\n  allowed_uids: [65534]\n");
  Daemon d(dir, profile);
  ASSERT_TRUE(d.running()) << d.log();
  chmod(d.socket().c_str(), 0666);
  const pid_t child = fork();
  if (child == 0) {
    if (setuid(65534) != 0) _exit(10);
    RawClient c(d.socket());
    const json r = c.ask(R"({"cmd":"status"})", 5);
    _exit(r.is_object() && r["ok"] == true ? 0 : 12);
  }
  int status = 0;
  waitpid(child, &status, 0);
  EXPECT_EQ(WEXITSTATUS(status), 0);
  EXPECT_EQ(d.stop(), 0);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ballast::test
