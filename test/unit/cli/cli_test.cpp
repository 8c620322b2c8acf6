// The CLI's own parts: what an operator types, looking fields up in a status, the plot script.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "cli/client.hpp"
#include "cli/plot.hpp"
#include "cli/status_view.hpp"
#include "cli/units.hpp"
#include "cli/verbs.hpp"

namespace ballast::cli {
namespace {

TEST(Units, DurationsAnglesVectors) {
  double v;
  std::string e;
  EXPECT_TRUE(parseDuration("3", v, e));
  EXPECT_DOUBLE_EQ(v, 3.0);
  EXPECT_TRUE(parseDuration("2.5s", v, e));
  EXPECT_DOUBLE_EQ(v, 2.5);
  EXPECT_TRUE(parseDuration("500ms", v, e));
  EXPECT_DOUBLE_EQ(v, 0.5);
  EXPECT_TRUE(parseDuration("2min", v, e));
  EXPECT_DOUBLE_EQ(v, 120.0);
  for (const char* bad : {"", "soon", "-1", "0", "3h", "1e999", "nan"}) {
    EXPECT_FALSE(parseDuration(bad, v, e)) << bad;
    EXPECT_NE(e.find("e.g. 3, 2.5s, 500ms"), std::string::npos);
  }
  EXPECT_TRUE(parseAngle("5deg", v, e));
  EXPECT_DOUBLE_EQ(v, 5 * M_PI / 180);
  EXPECT_TRUE(parseAngle("-0.1", v, e));
  EXPECT_DOUBLE_EQ(v, -0.1);
  EXPECT_TRUE(parseAngle("0.2rad", v, e));
  EXPECT_FALSE(parseAngle("5degrees", v, e));
  EXPECT_NE(e.find("5deg"), std::string::npos);
  std::array<double, 3> f;
  EXPECT_TRUE(parseVector3("40,0,-1.5", f, e));
  EXPECT_EQ(f, (std::array<double, 3>{40, 0, -1.5}));
  for (const char* bad : {"1,2", "1,2,3,4", "a,b,c", "1,,3"})
    EXPECT_FALSE(parseVector3(bad, f, e)) << bad;
}

TEST(StatusView, LookupByDottedPath) {
  const nlohmann::json s = {{"mode", "stand"},
                            {"base", {{"position", {0.1, -0.2, 0.89}}}},
                            {"timing", {{"tick_overruns", 0}}},
                            {"contacts", {true, false, true, true}}};
  std::string v;
  ASSERT_TRUE(lookup(s, "mode", v));
  EXPECT_EQ(v, "stand");
  ASSERT_TRUE(lookup(s, "base.position", v));
  EXPECT_EQ(v, "0.1 -0.2 0.89");
  ASSERT_TRUE(lookup(s, "base.position.2", v));
  EXPECT_EQ(v, "0.89");
  ASSERT_TRUE(lookup(s, "contacts.1", v));
  EXPECT_EQ(v, "false");
  ASSERT_TRUE(lookup(s, "timing.tick_overruns", v));
  EXPECT_EQ(v, "0");
  EXPECT_FALSE(lookup(s, "base.velocity", v));
  EXPECT_FALSE(lookup(s, "contacts.9", v));
  const std::string text = renderStatus(s);
  EXPECT_NE(text.find("mode       stand"), std::string::npos);
  EXPECT_NE(text.find("faults     none"), std::string::npos) << text;
}

TEST(LeaseFile, OnePerSocketUnlessGiven) {
  EXPECT_EQ(leaseFile("/x/lease", "/run/a.sock"), "/x/lease");
  const std::string a = leaseFile("", "/run/a.sock"), b = leaseFile("", "/run/b.sock");
  if (!std::getenv("BALLAST_LEASE_FILE")) {
    EXPECT_NE(a, b);
  }
  EXPECT_EQ(a, leaseFile("", "/run/./a.sock"));
  EXPECT_EQ(socketPath("/given.sock"), "/given.sock");
}

class Plot : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = std::filesystem::temp_directory_path() /
            ("ballast-plot-" + std::to_string(getpid()) + ".tsv");
  }
  void TearDown() override { std::filesystem::remove(path_); }
  std::filesystem::path path_;
};

TEST_F(Plot, ReadsARecordingAndPlotsOnlySeriesWithData) {
  std::ofstream(path_) << "# ballast telemetry 1\n# t\tmode\tv_fwd\ttrue_v_fwd\tcmd_vx\tlimb_err\tz\n"
                       << "0\t2\t0.1\tNaN\t0\tNaN\t0.89\n0.001\t2\t0.11\tNaN\t0\tNaN\t0.89\n";
  TelemetryTable t;
  std::string error;
  ASSERT_TRUE(readTelemetry(path_, t, error)) << error;
  EXPECT_EQ(t.rows, 2u);
  EXPECT_EQ(t.column("v_fwd"), 3);
  EXPECT_TRUE(t.has_data[2]);
  EXPECT_FALSE(t.has_data[3]);  // no ground truth in this one
  EXPECT_DOUBLE_EQ(t.max[2], 0.11);
  PlotOptions o;
  o.title = "title";
  const std::string g = plotScript(t, path_, "/tmp/x.png", o);
  EXPECT_NE(g.find("set terminal pngcairo"), std::string::npos);
  EXPECT_NE(g.find("set multiplot layout 2,3"), std::string::npos);
  for (const char* panel : {"(a) velocity tracking", "(b) limb tracking error", "(c) height",
                            "(d) roll", "(e) pitch", "(f) yaw"})
    EXPECT_NE(g.find(panel), std::string::npos) << panel;
  EXPECT_NE(g.find("using 1:($3) with lines"), std::string::npos);     // v_fwd
  EXPECT_EQ(g.find("using 1:($4) with lines"), std::string::npos);     // true_v_fwd: all NaN
  EXPECT_NE(g.find("no data in this recording"), std::string::npos);  // (b): limb_err all NaN
}

TEST_F(Plot, EachFigureHasItsPanels) {
  std::ofstream(path_)
      << "# ballast telemetry 1\n# t\tcontact_0\tcontact_1\tfz_0\tfz_1\tfx_0\tfx_1\tfy_0\tfy_1"
         "\tmpc_ms\twbc_ms\ttick_ms\tlateness_ms\tq_hip\tqref_hip\tq_knee\tqref_knee\n"
      << "0\t1\t0\t300\t0\t10\t0\t2\t0\t2.5\t0.3\t0.5\t0.012\t0.1\t0.11\t0.5\t0.52\n"
      << "0.001\t1\t1\t250\t60\t9\t1\t2\t0\t2.5\t0.31\t0.52\t0.06\t0.1\t0.1\t0.5\t0.5\n";
  TelemetryTable t;
  std::string error;
  ASSERT_TRUE(readTelemetry(path_, t, error)) << error;
  PlotOptions o;
  o.from = 0.0005;
  const std::map<std::string, std::vector<std::string>> panels = {
      {"contacts",
       {"(a) left foot: normal force", "(b) right foot: normal force", "(c) contact schedule",
        "(d) friction used"}},
      {"timing", {"(a) solve times", "(b) tick work and lateness", "(c) tick lateness",
                  "(d) solve times"}},
      {"joints", {"(a) joints 1-2"}}};
  for (const auto& [name, titles] : panels) {
    o.figure = findFigure(name);
    ASSERT_NE(o.figure, nullptr) << name;
    const std::string g = plotScript(t, path_, "/tmp/x.png", o);
    for (const std::string& title : titles) EXPECT_NE(g.find(title), std::string::npos) << title;
    EXPECT_NE(g.find("set xrange [0.0005:*]"), std::string::npos) << name;  // the window
  }
  o.figure = findFigure("contacts");
  std::string g = plotScript(t, path_, "/tmp/x.png", o);
  EXPECT_NE(g.find("using 1:($4 + $5)"), std::string::npos) << g;  // the left foot's sum
  EXPECT_NE(g.find("'no data in this recording'"), std::string::npos);  // (b): no right foot
  o.figure = findFigure("timing");
  g = plotScript(t, path_, "/tmp/x.png", o);
  // 60 bins up to the largest lateness, 0.06 ms: 1 µs.
  EXPECT_NE(g.find("using (inwin($1) ? bin(($13), 0.001) : NaN):(1) smooth frequency"),
            std::string::npos) << g;
  o.figure = findFigure("joints");
  t.limbs = {{"left_leg", {"hip", "knee"}}};
  g = plotScript(t, path_, "/tmp/x.png", o);
  EXPECT_NE(g.find("(a) left_leg"), std::string::npos);
  EXPECT_NE(g.find("using 1:(($14 - $15)*180/pi) with lines"), std::string::npos) << g;
  EXPECT_NE(g.find("title 'knee'"), std::string::npos);
  EXPECT_EQ(findFigure("nope"), nullptr);
  // A long recording's time panels draw 1 frame in N, no more than 50 000; the timing figure
  // draws every frame.
  t.rows = 120000;
  g = plotScript(t, path_, "/tmp/x.png", o);
  EXPECT_NE(g.find("every 3 using 1:(($14 - $15)*180/pi)"), std::string::npos) << g;
  EXPECT_NE(g.find("(1 frame in 3 drawn)"), std::string::npos);
  o.figure = findFigure("timing");
  EXPECT_EQ(plotScript(t, path_, "/tmp/x.png", o).find("every "), std::string::npos);
  // A slice of a binary recording holds the window's frames only: the window sets the axes and
  // is not applied to the data again.
  o.sliced = true;
  g = plotScript(t, path_, "/tmp/x.png", o);
  EXPECT_NE(g.find("set xrange [0.0005:*]"), std::string::npos) << g;
  EXPECT_NE(g.find("tmin = -1e300"), std::string::npos) << g;
  o.sliced = false;
  EXPECT_NE(plotScript(t, path_, "/tmp/x.png", o).find("tmin = 0.0005"), std::string::npos);
  // Only the rows of a window count.
  TelemetryTable w;
  ASSERT_TRUE(readTelemetry(path_, w, error, 0.0005, 1)) << error;
  EXPECT_EQ(w.rows, 1u);
  EXPECT_DOUBLE_EQ(w.max[3], 250);  // fz_0 of the second row only
  EXPECT_FALSE(readTelemetry(path_, w, error, 2, 3));
  EXPECT_NE(error.find("no frame"), std::string::npos) << error;
}

TEST_F(Plot, RefusesWhatIsNotARecording) {
  std::ofstream(path_) << "t,x\n1,2\n";
  TelemetryTable t;
  std::string error;
  EXPECT_FALSE(readTelemetry(path_, t, error));
  EXPECT_NE(error.find("ballast record start"), std::string::npos);
  std::ofstream(path_) << "# ballast telemetry 1\n# t\tx\n";
  TelemetryTable empty;
  EXPECT_FALSE(readTelemetry(path_, empty, error));
  EXPECT_NE(error.find("holds no frames"), std::string::npos);
}

// The CLI's verbs send protocol commands, and every command but the ones no verb needs has one;
// their help is the table's.
TEST(Verbs, EveryCommandHasAVerbAndItsHelpIsTheTables) {
  std::set<std::string> sent;
  for (const cli::Verb& v : cli::kVerbs) {
    EXPECT_NE(protocol::findCommand(v.command), nullptr) << v.words << " sends " << v.command;
    EXPECT_STRNE(cli::help(v.command), "") << v.command;
    sent.insert(v.command);
  }
  for (const char* c : cli::kNotSent) sent.insert(c);
  for (const auto& c : protocol::kCommands) EXPECT_TRUE(sent.count(c.name)) << c.name << " has no verb";
}

}  // namespace
}  // namespace ballast::cli
