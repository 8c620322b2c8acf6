// ballast-study: the paper's comparison (Sec. III-A) in one command. The variants cH, cNH and cI
// (profiles/study/*.yaml) walk at 0.5, 1.0 and 1.2 m/s and take pushes of 20, 40 and 60 N for
// 1 s along x while walking at 0.5 m/s; each run is a ballastd process in lockstep, held
// (ballastd --lockstep --hold), driven through the protocol like any client: every command lands
// at the controller time the script gives it, so a run is the same for one seed however loaded
// the machine is. Several runs go at once (--jobs), with a line per run on the terminal.
//
// Script of a run (controller time): stand until 2 s; walk (the experiment's speed, or 0.5 m/s
// for a push) from 2 s; a push at 5 s for 1 s; the end. The metrics' window (study_metrics.hpp):
// walking, the 10 s from 6 s on (steady speed: the start and the velocity's slew are over);
// pushes, from the push to the end (5 s after it). --quick: walk 1.0 m/s and the 40 N push
// only, 2 s windows, for the tests.
//
// Output in DIR: study.md (the table, the paper's outcome beside ours), study.json (the same,
// for programs), fig3.png (walking at 1.0 m/s, the variants laid out as the paper's Fig. 3:
// velocity, limb tracking error, height, roll, pitch, yaw) and fig5.png (the 40 N push as its
// Fig. 5: x, y, height, roll, pitch, yaw), drawn by gnuplot; runs/ (each run's profile,
// recording and daemon log) and data/ (the figures' series, 100 Hz).
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/client.hpp"
#include "cli/plot.hpp"
#include "cli/study_metrics.hpp"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using ballast::cli::MetricsWindow;
using ballast::cli::Recording;
using ballast::cli::RunMetrics;

constexpr double kStandUntil = 2.0;  // s: stand-up (1 s) and settling
constexpr double kPushAt = 5.0;      // s: the paper pushes at the fifth second
constexpr double kPushFor = 1.0;     // s
constexpr double kPushWalk = 0.5;    // m/s: walking while pushed (DESIGN.md's figures)

struct Experiment {
  std::string name;
  bool push = false;
  double speed = 0.0;  // m/s
  double force = 0.0;  // N along +x
};

/// The paper's outcome (Sec. III-A): which variant fell in which experiment. It reports the
/// lowest speed or force each variant fell at; beyond that it ran nothing ("not reported").
std::string paperOutcome(const std::string& variant, const Experiment& e) {
  const double value = e.push ? e.force : e.speed;
  const double fellAt = variant == "cI"    ? (e.push ? 20.0 : 0.5)
                        : variant == "cNH" ? (e.push ? 60.0 : 1.2)
                                           : -1.0;
  if (fellAt < 0.0) return "stable";
  if (std::abs(value - fellAt) < 1e-9) return "fell";
  return value < fellAt ? "stable" : "not reported";
}

struct Options {
  std::string out = "study";
  int jobs = 0;
  std::vector<std::string> variants{"cH", "cNH", "cI"};
  bool quick = false;
  long seed = -1;  // the profiles' own (backend.seed) when negative
  std::string ballastd, profiles;
};

std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

std::string selfDirectory() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string(".") : self.parent_path().string();
}

/// Options, or exits (2 for bad arguments, as CLI11 does).
Options parse(int argc, char** argv) {
  Options o;
  std::string variants = "cH,cNH,cI";
  CLI::App app{"ballast-study: the paper's comparison of cH, cNH and cI in lockstep simulation "
               "(ballast-study(1))"};
  app.add_option("--out", o.out, "where the table, the figures and the runs go (default: study)");
  app.add_option("-j,--jobs", o.jobs, "runs at a time (default: the number of processors)");
  app.add_option("--variants", variants, "comma-separated profiles in --profiles (default: cH,cNH,cI)");
  app.add_flag("--quick", o.quick, "walk 1.0 m/s and the 40 N push only, 2 s windows (the tests' run)");
  app.add_option("--seed", o.seed, "backend.seed of every run (default: the profiles')")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--profiles", o.profiles,
                 "the variants' profiles (default: the source tree's profiles/study, else the installed)");
  app.add_option("--ballastd", o.ballastd, "the daemon (default: ballastd beside ballast-study)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    std::exit(app.exit(e));
  }
  o.variants = split(variants);
  auto refuse = [](const std::string& why) {
    std::fprintf(stderr, "ballast-study: %s\n", why.c_str());
    std::exit(2);
  };
  if (o.variants.empty()) refuse("--variants names none");
  if (o.jobs <= 0) o.jobs = static_cast<int>(std::max(1L, sysconf(_SC_NPROCESSORS_ONLN)));
  if (o.ballastd.empty()) o.ballastd = selfDirectory() + "/ballastd";
  if (o.profiles.empty()) {
    o.profiles = BALLAST_SOURCE_DIR "/profiles/study";
    if (!fs::exists(o.profiles)) o.profiles = BALLAST_INSTALL_PROFILE_DIR "/study";
  }
  for (const std::string& v : o.variants)
    if (!fs::exists(o.profiles + "/" + v + ".yaml"))
      refuse("no profile " + o.profiles + "/" + v + ".yaml (--profiles DIR)");
  return o;
}

std::vector<Experiment> experiments(bool quick) {
  std::vector<Experiment> e;
  for (double v : {0.5, 1.0, 1.2})
    if (!quick || v == 1.0) {
      char name[32];
      std::snprintf(name, sizeof name, "walk_%.1f", v);
      e.push_back({name, false, v, 0.0});
    }
  for (double f : {20.0, 40.0, 60.0})
    if (!quick || f == 40.0) e.push_back({"push_" + std::to_string(static_cast<int>(f)) + "N", true, kPushWalk, f});
  return e;
}

/// When a run ends, and its metrics' window.
double endTime(const Experiment& e, bool quick) {
  if (e.push) return kPushAt + kPushFor + (quick ? 2.0 : 5.0);
  return quick ? kStandUntil + 5.0 : kStandUntil + 14.0;
}
MetricsWindow windowOf(const Experiment& e, bool quick) {
  MetricsWindow w;
  w.end = endTime(e, quick);
  w.begin = e.push ? kPushAt : w.end - (quick ? 2.0 : 10.0);
  w.headingTime = kStandUntil;
  return w;
}

struct Run {
  std::string variant;
  Experiment experiment;
  std::string profile, recording, log, socket;
  // results
  bool ok = false;
  std::string error;
  RunMetrics metrics;
  double wallSeconds = 0.0;
};

/// One ballastd, scripted through the protocol.
class Driver {
 public:
  explicit Driver(Run& run) : run_(run) {}
  ~Driver() { stopDaemon(); }

  void execute(const std::string& ballastd, bool quick) {
    start(ballastd);
    token_ = request({{"cmd", "lease_acquire"}})["lease"].get<std::string>();
    request({{"cmd", "record_start"}, {"path", run_.recording}});
    const Experiment& e = run_.experiment;
    const double end = endTime(e, quick);
    if (!advance(kStandUntil)) throw std::runtime_error("fell before walking");
    if (status_.value("mode", "") != "stand")
      throw std::runtime_error("not standing at t = 2 s (mode " + status_.value("mode", "?") + ")");
    motion({{"cmd", "walk"}, {"vx", e.speed}, {"ttl", end - kStandUntil + 1.0}});
    if (e.push && advance(kPushAt))
      motion({{"cmd", "push"}, {"force", {e.force, 0.0, 0.0}}, {"duration", kPushFor}, {"body", "torso"}});
    advance(end);  // a fall ends the script early; the recording says when
    request({{"cmd", "record_stop"}});
    stopDaemon();
  }

 private:
  void start(const std::string& ballastd) {
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, run_.log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    std::vector<std::string> args{ballastd, "--profile", run_.profile, "--lockstep", "--hold",
                                  "--socket", run_.socket, "--log-level", "warn"};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    const int rc = posix_spawn(&pid_, ballastd.c_str(), &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) {
      pid_ = -1;
      throw std::runtime_error("cannot start " + ballastd + ": " + std::strerror(rc));
    }
    std::string error;
    for (int i = 0;; ++i) {
      if (conn_.open(run_.socket, error)) return;
      int status;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        throw std::runtime_error("ballastd exited at start (its log: " + run_.log + ")");
      }
      if (i > 600) throw std::runtime_error("ballastd did not come up in 60 s: " + error);
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  }

  json request(json r) {
    json reply;
    std::string error;
    if (!conn_.request(r, reply, error, 30.0)) throw std::runtime_error(r["cmd"].get<std::string>() + ": " + error);
    if (!reply.value("ok", false))
      throw std::runtime_error(r["cmd"].get<std::string>() + ": " +
                               reply["error"].value("message", reply.dump()));
    return reply;
  }
  json motion(json r) {
    r["lease"] = token_;
    return request(r);
  }

  /// Runs to controller time `until`; false as soon as the robot is damped or has fallen.
  bool advance(double until) {
    motion({{"cmd", "advance"}, {"until", until}});
    const auto start = std::chrono::steady_clock::now();
    for (;;) {
      status_ = request({{"cmd", "status"}})["status"];
      if (status_.value("fallen", false) || status_.value("mode", "") == "damp") return false;
      if (status_.value("t", 0.0) >= until - 1e-6) return true;
      const double waited =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (waited > 120.0 + 30.0 * until)
        throw std::runtime_error("the simulation did not reach t = " + std::to_string(until) + " s");
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }

  void stopDaemon() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGTERM);
    int status;
    waitpid(pid_, &status, 0);
    pid_ = -1;
  }

  Run& run_;
  ballast::cli::Connection conn_;
  pid_t pid_ = -1;
  std::string token_;
  json status_;
};

// ---- output

std::string fixed(double v, int digits) {
  if (!std::isfinite(v)) return "-";  // fell before the window
  char b[32];
  std::snprintf(b, sizeof b, "%.*f", digits, v);
  return b;
}
constexpr double kDeg = 180.0 / M_PI;

std::string outcome(const Run& r) {
  if (!r.ok) return "error";
  return r.metrics.fell ? "fell at " + fixed(r.metrics.fallTime, 2) + " s" : "stable";
}

json runJson(const Run& r, bool quick) {
  const MetricsWindow w = windowOf(r.experiment, quick);
  json j = {{"variant", r.variant},
            {"experiment", r.experiment.name},
            {"kind", r.experiment.push ? "push" : "walk"},
            {"speed", r.experiment.speed},
            {"paper", paperOutcome(r.variant, r.experiment)},
            {"ok", r.ok}};
  if (r.experiment.push) j["force"] = r.experiment.force;
  if (!r.ok) {
    j["error"] = r.error;
    return j;
  }
  const RunMetrics& m = r.metrics;
  j["fell"] = m.fell;
  j["fall_time"] = m.fell ? json(m.fallTime) : json(nullptr);
  j["window"] = {w.begin, m.fell ? std::min(w.end, m.fallTime) : w.end};
  auto number = [](double v) { return std::isfinite(v) ? json(v) : json(nullptr); };  // NaN: none
  j["velocity_rms"] = number(m.velocity);
  j["limb_error_rms"] = number(m.limb);
  j["height_rms"] = number(m.height);
  j["roll_rms"] = number(m.roll);
  j["pitch_rms"] = number(m.pitch);
  j["yaw_rms"] = number(m.yaw);
  j["mpc_ms"] = number(m.mpcMs);
  j["wbc_ms"] = number(m.wbcMs);
  j["recording"] = r.recording;
  return j;
}

void writeMarkdown(const std::string& path, const Options& o, const std::vector<Run>& runs,
                   double wallSeconds) {
  std::ofstream md(path);
  md << "# The paper's comparison (Sec. III-A), rerun by ballast-study\n\n"
     << "Lockstep Simbody simulation (profiles/study/*.yaml, extending sim-flat), "
     << (o.seed >= 0 ? "seed " + std::to_string(o.seed) : std::string("the profiles' seed"))
     << (o.quick ? ", --quick (walk 1.0 m/s and the 40 N push only, 2 s windows)" : "")
     << ". Walking: forward from 2 s, metrics over the 10 s from 6 s on"
     << (o.quick ? " (quick: the last 2 s)" : "") << ". Pushes: along +x on the torso at 5 s for 1 s "
     << "while walking at 0.5 m/s, metrics from the push to the end (5 s after it"
     << (o.quick ? "; quick: 2 s" : "") << "). A fall (the daemon damps the robot) ends the "
     << "window. RMS: forward velocity - command; limb error (RMS over the joints of q - the "
     << "plan's q); base height about its mean; roll, pitch against the command; yaw against the "
     << "heading at the start. Ground truth from the simulator.\n\n"
     << "| experiment | variant | paper | ours | v RMS (m/s) | limb RMS (deg) | height RMS (mm) "
        "| roll RMS (deg) | pitch RMS (deg) | yaw RMS (deg) |\n"
     << "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const Run& r : runs) {
    md << "| " << r.experiment.name << " | " << r.variant << " | "
       << paperOutcome(r.variant, r.experiment) << " | " << outcome(r) << " | ";
    if (!r.ok) {
      md << r.error << " | | | | | |\n";
      continue;
    }
    const RunMetrics& m = r.metrics;
    md << fixed(m.velocity, 3) << " | " << fixed(m.limb * kDeg, 2) << " | " << fixed(m.height * 1e3, 1)
       << " | " << fixed(m.roll * kDeg, 2) << " | " << fixed(m.pitch * kDeg, 2) << " | "
       << fixed(m.yaw * kDeg, 2) << " |\n";
  }
  md << "\nSolve times, mean from the walk's start to the end or the fall (wall time on this "
        "machine, ms; they differ from run to run, the table above does not):\n\n"
     << "| experiment | variant | MPC | WBC |\n|---|---|---|---|\n";
  for (const Run& r : runs)
    if (r.ok)
      md << "| " << r.experiment.name << " | " << r.variant << " | " << fixed(r.metrics.mpcMs, 2)
         << " | " << fixed(r.metrics.wbcMs, 3) << " |\n";
  md << "\nFigures: fig3.png (walking at 1.0 m/s, as the paper's Fig. 3), fig5.png (the 40 N push, "
        "as its Fig. 5). The whole study took " << fixed(wallSeconds, 0) << " s of wall time with "
     << o.jobs << " job" << (o.jobs == 1 ? "" : "s") << ".\n";
}

/// The figures' series of a run at 100 Hz: t v_fwd cmd_vx limb_err x y z roll pitch yaw.
bool writeSeries(const Recording& rec, const std::string& path) {
  auto col = [&](const char* name) { return truthOrEstimate(rec, name); };
  const int c[] = {0, col("v_fwd"), rec.column("cmd_vx"), rec.column("limb_err"), col("x"),
                   col("y"), col("z"), col("roll"), col("pitch"), col("yaw")};
  for (int i : c)
    if (i < 0) return false;
  std::ofstream out(path);
  out << "# t\tv_fwd\tcmd_vx\tlimb_err\tx\ty\tz\troll\tpitch\tyaw\n";
  for (std::size_t f = 0; f < rec.frames(); f += 10) {
    for (int k = 0; k < 10; ++k) out << (k ? "\t" : "") << rec.at(f, c[k]);
    out << "\n";
  }
  return true;
}

struct Panel {
  const char* title;
  const char* ylabel;
  int column;    // 1-based in the series file
  double scale;  // to the unit shown
  bool command;  // also the command (cmd_vx)
};

const char* colourOf(const std::string& variant) {
  if (variant == "cH") return "#d62728";   // red, as the paper
  if (variant == "cNH") return "#1f77b4";  // blue
  return "#2ca02c";
}

bool drawFigure(const std::string& png, const std::string& title,
                const std::vector<std::pair<std::string, std::string>>& series,  // variant, file
                const std::vector<Panel>& panels, double from, double to, double shadeFrom,
                double shadeTo, std::string& error) {
  using ballast::cli::gnuplotQuoted;
  std::ostringstream g;
  g << "set terminal pngcairo size 1500,900 enhanced font ',10'\nset output " << gnuplotQuoted(png)
    << "\nset datafile separator '\\t'\nset grid\nset key top right\nset xlabel 't (s)'\n"
    << "set xrange [" << from << ":" << to << "]\n"
    << "set multiplot layout 2,3 title " << gnuplotQuoted(title) << "\n";
  for (const Panel& p : panels) {
    g << "set title " << gnuplotQuoted(p.title) << "\nset ylabel " << gnuplotQuoted(p.ylabel) << "\n";
    if (shadeTo > shadeFrom)
      g << "set object 1 rect from " << shadeFrom << ", graph 0 to " << shadeTo
        << ", graph 1 fc rgb '#eeeeee' fs solid noborder behind\n";
    std::string plot;
    for (const auto& [variant, file] : series) {
      plot += plot.empty() ? "plot " : ", ";
      plot += gnuplotQuoted(file) + " using 1:($" + std::to_string(p.column) + "*" + fixed(p.scale, 6) +
              ") with lines lw 1.5 lc rgb '" + colourOf(variant) + "' title " + gnuplotQuoted(variant);
    }
    if (p.command && !series.empty())
      plot += ", " + gnuplotQuoted(series.front().second) +
              " using 1:3 with lines lw 1.2 dt 2 lc rgb '#2ca02c' title 'command'";
    g << plot << "\nunset object 1\n";
  }
  g << "unset multiplot\n";
  return ballast::cli::runGnuplot(g.str(), error);
}

}  // namespace

int main(int argc, char** argv) {
  Options o = parse(argc, argv);
  const fs::path out = fs::absolute(o.out);
  fs::create_directories(out / "runs");
  fs::create_directories(out / "data");
  fs::create_directories(out / "profiles");
  char scratch[] = "/tmp/ballast-study.XXXXXX";  // sockets: a short path (108 bytes at most)
  if (!::mkdtemp(scratch)) {
    std::perror("ballast-study: mkdtemp");
    return 1;
  }

  // The variants' profiles, with the seed asked for.
  std::map<std::string, std::string> profileOf;
  for (const std::string& v : o.variants) {
    const fs::path p = out / "profiles" / (v + ".yaml");
    std::ofstream f(p);
    f << "# ballast-study: " << v << " as run\nextends: " << fs::absolute(o.profiles + "/" + v + ".yaml").string()
      << "\n";
    if (o.seed >= 0) f << "backend:\n  seed: " << o.seed << "\n";
    profileOf[v] = p.string();
  }
  std::vector<Run> runs;
  for (const Experiment& e : experiments(o.quick))
    for (const std::string& v : o.variants) {
      Run r;
      r.variant = v;
      r.experiment = e;
      r.profile = profileOf[v];
      const std::string name = v + "_" + e.name;
      r.recording = (out / "runs" / (name + ".blog")).string();
      r.log = (out / "runs" / (name + ".log")).string();
      r.socket = std::string(scratch) + "/" + name + ".sock";
      runs.push_back(r);
    }
  std::fprintf(stderr, "ballast-study: %zu runs (%zu variants x %zu experiments), %d at a time, into %s\n",
               runs.size(), o.variants.size(), runs.size() / o.variants.size(), o.jobs, out.c_str());

  const auto t0 = std::chrono::steady_clock::now();
  std::atomic<std::size_t> next{0};
  std::atomic<int> done{0};
  std::mutex print;
  auto worker = [&] {
    for (std::size_t i; (i = next.fetch_add(1)) < runs.size();) {
      Run& r = runs[i];
      const auto start = std::chrono::steady_clock::now();
      try {
        Driver(r).execute(o.ballastd, o.quick);
        Recording rec;
        std::string error;
        if (!ballast::cli::loadRecording(r.recording, rec, error) ||
            !ballast::cli::computeMetrics(rec, windowOf(r.experiment, o.quick), r.metrics, error))
          throw std::runtime_error(error);
        writeSeries(rec, (out / "data" / (r.variant + "_" + r.experiment.name + ".tsv")).string());
        r.ok = true;
      } catch (const std::exception& e) {
        r.error = e.what();
      }
      r.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::lock_guard<std::mutex> lock(print);
      const int k = ++done;
      std::fprintf(stderr, "[%d/%zu] %-4s %-9s %-18s (paper: %s)  %.0f s; %.0f s so far\n", k,
                   runs.size(), r.variant.c_str(), r.experiment.name.c_str(),
                   (r.ok ? outcome(r) : "error: " + r.error).c_str(),
                   paperOutcome(r.variant, r.experiment).c_str(), r.wallSeconds, total);
    }
  };
  std::vector<std::thread> threads;
  for (int j = 0; j < std::min<int>(o.jobs, static_cast<int>(runs.size())); ++j) threads.emplace_back(worker);
  for (auto& t : threads) t.join();
  fs::remove_all(scratch);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  json j = {{"quick", o.quick}, {"seed", o.seed >= 0 ? json(o.seed) : json(nullptr)},
            {"variants", o.variants}, {"wall_seconds", wall}, {"jobs", o.jobs}, {"runs", json::array()}};
  for (const Run& r : runs) j["runs"].push_back(runJson(r, o.quick));
  std::ofstream(out / "study.json") << j.dump(2) << "\n";
  writeMarkdown((out / "study.md").string(), o, runs, wall);

  // Figures: whichever of cH, cNH (and cI) ran, as the paper's (which shows cH and cNH).
  int failures = 0;
  auto figure = [&](const std::string& experiment, const std::string& png, const std::string& title,
                    const std::vector<Panel>& panels, double from, double to, double shadeFrom,
                    double shadeTo) {
    std::vector<std::pair<std::string, std::string>> series;
    for (const Run& r : runs)
      if (r.ok && r.experiment.name == experiment)
        series.emplace_back(r.variant, (out / "data" / (r.variant + "_" + experiment + ".tsv")).string());
    std::string error;
    if (series.empty() || !drawFigure((out / png).string(), title, series, panels, from, to,
                                      shadeFrom, shadeTo, error)) {
      std::fprintf(stderr, "ballast-study: %s not drawn: %s\n", png.c_str(),
                   series.empty() ? ("no run of " + experiment).c_str() : error.c_str());
      ++failures;
    }
  };
  const Experiment walk{"walk_1.0", false, 1.0, 0.0}, push{"push_40N", true, kPushWalk, 40.0};
  figure("walk_1.0", "fig3.png", "Walking at 1.0 m/s (paper Fig. 3)",
         {{"(a) velocity tracking", "forward velocity (m/s)", 2, 1.0, true},
          {"(b) limb tracking error", "RMS joint error (deg)", 4, kDeg, false},
          {"(c) height", "base height (m)", 7, 1.0, false},
          {"(d) roll", "roll (deg)", 8, kDeg, false},
          {"(e) pitch", "pitch (deg)", 9, kDeg, false},
          {"(f) yaw", "yaw (deg)", 10, kDeg, false}},
         kStandUntil, endTime(walk, o.quick), 0.0, 0.0);
  figure("push_40N", "fig5.png", "A 40 N push along x for 1 s, walking at 0.5 m/s (paper Fig. 5)",
         {{"(a) x", "x (m)", 5, 1.0, false},
          {"(b) y", "y (m)", 6, 1.0, false},
          {"(c) height", "base height (m)", 7, 1.0, false},
          {"(d) roll", "roll (deg)", 8, kDeg, false},
          {"(e) pitch", "pitch (deg)", 9, kDeg, false},
          {"(f) yaw", "yaw (deg)", 10, kDeg, false}},
         kStandUntil, endTime(push, o.quick), kPushAt, kPushAt + kPushFor);

  int errors = 0;
  for (const Run& r : runs) errors += r.ok ? 0 : 1;
  std::fprintf(stderr, "ballast-study: %s/study.md, study.json%s in %.0f s%s\n", out.c_str(),
               failures ? "" : ", fig3.png, fig5.png", wall,
               errors ? (" (" + std::to_string(errors) + " runs failed)").c_str() : "");
  return errors || failures ? 1 : 0;
}
