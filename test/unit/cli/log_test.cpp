// `ballast log` and `ballast plot` through the CLI (the built binary, no daemon), on recordings
// written here: --info, --to tsv|csv, --columns, --from/--to windows, -o, each figure of a .blog
// and a text recording, and what they say about bad values.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>

#include "blog/blog.hpp"
#include "test/unit/run_program.hpp"

namespace ballast::cli {
namespace {

using test::Outcome;

std::vector<std::string> split(const std::string& text, char sep) {
  std::vector<std::string> out;
  std::size_t start = 0;
  for (std::size_t end; (end = text.find(sep, start)) != std::string::npos; start = end + 1)
    out.push_back(text.substr(start, end - start));
  if (start < text.size()) out.push_back(text.substr(start));
  return out;
}

class Log : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("ballast-log-" + std::to_string(getpid()));
    std::filesystem::create_directories(dir_);
    file_ = (dir_ / "walk.blog").string();
    // 3 s at 1 kHz from t = 0.5: the time, the mode, two joints, a torque with NaN gaps, a flag.
    blog::Header h;
    h.profile = "sim-flat";
    h.robot = "humanoid";
    h.columns = {{"t", "s", blog::Type::kF64, 0, "controller time"},
                 {"mode", "-", blog::Type::kU8, 0, "the mode"},
                 {"q_knee", "rad", blog::Type::kI32, 1e-5, "joint position"},
                 {"q_hip", "rad", blog::Type::kI32, 1e-5, "joint position"},
                 {"tau_knee", "N*m", blog::Type::kI32, 0.01, "joint torque"},
                 {"contact_0", "-", blog::Type::kU8, 0, "contact"}};
    blog::Writer w;
    std::string error;
    ASSERT_TRUE(w.open(file_, h, error)) << error;
    for (int i = 0; i < 3000; ++i) {
      const double t = 0.5 + 0.001 * i;
      const double v[] = {t,
                          3,
                          0.3 * std::sin(6 * t),
                          -0.2 * std::cos(6 * t),
                          i % 100 == 7 ? std::nan("") : 40 * std::sin(6 * t),
                          double(i / 350 % 2)};
      w.append(v);
    }
    w.close();
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  Outcome log(std::vector<std::string> args) {
    args.insert(args.begin(), {BALLAST, "log", file_});
    return test::runProgram(args);
  }

  std::filesystem::path dir_;
  std::string file_;
};

TEST_F(Log, WithoutOptionsItPrintsTheTsvRecording) {
  const Outcome r = log({});
  ASSERT_EQ(r.status, 0) << r.err;
  const auto lines = split(r.out, '\n');
  ASSERT_EQ(lines.size(), 3002u);
  EXPECT_EQ(lines[0], "# ballast telemetry 1");
  EXPECT_EQ(lines[1], "# t\tmode\tq_knee\tq_hip\ttau_knee\tcontact_0");
  EXPECT_EQ(lines[2], "0.5\t3\t0.04234\t0.198\t5.64\t0");  // each to its resolution
  EXPECT_EQ(split(lines[9], '\t')[4], "NaN");                 // frame 7
  EXPECT_EQ(r.err, "");
}

TEST_F(Log, ToCsvWritesOneLineOfNamesAndEmptyFieldsForNaN) {
  const Outcome r = log({"--to", "csv"});
  ASSERT_EQ(r.status, 0) << r.err;
  const auto lines = split(r.out, '\n');
  ASSERT_EQ(lines.size(), 3001u);
  EXPECT_EQ(lines[0], "t,mode,q_knee,q_hip,tau_knee,contact_0");
  EXPECT_EQ(lines[1], "0.5,3,0.04234,0.198,5.64,0");
  EXPECT_EQ(lines[8], "0.507,3,0.02983,0.19901,,0");  // frame 7: no torque
  // The same values as the TSV, another separator.
  const auto tsv = split(log({"--to", "tsv"}).out, '\n');
  for (std::size_t i = 1; i < lines.size(); ++i) {
    std::string row = tsv[i + 1];
    for (char& c : row) c = c == '\t' ? ',' : c;
    if (row.find("NaN") != std::string::npos) continue;
    ASSERT_EQ(lines[i], row) << i;
  }
}

TEST_F(Log, ColumnsKeepsTheMatchingColumnsInFileOrderAfterT) {
  Outcome r = log({"--to", "csv", "--columns", "tau_*,q_*"});
  ASSERT_EQ(r.status, 0) << r.err;
  auto lines = split(r.out, '\n');
  EXPECT_EQ(lines[0], "t,q_knee,q_hip,tau_knee");
  EXPECT_EQ(lines[1], "0.5,0.04234,0.198,5.64");
  r = log({"--columns", "q_hip", "--columns", "mode"});  // repeated, and without t: t is kept
  ASSERT_EQ(r.status, 0) << r.err;
  lines = split(r.out, '\n');
  EXPECT_EQ(lines[1], "# t\tmode\tq_hip");
  r = log({"--columns", "q_*,nope*"});
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("no column matches 'nope*'"), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "");
  r = test::runProgram({BALLAST, "--json", "log", file_, "--columns", "nope"});
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.parsed()["error"]["code"], "no_such_column") << r.out;
}

TEST_F(Log, FromAndToKeepTheFramesOfAWindow) {
  Outcome r = log({"--to", "csv", "--from", "1", "--to", "1.5", "--columns", "mode"});
  ASSERT_EQ(r.status, 0) << r.err;
  auto lines = split(r.out, '\n');
  ASSERT_EQ(lines.size(), 502u);  // 1.000 .. 1.500, both ends
  EXPECT_EQ(lines[1], "1,3");
  EXPECT_EQ(lines.back(), "1.5,3");
  // Units, and the format after the time.
  r = log({"--from", "1000ms", "--to", "1.5s", "--to", "csv", "--columns", "mode"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(split(r.out, '\n'), lines);
  r = log({"--from", "3.2", "--columns", "mode"});  // to the end: 3.2 .. 3.499
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(split(r.out, '\n').size(), 2u + 300);
  r = log({"--to", "0.5009", "--columns", "mode"});  // from the start
  EXPECT_EQ(split(r.out, '\n').size(), 2u + 1);
  // A window without frames: the header, and a word on standard error.
  r = log({"--from", "10", "--to", "20"});
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(split(r.out, '\n').size(), 2u);
  EXPECT_NE(r.err.find("no frame"), std::string::npos) << r.err;
}

TEST_F(Log, BadValuesAreUsageErrors) {
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"--to", "json"}, {"--to", "tsv", "--to", "csv"},
        {"--to", "1", "--to", "2"}, {"--from", "-1"}, {"--from", "soon"},
        {"--from", "2", "--to", "1"}, {"--info", "--to", "csv"}, {"--info", "--from", "1"}}) {
    const Outcome r = log(args);
    EXPECT_EQ(r.status, 2) << args[0] << " " << args[1];
    EXPECT_NE(r.err.find("ballast"), std::string::npos);
  }
  const Outcome r = test::runProgram({BALLAST, "log", (dir_ / "missing.blog").string()});
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("cannot read"), std::string::npos) << r.err;
}

TEST_F(Log, OutputGoesToAFileThatPlotReads) {
  const std::string out = (dir_ / "window.tsv").string();
  Outcome r = log({"--from", "1", "--to", "2", "-o", out});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "");
  std::ifstream in(out);
  std::string first;
  std::getline(in, first);
  EXPECT_EQ(first, "# ballast telemetry 1");
  r = log({"--columns", "nope", "-o", out});
  EXPECT_EQ(r.status, 1);
  EXPECT_FALSE(std::filesystem::exists(out));  // no half-written file left behind
}

TEST_F(Log, InfoDescribesTheFileAndItsColumns) {
  Outcome r = log({"--info"});
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* line :
       {"format    ballast binary log, version 2", "profile   sim-flat", "robot     humanoid",
        "frames    3000 (t 0.500 to 3.499 s: 2.999 s)", "columns   6\n",
        "  q_knee    rad    1e-05        joint position", "  t         s      exact (f64)"})
    EXPECT_NE(r.out.find(line), std::string::npos) << line << "\n" << r.out;
  r = log({"--info", "--columns", "tau_*"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("columns   2 of 6"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("q_knee"), std::string::npos);
  r = test::runProgram({BALLAST, "--json", "log", file_, "--info"});
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = r.parsed();
  EXPECT_EQ(j["frames"], 3000);
  EXPECT_EQ(j["format"], 2);
  EXPECT_EQ(j["columns"][4]["name"], "tau_knee");
  EXPECT_EQ(j["columns"][4]["resolution"], 0.01);
  EXPECT_EQ(j["columns"][4]["doc"], "joint torque");
  EXPECT_FALSE(j["columns"][0].contains("resolution"));
  EXPECT_GT(j["bytes_per_frame"].get<double>(), 0.0);
}

TEST_F(Log, ATruncatedFileConvertsItsCompleteBlocksWithAWarning) {
  const auto size = std::filesystem::file_size(file_);
  std::filesystem::resize_file(file_, size - 10);  // inside the last block (frames 2000..2999)
  const Outcome r = log({"--to", "csv", "--columns", "mode"});
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(split(r.out, '\n').size(), 1u + 2000);
  EXPECT_NE(r.err.find("truncated"), std::string::npos) << r.err;
}

/// A short walk-like recording with every figure's columns and the robot's limbs.
class PlotCli : public Log {
 protected:
  void SetUp() override {
    Log::SetUp();
    blog_ = (dir_ / "robot.blog").string();
    script_ = (dir_ / "plot.gp").string();
    blog::Header h;
    h.limbs = {{"left_foot", {"left_hip", "left_knee"}}, {"right_foot", {"right_hip"}}};
    auto col = [](const std::string& name, double resolution) {
      return blog::Column{name, "-", resolution > 0 ? blog::Type::kI32 : blog::Type::kF64,
                          resolution, ""};
    };
    std::vector<std::string> names = {"t", "v_fwd", "cmd_vx", "limb_err", "z", "roll", "pitch",
                                      "yaw", "mpc_ms", "wbc_ms", "tick_ms", "lateness_ms"};
    for (const char* prefix : {"contact_", "fx_", "fy_", "fz_"})
      for (int i = 0; i < 4; ++i) names.push_back(prefix + std::to_string(i));
    for (const char* prefix : {"q_", "qref_"})
      for (const char* j : {"left_hip", "left_knee", "right_hip"}) names.push_back(prefix + std::string(j));
    for (const auto& n : names) h.columns.push_back(col(n, n == "t" ? 0 : 1e-4));
    blog::Writer w;
    std::string error;
    ASSERT_TRUE(w.open(blog_, h, error)) << error;
    std::vector<double> v(names.size());
    for (int i = 0; i < 2000; ++i) {
      const double t = 0.001 * i;
      for (std::size_t c = 1; c < names.size(); ++c) v[c] = std::sin(t * c) + (c % 3 == 0 ? 0.5 : 0);
      v[0] = t;
      for (int k = 0; k < 4; ++k) v[12 + k] = (i / 400 + k / 2) % 2;  // contacts
      w.append(v.data());
    }
    w.close();
  }

  /// ballast plot ARGS, gnuplot's script kept in script_.
  Outcome plot(std::vector<std::string> args) {
    args.insert(args.begin(), {BALLAST, "plot"});
    return test::runProgram(args, {"BALLAST_GNUPLOT=tee " + script_ + " | gnuplot"});
  }
  std::string script() const {
    std::ifstream in(script_);
    return {std::istreambuf_iterator<char>(in), {}};
  }

  std::string blog_, script_;
};

TEST_F(PlotCli, EachFigureOfABinaryRecording) {
  const std::map<std::string, std::vector<std::string>> panels = {
      {"fig3", {"(a) velocity tracking", "(b) limb tracking error", "(c) height", "(d) roll",
                "(e) pitch", "(f) yaw"}},
      {"fig6", {"(a) height", "(b) yaw", "(c) pitch", "(d) roll"}},
      {"contacts", {"(a) left foot: normal force", "(b) right foot: normal force",
                    "(c) contact schedule", "(d) friction used"}},
      {"timing", {"(a) solve times", "(b) tick work and lateness", "(c) tick lateness",
                  "(d) solve times"}},
      {"joints", {"(a) left_foot", "(b) right_foot"}}};
  for (const auto& [figure, titles] : panels) {
    const std::string png = (dir_ / (figure + ".png")).string();
    const Outcome r = plot({blog_, "--fig", figure, "-o", png});
    ASSERT_EQ(r.status, 0) << figure << ": " << r.err;
    EXPECT_NE(r.out.find("2000 frames"), std::string::npos) << r.out;
    std::ifstream image(png, std::ios::binary);
    std::string magic(4, '\0');
    image.read(magic.data(), 4);
    EXPECT_EQ(magic.substr(1, 3), "PNG") << figure;
    const std::string g = script();
    for (const auto& title : titles) EXPECT_NE(g.find(title), std::string::npos) << title;
    EXPECT_EQ(g.find("no data in this recording"), std::string::npos) << figure;
  }
  // The temporary conversion is gone.
  for (const auto& e : std::filesystem::directory_iterator(std::filesystem::temp_directory_path()))
    EXPECT_EQ(e.path().filename().string().rfind("ballast-plot-" + std::to_string(getpid()), 0),
              std::string::npos);
}

TEST_F(PlotCli, AWindowOfABinaryOrATextRecording) {
  const std::string png = (dir_ / "w.png").string(), tsv = (dir_ / "robot.tsv").string();
  Outcome r = plot({blog_, "--fig", "contacts", "--from", "0.5", "--to", "1s", "-o", png});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("501 frames"), std::string::npos) << r.out;  // 0.5 .. 1.0 converted
  ASSERT_EQ(test::runProgram({BALLAST, "log", blog_, "-o", tsv}).status, 0);
  r = plot({tsv, "--fig", "timing", "--from", "500ms", "--to", "1", "-o", png});
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string g = script();
  EXPECT_NE(g.find("set xrange [0.5:1]"), std::string::npos);  // gnuplot windows the text
  EXPECT_NE(g.find("tmin = 0.5\ntmax = 1\n"), std::string::npos);  // and the histograms
  // The text names the limbs as the .blog does; one from before it did gets joints in threes.
  r = plot({tsv, "--fig", "joints", "-o", png});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(script().find("(a) left_foot"), std::string::npos);
  EXPECT_NE(script().find("(b) right_foot"), std::string::npos);
  const std::string old = (dir_ / "old.tsv").string();
  {
    std::ifstream in(tsv);
    std::ofstream out(old);
    int limbs = 0;
    for (std::string line; std::getline(in, line);)
      if (line.rfind("# limb ", 0) == 0)
        ++limbs;
      else
        out << line << '\n';
    EXPECT_EQ(limbs, 2);
  }
  r = plot({old, "--fig", "joints", "-o", png});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(script().find("(a) joints 1-3"), std::string::npos);
}

TEST_F(PlotCli, BadFiguresAndEmptyWindowsAreSaidSo) {
  const std::string png = (dir_ / "x.png").string();
  Outcome r = plot({blog_, "--fig", "nope", "-o", png});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("fig3, fig6, contacts, timing, joints"), std::string::npos) << r.err;
  r = plot({blog_, "--from", "5", "-o", png});
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("no frame"), std::string::npos) << r.err;
  r = plot({blog_, "--from", "2", "--to", "1", "-o", png});
  EXPECT_EQ(r.status, 2);
  r = plot({file_, "--fig", "contacts", "-o", png});  // a recording without those columns
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(script().find("no data in this recording"), std::string::npos);
}

}  // namespace
}  // namespace ballast::cli
