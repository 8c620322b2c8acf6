// The control loop in-process on the fake backend: commands in, replies and status out, a
// planner in its slot, a profile switch; and the 1 kHz path allocates nothing: a counting
// malloc watches every tick while the loop stands up, changes pose, takes a push, refuses a
// walk, switches settings, records telemetry, faults on a NaN, is estopped and reset.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <list>
#include <thread>

#include "control/control_loop.hpp"
#include "control/mpc_planner.hpp"
#include "control/terrain_mapper.hpp"
#include "profile/settings.hpp"
#include "test/unit/allocation_counter.hpp"
#include "test/unit/control/attached_planner.hpp"
#include "test/unit/settings_support.hpp"
#include "test/unit/test_support.hpp"

extern "C" const ballast::backend::BackendEntry* ballast_backend_entry();


namespace ballast::control {
namespace {

/// The default profile, starting passive and standing up in half a second.
ControlSettings passiveSimFlat() {
  ControlSettings s = test::simFlat().control;
  s.initial_mode = Mode::kPassive;
  s.stand_up_duration = 0.5;
  return s;
}

class LoopOnFake : public ::testing::Test {
 protected:
  void SetUp() override {
    settings_ = passiveSimFlat();
    backend_ = ballast_backend_entry()->create();
    backend::Config config;
    config.section_yaml = section_;
    config.section_origin = "test:1";
    const std::string urdf = test::humanoidUrdf();
    config.urdf_path = urdf.c_str();
    config.period = 0.001;
    config.lockstep = true;
    backend::Error error;
    ASSERT_TRUE(backend_->configure(config, error)) << error.message;
    ASSERT_TRUE(backend_->start(error));
    LoopOptions options;
    options.lockstep = true;
    loop_ = std::make_unique<ControlLoop>(test::humanoid(), *backend_, hand(settings_), options);
  }
  void TearDown() override {
    loop_.reset();
    ballast_backend_entry()->destroy(backend_);
  }
  /// Submits a command and ticks until its reply.
  CommandReply command(OperatorCommand c) {
    c.sequence = ++sequence_;
    EXPECT_TRUE(loop_->submit(c));
    CommandReply r;
    for (int i = 0; i < 10 && !loop_->popReply(r); ++i) loop_->tick();
    EXPECT_EQ(r.sequence, c.sequence);
    return r;
  }
  void ticks(int n) {
    for (int i = 0; i < n; ++i) loop_->tick();
  }
  /// Stands the robot up and ticks until the loop is in stand (false if it never gets there).
  bool standUp() {
    OperatorCommand c;
    c.kind = CommandKind::kStand;
    command(c);
    for (int i = 0; i < 2000 && loop_->status().mode != Mode::kStand; ++i) loop_->tick();
    return loop_->status().mode == Mode::kStand;
  }
  /// The settings as the IO side hands them to the loop: it keeps them (the loop shares them and
  /// frees none); the handle a switch command carries is &held_.back().
  SettingsPtr hand(const ControlSettings& s) {
    held_.push_back(std::make_shared<const ControlSettings>(s));
    return held_.back();
  }
  const char* section_ = "{}";
  ControlSettings settings_;
  std::list<SettingsPtr> held_;
  backend::Backend* backend_ = nullptr;
  std::unique_ptr<ControlLoop> loop_;
  std::uint64_t sequence_ = 0;
};

TEST_F(LoopOnFake, StandsUpAndAnswersCommands) {
  ticks(5);
  EXPECT_EQ(loop_->status().mode, Mode::kPassive);
  OperatorCommand c;
  c.kind = CommandKind::kStand;
  CommandReply r = command(c);
  EXPECT_EQ(r.refusal, Refusal::kNone);
  EXPECT_EQ(r.mode, Mode::kStandUp);
  ticks(3000);  // the fake's lightly damped arms settle in about 3 s
  LoopStatus s = loop_->status();
  EXPECT_EQ(s.mode, Mode::kStand);
  // The fake's joints follow their PD commands: the robot now stands in the nominal posture.
  for (int j = 0; j < s.num_joints; ++j) EXPECT_NEAR(s.q[j], settings_.nominal_q[j], 0.03) << j;
  EXPECT_NEAR(s.base.position[2], loop_->nominalHeight(), 0.01);
  c.kind = CommandKind::kWalk;
  r = command(c);
  EXPECT_EQ(r.refusal, Refusal::kUnavailable);
  LoopEvent e;
  int events = 0;
  while (loop_->popEvent(e)) ++events;
  EXPECT_GE(events, 2);  // passive -> stand-up -> stand
}

TEST_F(LoopOnFake, SettingsSwitchBlendsGainsAndTheIoSideFreesTheOldOnes) {
  OperatorCommand c;
  c.kind = CommandKind::kStand;
  command(c);
  ticks(600);
  ControlSettings next = settings_;
  for (double& kp : next.kp) kp *= 0.5;
  next.gain_blend_time = 0.2;
  c.kind = CommandKind::kSwitchSettings;
  hand(next);
  c.settings = &held_.back();
  const CommandReply r = command(c);
  EXPECT_EQ(r.refusal, Refusal::kNone);
  EXPECT_EQ(held_.front().use_count(), 1);  // the loop let go of the old ones: the IO side frees them
  EXPECT_EQ(held_.back().use_count(), 2);
  EXPECT_EQ(loop_->status().settings_generation, 1u);
  ticks(300);
  EXPECT_EQ(loop_->status().mode, Mode::kStand);
}

// The IO side keeps every settings it hands the loop (SettingsKeeper) and frees them once the loop
// has let go; the loop itself never frees memory. A switch whose reply the loop cannot send (the
// IO side reads no replies: the ring is full) leaks nothing and does not block the next one.
TEST_F(LoopOnFake, ASwitchUnderAFullReplyRingLeaksNothing) {
  loop_.reset();
  SettingsKeeper keeper;
  std::weak_ptr<const ControlSettings> first, second, third;
  LoopOptions options;
  options.lockstep = true;
  options.command_capacity = 8;
  {
    SettingsPtr initial = std::make_shared<const ControlSettings>(settings_);
    first = initial;
    keeper.keep(initial, 0);
    loop_ = std::make_unique<ControlLoop>(test::humanoid(), *backend_, std::move(initial), options);
  }
  ticks(3);
  // Replies nobody reads, until the ring is full and drops them.
  OperatorCommand stop;
  stop.kind = CommandKind::kStop;
  for (int i = 0; i < 16; ++i) {
    stop.sequence = ++sequence_;
    ASSERT_TRUE(loop_->submit(stop));
    ticks(1);
  }
  auto switchTo = [&](double blend, std::weak_ptr<const ControlSettings>& watch) {
    ControlSettings next = settings_;
    next.gain_blend_time = blend;
    OperatorCommand c;
    c.kind = CommandKind::kSwitchSettings;
    c.sequence = ++sequence_;
    SettingsPtr p = std::make_shared<const ControlSettings>(next);
    watch = p;
    c.settings = keeper.keep(std::move(p), c.sequence);
    EXPECT_TRUE(loop_->submit(c));
    long frees = 0;
    EXPECT_EQ(test::allocationsIn([&] { frees = test::freesIn([&] { ticks(5); }); }), 0);
    EXPECT_EQ(frees, 0) << "the loop freed memory";
    EXPECT_EQ(loop_->status().last_command, c.sequence);
  };
  switchTo(0.1, second);
  EXPECT_EQ(loop_->status().settings_generation, 1u);
  EXPECT_EQ(keeper.collect(loop_->status().last_command), 1u);  // the first settings
  EXPECT_TRUE(first.expired());
  EXPECT_FALSE(second.expired());
  switchTo(0.2, third);  // the lost reply blocks nothing
  EXPECT_EQ(loop_->status().settings_generation, 2u);
  EXPECT_EQ(keeper.collect(loop_->status().last_command), 1u);
  EXPECT_TRUE(second.expired());
  CommandReply r;
  int replies = 0;
  while (loop_->popReply(r)) ++replies;
  EXPECT_EQ(replies, 8);  // the ring's capacity: the rest, the switches' among them, were dropped
  loop_.reset();
  EXPECT_EQ(keeper.collect(sequence_), 1u);
  EXPECT_TRUE(third.expired());
  EXPECT_EQ(keeper.held(), 0u);
}

class CountingPlanner : public Planner {
 public:
  void plan(const PlannerInput& in, PlannerOutput& out) override {
    out.t = in.t;
    out.valid = true;
    ++calls;
  }
  std::atomic<int> calls{0};
};

TEST_F(LoopOnFake, PlannerSlotRunsAtItsRateInControllerTimeWhileStanding) {
  CountingPlanner planner;
  const AttachedPlanner attached(*loop_, planner);
  ticks(300);
  EXPECT_TRUE(loop_->status().planner_available);
  EXPECT_EQ(planner.calls.load(), 0);  // passive: nothing to plan
  ASSERT_TRUE(standUp());
  EXPECT_LE(planner.calls.load(), 1);  // none during stand-up
  const int before = planner.calls.load();
  ticks(1000);  // 1 s of controller time at planner.rate 100 Hz, synchronous in lockstep
  EXPECT_NEAR(planner.calls.load() - before, 100, 1);
}

/// The real planner, with its answers to the inputs of a window of controller time invalidated
/// (a solver failure as the loop sees it). The window is on the input's time, not a flag the test
/// flips between ticks: the planner thread solves while the loop ticks on (lockstep waits only
/// when a plan is due), so with a flag read after the solve the count of failed answers was 4, 5
/// or 6 by which side of the flip each solve ended (2 runs in 15 on a loaded machine, main too).
class FailingPlanner : public Planner {
 public:
  explicit FailingPlanner(Planner& inner) : inner_(inner) {}
  void plan(const PlannerInput& in, PlannerOutput& out) override {
    inner_.plan(in, out);
    if (in.t >= failFrom.load() && in.t < failUntil.load()) {
      out.valid = false;
      copyText(out.message, "injected: no step reduced cost or constraint violation");
    }
  }
  /// Inputs with failFrom <= t < failUntil fail; none at first.
  std::atomic<double> failFrom{kInf}, failUntil{kInf};

 private:
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  Planner& inner_;
};

TEST_F(LoopOnFake, APlannerFailureKeepsTheLastPlanUntilItIsTooOld) {
  MpcPlanner mpc(test::humanoid(), settings_, std::make_shared<const terrain::HeightMap>());
  FailingPlanner planner(mpc);
  const AttachedPlanner attached(*loop_, planner);
  ASSERT_TRUE(standUp());
  ticks(100);
  LoopEvent e;
  while (loop_->popEvent(e)) {
  }
  // Fifteen failed answers (150 ms at 100 Hz, within safety.max_plan_age 0.2 s): still standing
  // on the last plan, the failures counted, one warning for the streak and one when the plan in
  // force passed half the limit.
  ASSERT_NEAR(settings_.max_plan_age, 0.2, 1e-12);
  // From half a tick on (no input's time on the window's edges): the inputs of 150 ticks.
  const double from = loop_->status().t + 0.0005;
  planner.failUntil = from + 0.15;  // first: the window is empty until failFrom comes down
  planner.failFrom = from;
  ticks(250);
  LoopStatus s = loop_->status();
  EXPECT_EQ(s.mode, Mode::kStand);
  EXPECT_EQ(s.faults.size, 0);
  EXPECT_EQ(s.planner_failures, 15u);
  int failed = 0, old = 0;
  while (loop_->popEvent(e)) {
    if (e.warning && std::strstr(e.message, "keeping the last one")) ++failed;
    if (e.warning && std::strstr(e.message, "the plan in force is 0.1")) {
      ++old;
      EXPECT_NE(std::strstr(e.message, "(safety.max_plan_age 0.200 s): injected"), nullptr)
          << e.message;
    }
  }
  EXPECT_EQ(failed, 1);
  EXPECT_EQ(old, 1);
  // A planner that keeps failing: the plan grows older than 0.2 s, a planner fault damps.
  planner.failFrom = loop_->status().t + 0.0005;  // the last window is past: still none
  planner.failUntil = std::numeric_limits<double>::infinity();
  ticks(300);
  s = loop_->status();
  EXPECT_EQ(s.mode, Mode::kDamp);
  ASSERT_EQ(s.faults.size, 1);
  EXPECT_EQ(s.faults.fault[0].kind, FaultKind::kPlanner);
  EXPECT_NE(std::strstr(s.faults.fault[0].message, "safety.max_plan_age"), nullptr)
      << s.faults.fault[0].message;
  EXPECT_NE(std::strstr(s.faults.fault[0].message, "injected"), nullptr);
  EXPECT_NEAR(s.faults.fault[0].t, s.t - 0.1, 0.012);  // 0.2 s after the last valid plan
}

TEST(MpcPlannerInput, ANotANumberStateGivesNoPlan) {
  ControlSettings settings = passiveSimFlat();
  MpcPlanner planner(test::humanoid(), settings, std::make_shared<const terrain::HeightMap>());
  PlannerInput in;
  in.mode = Mode::kStand;
  in.restart = true;
  in.state.num_joints = test::humanoid().nj();
  for (int j = 0; j < in.state.num_joints; ++j) in.state.q[j] = settings.nominal_q[j];
  in.state.base.position[2] = 0.89;
  in.command.height = 0.89;
  PlannerOutput out;
  planner.plan(in, out);
  ASSERT_TRUE(out.valid) << out.message;
  in.restart = false;
  in.t = 0.01;
  in.state.base.linear_velocity[0] = std::nan("");
  planner.plan(in, out);
  EXPECT_FALSE(out.valid);
  EXPECT_NE(std::strstr(out.message, "NaN"), nullptr) << out.message;
}

// A profile switch hands the planner the settings the loop switches to, shared and not copied;
// it takes their numbers at its next plan made standing and lets go of them, and a request it
// has not taken yet is replaced by a later one (the IO side then frees the first).
TEST(MpcPlannerInput, NewSettingsAreSharedAndLetGoOnceTaken) {
  const ControlSettings settings = passiveSimFlat();
  MpcPlanner planner(test::humanoid(), settings, std::make_shared<const terrain::HeightMap>());
  PlannerInput in;
  in.mode = Mode::kStand;
  in.restart = true;
  in.state.num_joints = test::humanoid().nj();
  for (int j = 0; j < in.state.num_joints; ++j) in.state.q[j] = settings.nominal_q[j];
  in.state.base.position[2] = 0.89;
  in.command.height = 0.89;
  PlannerOutput out;
  planner.plan(in, out);
  ASSERT_TRUE(out.valid) << out.message;

  SettingsPtr first = std::make_shared<const ControlSettings>(settings);
  SettingsPtr second = std::make_shared<const ControlSettings>(settings);
  planner.requestSettings(first);
  EXPECT_EQ(first.use_count(), 2);
  planner.requestSettings(second);
  EXPECT_EQ(first.use_count(), 1);  // replaced before it was taken
  EXPECT_EQ(second.use_count(), 2);
  in.restart = false;
  in.t = 0.01;
  planner.plan(in, out);
  EXPECT_TRUE(out.valid) << out.message;
  EXPECT_EQ(second.use_count(), 1);  // taken: the planner keeps numbers, not the settings
}

class NoAllocation : public LoopOnFake {
 protected:
  void SetUp() override {
    section_ = "nan_at: 2.5";
    LoopOnFake::SetUp();
  }
};

TEST_F(NoAllocation, StandAndWalkUnderTheWholeBodyControllerAllocateNothing) {
  // The real planner on its thread (which may allocate); the loop samples its plans and runs
  // the whole-body controller on them.
  MpcPlanner planner(test::humanoid(), settings_, std::make_shared<const terrain::HeightMap>());
  const AttachedPlanner attached(*loop_, planner);
  ASSERT_TRUE(standUp());
  ticks(20);  // the first plans: the walking controller takes over from the standing one
  OperatorCommand c;
  c.kind = CommandKind::kWalk;
  c.vx = 0.3;
  c.sequence = ++sequence_;
  ASSERT_TRUE(loop_->submit(c));
  EXPECT_EQ(test::allocationsIn([&] { ticks(300); }), 0);
  EXPECT_EQ(loop_->status().mode, Mode::kWalk);
  EXPECT_GT(loop_->status().mpc_ms, 0.0);  // plans arrived and were used
}

class NoAllocationWithLidar : public LoopOnFake {
 protected:
  void SetUp() override {
    section_ = "lidar: true";
    LoopOnFake::SetUp();
  }
};

TEST_F(NoAllocationWithLidar, HandingScansToTheMappingThreadAllocatesNothing) {
  // The fake's lidar gives a scan every 0.1 s; the loop copies each into the mapper's slot with
  // the estimated pose, and in lockstep waits for its map at mapping.latency. The mapping thread
  // and the planner's allocate; the loop's ticks do not.
  MpcPlanner planner(test::humanoid(), settings_, std::make_shared<const terrain::HeightMap>());
  MappingSettings mapping;
  mapping.map.resolution = 0.05;
  TerrainMapper mapper(test::humanoid(), mapping, &planner);
  loop_->attachMapper(&mapper);
  mapper.start();
  {
    const AttachedPlanner attached(*loop_, planner);
    ASSERT_TRUE(standUp());
    ticks(20);
    OperatorCommand c;
    c.kind = CommandKind::kWalk;
    c.vx = 0.3;
    c.sequence = ++sequence_;
    ASSERT_TRUE(loop_->submit(c));
    ticks(5);
    const std::uint64_t before = mapper.done();
    EXPECT_EQ(test::allocationsIn([&] { ticks(500); }), 0);
    EXPECT_GE(mapper.done(), before + 4);  // every scan inserted (lockstep skips none)
    EXPECT_EQ(loop_->status().mode, Mode::kWalk);
  }
  mapper.stop();
  const nlohmann::json info = mapper.info();
  EXPECT_EQ(info["scans"]["skipped"], 0);
  EXPECT_GT(info["heights"]["known"].get<int>(), 1000);
}

TEST_F(NoAllocation, CounterSeesAnAllocation) {
  void* p = nullptr;
  EXPECT_GT(test::allocationsIn([&] { p = std::malloc(16); }), 0);
  std::free(p);
}

TEST_F(NoAllocation, TheLoopAllocatesNothingPerTick) {
  const std::string file = std::filesystem::temp_directory_path() /
                           ("ballast-noalloc-" + std::to_string(getpid()) + ".tsv");
  TelemetryWriter writer(loop_->telemetryRing(), loop_->jointNames());
  loop_->setTelemetryWriter(&writer);
  writer.start();
  std::string error;
  ASSERT_TRUE(writer.startRecording(file, error)) << error;
  ControlSettings other = settings_;
  other.gain_blend_time = 0.3;
  hand(other);
  const SettingsPtr* otherHandle = &held_.back();
  ticks(3);  // first ticks: lazy one-time work is not the steady state

  long counted = 0;
  auto run = [&](OperatorCommand c, int n) {
    c.sequence = ++sequence_;
    ASSERT_TRUE(loop_->submit(c));
    const long allocations = test::allocationsIn([&] { ticks(n); });
    counted += allocations;
    EXPECT_EQ(allocations, 0) << "command kind " << static_cast<int>(c.kind);
    CommandReply r;
    while (loop_->popReply(r)) {
    }
    LoopEvent e;
    while (loop_->popEvent(e)) {
    }
  };
  OperatorCommand c;
  c.kind = CommandKind::kStand;
  run(c, 700);  // stand-up, then stand
  c = {};
  c.kind = CommandKind::kPose;
  c.height = 0.84;
  c.pitch = 0.05;
  run(c, 500);
  c = {};
  c.kind = CommandKind::kPush;
  c.push.force[0] = 20;
  c.push.duration = 0.1;
  run(c, 100);
  c = {};
  c.kind = CommandKind::kPose;  // refused: numbers formatted into the reply
  c.height = 2.0;
  run(c, 10);
  c = {};
  c.kind = CommandKind::kWalk;  // refused: a message formatted into the reply
  c.vx = 5.0;
  run(c, 100);
  c = {};
  c.kind = CommandKind::kSwitchSettings;
  c.settings = otherHandle;
  run(c, 500);
  c = {};
  c.kind = CommandKind::kStop;
  run(c, 700);  // the NaN at t = 2.5 s faults the loop into damp in here
  EXPECT_EQ(loop_->status().mode, Mode::kDamp);
  EXPECT_EQ(loop_->status().faults.fault[0].kind, FaultKind::kNotANumber);
  c = {};
  c.kind = CommandKind::kReset;
  run(c, 50);
  c = {};
  c.kind = CommandKind::kEstop;
  run(c, 50);
  EXPECT_EQ(counted, 0);
  EXPECT_GT(loop_->status().telemetry_frames, 2500u);
  std::uint64_t frames;
  std::string path;
  writer.stopRecording(frames, path);
  writer.stop();
  EXPECT_EQ(frames, loop_->status().telemetry_frames);
  std::filesystem::remove(file);
}

TEST_F(NoAllocation, TheLoopAllocatesNothingPerTickRecordingABinaryLog) {
  const std::string file = std::filesystem::temp_directory_path() /
                           ("ballast-noalloc-" + std::to_string(getpid()) + ".blog");
  TelemetryWriter writer(loop_->telemetryRing(), loop_->jointNames());
  loop_->setTelemetryWriter(&writer);
  writer.start();
  std::string error;
  ASSERT_TRUE(writer.startRecording(file, error)) << error;
  ticks(3);
  OperatorCommand c;
  c.kind = CommandKind::kStand;
  c.sequence = ++sequence_;
  ASSERT_TRUE(loop_->submit(c));
  EXPECT_EQ(test::allocationsIn([&] { ticks(2400); }), 0);  // blocks of 1000 frames written
  std::uint64_t frames;
  std::string path;
  ASSERT_TRUE(writer.stopRecording(frames, path));
  writer.stop();
  EXPECT_EQ(frames, loop_->status().telemetry_frames);
  blog::Summary s;
  ASSERT_TRUE(blog::summarize(file, s, error)) << error;
  EXPECT_EQ(s.frames, frames);
  std::filesystem::remove(file);
}

// ---- the binary log against the text one

/// Splits a TSV recording into its lines.
std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::size_t start = 0;
  for (std::size_t end; (end = text.find('\n', start)) != std::string::npos; start = end + 1)
    out.push_back(text.substr(start, end - start));
  return out;
}
std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out;
  std::size_t start = 0;
  for (std::size_t end;; start = end + 1) {
    end = line.find('\t', start);
    out.push_back(line.substr(start, end - start));
    if (end == std::string::npos) break;
  }
  return out;
}
std::string slurp(const std::string& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), {}};
}
std::string blogAsTsv(const std::string& path) {
  const std::string out = path + ".tsv";
  std::FILE* f = std::fopen(out.c_str(), "w");
  std::string error, truncation;
  EXPECT_EQ(blog::convert(path, f, {}, error, &truncation), blog::Converted::kOk) << error;
  std::fclose(f);
  EXPECT_TRUE(truncation.empty()) << truncation;
  std::string text = slurp(out);
  std::filesystem::remove(out);
  return text;
}

/// Compares the TSV converted from a .blog with the TSV the writer wrote: the same header, the
/// same rows, every value the same text (both print what the column keeps: blog::TextFormat).
/// Columns named in skip are not compared (wall-clock times across two runs).
void expectSameRecording(const std::string& tsv, const std::string& converted,
                         const std::vector<blog::Column>& columns,
                         const std::vector<std::string>& skip = {}) {
  const auto a = lines(tsv), b = lines(converted);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GE(a.size(), 3u);
  EXPECT_EQ(a[0], b[0]);
  EXPECT_EQ(a[1], b[1]);
  std::size_t compared = 0;
  for (std::size_t i = 2; i < a.size(); ++i) {
    const auto x = cells(a[i]), y = cells(b[i]);
    ASSERT_EQ(x.size(), columns.size()) << "row " << i;
    ASSERT_EQ(y.size(), columns.size()) << "row " << i;
    for (std::size_t c = 0; c < columns.size(); ++c) {
      if (std::find(skip.begin(), skip.end(), columns[c].name) != skip.end()) continue;
      ASSERT_EQ(x[c], y[c]) << "row " << i << " column " << columns[c].name;
      ++compared;
    }
  }
  EXPECT_GT(compared, 0u);
}

TEST_F(LoopOnFake, BinaryAndTextRecordingsOfTheSameLockstepRunAgree) {
  // The fake backend in lockstep is deterministic: two fresh loops given the same commands
  // produce the same frames, but for the wall-clock times (solve and tick times).
  const std::string base = std::filesystem::temp_directory_path() /
                           ("ballast-roundtrip-" + std::to_string(getpid()));
  auto record = [&](const std::string& file) {
    TelemetryWriter writer(loop_->telemetryRing(), loop_->jointNames());
    loop_->setTelemetryWriter(&writer);
    writer.start();
    std::string error;
    ASSERT_TRUE(writer.startRecording(file, error, {"sim-flat", "humanoid", {}})) << error;
    ASSERT_TRUE(standUp());
    OperatorCommand c;
    c.kind = CommandKind::kPose;
    c.height = 0.84;
    c.pitch = 0.05;
    command(c);
    ticks(1500);
    std::uint64_t frames;
    std::string path;
    ASSERT_TRUE(writer.stopRecording(frames, path));
    writer.stop();
    loop_->setTelemetryWriter(nullptr);
  };
  record(base + ".tsv");
  TearDown();
  SetUp();
  record(base + ".blog");
  const auto columns = telemetryColumnsDescribed(loop_->jointNames());
  expectSameRecording(slurp(base + ".tsv"), blogAsTsv(base + ".blog"), columns,
                      {"mpc_ms", "wbc_ms", "tick_ms", "lateness_ms"});
  blog::Summary s;
  std::string error;
  ASSERT_TRUE(blog::summarize(base + ".blog", s, error)) << error;
  EXPECT_EQ(s.header.profile, "sim-flat");
  EXPECT_EQ(s.header.robot, "humanoid");
  EXPECT_GT(s.frames, 1500u);
  std::filesystem::remove(base + ".tsv");
  std::filesystem::remove(base + ".blog");
}

TEST(TelemetryWriter, BinaryAndTextRecordingsOfTheSameFramesAgreeInEveryColumn) {
  // The same frames (with every field set, the times too) through two writers.
  TelemetryRing text_ring(4096), binary_ring(4096);
  const std::vector<std::string> joints = {"hip", "knee", "ankle"};
  TelemetryWriter text(text_ring, joints), binary(binary_ring, joints);
  const std::string base = std::filesystem::temp_directory_path() /
                           ("ballast-frames-" + std::to_string(getpid()));
  std::string error;
  ASSERT_TRUE(text.startRecording(base + ".tsv", error)) << error;
  ASSERT_TRUE(binary.startRecording(base + ".blog", error)) << error;
  text.start();
  binary.start();
  for (int i = 0; i < 2500; ++i) {
    TelemetryFrame f;
    const double t = 0.001 * i;
    f.t = t;
    f.mode = static_cast<Mode>(i / 1000);
    for (int k = 0; k < 3; ++k) {
      f.base.position[k] = 0.1 * k + 0.01 * std::sin(t + k);
      f.base.linear_velocity[k] = 0.3 * std::cos(2 * t + k);
      f.base.rpy[k] = 0.02 * std::sin(3 * t + k);
      f.base.angular_velocity[k] = 0.1 * std::cos(5 * t + k);
    }
    f.has_truth = i % 2 == 0;
    f.truth = f.base;
    f.truth.position[2] += 1e-3;
    f.command.vx = 0.5;
    f.command.height = 0.84;
    for (int k = 0; k < kNumContacts; ++k) f.contact[k] = (i / 350 + k) % 2 == 0;
    for (int k = 0; k < kNumPriorityLevels; ++k) f.task_error[k] = k == 3 ? kNaN : 1e-3 * (k + 1) * std::sin(t);
    f.mpc_ms = 2.1 + 0.01 * (i % 7);
    f.wbc_ms = 0.31 + 0.001 * (i % 5);
    f.tick_ms = 0.4 + 0.003 * (i % 11);
    f.lateness_ms = 0.0;
    f.num_joints = 3;
    for (int j = 0; j < 3; ++j) {
      f.q[j] = 0.3 * std::sin(6 * t + j);
      f.dq[j] = 1.8 * std::cos(6 * t + j);
      f.tau[j] = 40 * std::sin(6 * t + j) + 0.05 * ((i * 7919 + j * 104729) % 101);
      f.q_ref[j] = f.q[j] + 1e-3;
      f.tau_ff[j] = 38 * std::sin(6 * t + j);
    }
    f.recording = text.activeRecording();
    while (!text_ring.tryPush(f)) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    f.recording = binary.activeRecording();
    while (!binary_ring.tryPush(f)) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  std::uint64_t text_frames, binary_frames;
  std::string path;
  ASSERT_TRUE(text.stopRecording(text_frames, path));
  ASSERT_TRUE(binary.stopRecording(binary_frames, path));
  text.stop();
  binary.stop();
  EXPECT_EQ(text_frames, 2500u);
  EXPECT_EQ(binary_frames, 2500u);
  expectSameRecording(slurp(base + ".tsv"), blogAsTsv(base + ".blog"),
                      telemetryColumnsDescribed(joints));
  std::filesystem::remove(base + ".tsv");
  std::filesystem::remove(base + ".blog");
}

/// Delegates to the fake and, at every backend call inside a tick, takes any reply the loop has
/// already let out and checks that the published status is at least as new as it. Keeps the
/// last commands written.
class WatchingBackend final : public backend::Backend {
 public:
  explicit WatchingBackend(backend::Backend& inner) : inner_(inner) {}
  bool configure(const backend::Config& c, backend::Error& e) override {
    return inner_.configure(c, e);
  }
  const backend::Capabilities& capabilities() const override { return inner_.capabilities(); }
  bool start(backend::Error& e) override { return inner_.start(e); }
  backend::Status read(backend::Sensors& s) override {
    check();
    return inner_.read(s);
  }
  backend::Status write(const backend::Commands& c) override {
    check();
    last = c;
    return inner_.write(c);
  }
  backend::Status advance(backend::TickTiming& timing) override {
    check();
    return inner_.advance(timing);
  }
  const backend::Error& lastError() const override { return inner_.lastError(); }
  void stop() override { inner_.stop(); }

  ControlLoop* loop = nullptr;
  int replies = 0, stale = 0;
  backend::Commands last;

 private:
  void check() {
    CommandReply r;
    while (loop && loop->popReply(r)) {
      ++replies;
      if (loop->status().mode != r.mode) ++stale;
    }
  }
  backend::Backend& inner_;
};

TEST_F(LoopOnFake, RepliesLeaveOnlyAfterTheStatusOfTheirTick) {
  // A client that has its reply and then asks for status must see the command's effect (the
  // acceptance scripts and the CLI rely on it): reset -> passive, not the damp before it.
  loop_.reset();
  WatchingBackend watcher(*backend_);
  LoopOptions options;
  options.lockstep = true;
  loop_ = std::make_unique<ControlLoop>(test::humanoid(), watcher, hand(settings_), options);
  watcher.loop = loop_.get();
  const CommandKind kinds[] = {CommandKind::kStand, CommandKind::kEstop, CommandKind::kReset,
                               CommandKind::kStand, CommandKind::kPassive};
  for (CommandKind k : kinds) {
    OperatorCommand c;
    c.kind = k;
    c.sequence = ++sequence_;
    ASSERT_TRUE(loop_->submit(c));
    ticks(2);
  }
  EXPECT_EQ(watcher.replies, 5);
  EXPECT_EQ(watcher.stale, 0);
  loop_.reset();  // before the watcher it points at
}

TEST_F(LoopOnFake, DampSendsOnlyVelocityDampingToEveryJoint) {
  loop_.reset();
  WatchingBackend watcher(*backend_);
  LoopOptions options;
  options.lockstep = true;
  loop_ = std::make_unique<ControlLoop>(test::humanoid(), watcher, hand(settings_), options);
  ASSERT_TRUE(standUp());
  OperatorCommand c;
  double stiffness = 0.0;
  for (int j = 0; j < watcher.last.num_joints; ++j) stiffness += watcher.last.joint[j].kp;
  EXPECT_GT(stiffness, 0.0);  // standing holds the posture
  c.kind = CommandKind::kEstop;
  command(c);
  ticks(2);
  ASSERT_EQ(loop_->status().mode, Mode::kDamp);
  ASSERT_EQ(watcher.last.num_joints, test::humanoid().nj());
  for (int j = 0; j < watcher.last.num_joints; ++j) {
    const backend::JointCommand& jc = watcher.last.joint[j];
    EXPECT_EQ(jc.kp, 0.0) << j;
    EXPECT_EQ(jc.tau_ff, 0.0) << j;
    EXPECT_EQ(jc.dq_des, 0.0) << j;
    EXPECT_GT(jc.kd, 0.0) << j;
  }
  loop_.reset();  // before the watcher it points at
}

TEST_F(LoopOnFake, StatusReadersNeverHoldTheLoopUp) {
  std::atomic<bool> done{false};
  std::atomic<long> reads{0};
  std::thread reader([&] {
    while (!done) {
      const LoopStatus s = loop_->status();
      ASSERT_LE(s.t, 1e6);
      ++reads;
    }
  });
  OperatorCommand c;
  c.kind = CommandKind::kStand;
  c.sequence = 1;
  loop_->submit(c);
  ticks(2000);
  done = true;
  reader.join();
  EXPECT_EQ(loop_->status().ticks, 1999u);
  EXPECT_GT(reads.load(), 0);
}

}  // namespace
}  // namespace ballast::control
