// ballast-push-map: the largest push (N, for 1 s) the robot survives, per direction and gait
// phase, standing and walking (issue 13), measured in lockstep simulations of ballastd's control
// core (DaemonStack: the profile, the Simbody backend, the MPC planner and the control loop, on
// the state estimate), a fresh robot per trial, several trials in parallel processes.
//
// Per cell (speed, direction, phase) the forces on a grid (--step N up to --max N) are searched
// by bisection from a first guess (--guess): a trial survives when the robot neither falls nor is
// damped within --after s of the push's end (standing: and is back in `stand` by then). The
// cell's figure is the largest force survived below the smallest one that was not.
//
// Output: a table per speed on the terminal and in DIR/push_map.txt, the raw cells in
// DIR/push_map.dat, and DIR/push_map.png: gnuplot polar plots, one per speed, the radius the
// largest survived force per direction (the smallest over phases as a line, each phase a point).
//
// --trace: one trial (--speed, --direction, --phase, --force), its state every 20 ms
// (--trace-period S: every S, down to a tick).
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "test/integration/daemon_stack/daemon_stack.hpp"
#include "test/integration/daemon_stack/push_trial.hpp"

namespace {

using ballast::test::PushTrial;
using ballast::test::PushOutcome;

struct Options {
  std::string profile = ballast::test::kDefaultProfile;
  std::vector<double> speeds{0.0, 0.5, 1.0};
  int directions = 8;
  std::vector<double> angles;  ///< --angles: these directions (deg) instead of --directions
  int phases = 8;
  double step = 10.0, max = 150.0, guess = 60.0;
  double duration = 1.0, after = 4.0;
  std::string body = "torso";
  int jobs = 0;
  std::string out = "push-map";
  bool trace = false;
  double tracePeriod = 0.02;
  bool unpushed = false;  ///< no pushes: the estimated push walking undisturbed, per speed
  double speed = 0.5, direction = 0.0, phase = 0.0, force = 60.0;
  double yawRate = 0.0;      ///< --yaw-rate: rad/s, every walking trial turns at it
  double standBefore = 1.0;  ///< --stand-before: standing, s from 0.5 s after stand to the push
};

[[noreturn]] void usage(const char* why) {
  if (why) std::fprintf(stderr, "ballast-push-map: %s\n", why);
  std::fprintf(stderr,
               "usage: ballast-push-map [--profile FILE] [--speeds 0,0.5,1.0] [--directions 8]\n"
               "         [--angles DEG,DEG...]\n"
               "         [--phases 8] [--step 10] [--max 150] [--guess 60] [--duration 1]\n"
               "         [--after 4] [--body torso] [--yaw-rate 0] [--stand-before 1]\n"
               "         [-j JOBS] [--out DIR]\n"
               "       ballast-push-map --unpushed [--profile FILE] [--speeds 0.5,1.0,1.2,1.5]\n"
               "       ballast-push-map --trace [--profile FILE] --speed V --direction DEG\n"
               "         --phase FRACTION --force N [--duration 1] [--after 4] [--body LINK]\n"
               "         [--yaw-rate 0]\n"
               "         [--trace-period 0.02]\n"
               "         [--stand-before 1] (standing: s from 0.5 s after stand to the push)\n");
  std::exit(2);
}

std::vector<double> numberList(const std::string& text) {
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) out.push_back(std::atof(item.c_str()));
  return out;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage(("missing value after " + a).c_str());
      return argv[++i];
    };
    if (a == "--profile") o.profile = value();
    else if (a == "--speeds") o.speeds = numberList(value());
    else if (a == "--directions") o.directions = std::atoi(value().c_str());
    else if (a == "--angles") o.angles = numberList(value());
    else if (a == "--phases") o.phases = std::atoi(value().c_str());
    else if (a == "--step") o.step = std::atof(value().c_str());
    else if (a == "--max") o.max = std::atof(value().c_str());
    else if (a == "--guess") o.guess = std::atof(value().c_str());
    else if (a == "--duration") o.duration = std::atof(value().c_str());
    else if (a == "--after") o.after = std::atof(value().c_str());
    else if (a == "--trace-period")
      o.tracePeriod = std::atof(value().c_str());
    else if (a == "--body") o.body = value();
    else if (a == "-j" || a == "--jobs") o.jobs = std::atoi(value().c_str());
    else if (a == "--out") o.out = value();
    else if (a == "--trace") o.trace = true;
    else if (a == "--unpushed") o.unpushed = true;
    else if (a == "--speed") o.speed = std::atof(value().c_str());
    else if (a == "--direction") o.direction = std::atof(value().c_str());
    else if (a == "--phase") o.phase = std::atof(value().c_str());
    else if (a == "--force") o.force = std::atof(value().c_str());
    else if (a == "--yaw-rate")
      o.yawRate = std::atof(value().c_str());
    else if (a == "--stand-before") o.standBefore = std::atof(value().c_str());
    else if (a == "-h" || a == "--help") usage(nullptr);
    else usage(("unknown argument " + a).c_str());
  }
  if (o.directions < 1 || o.phases < 1 || o.step <= 0.0 || o.max < o.step) usage("bad grid");
  if (!(o.tracePeriod >= 0.001 && o.tracePeriod <= 1.0)) usage("--trace-period: 0.001 to 1 s");
  if (o.angles.empty())
    for (int d = 0; d < o.directions; ++d) o.angles.push_back(360.0 * d / o.directions);
  if (o.jobs <= 0) o.jobs = std::max(1L, sysconf(_SC_NPROCESSORS_ONLN));
  return o;
}

/// One cell of the map: bisection over force indices 1..n (force = index · step).
struct Cell {
  double speed = 0.0, direction = 0.0, phase = 0.0;
  int lo = 0;      // largest index survived (0: none tried or none survived)
  int hi = 0;      // smallest index failed (n + 1: none failed)
  int pending = 0; // index being tried, 0 when none
  int trials = 0;
  bool done() const { return hi - lo <= 1; }
};

struct Running {
  pid_t pid;
  int fd;
  std::size_t cell;
  int index;
};

std::string directionName(double deg) {
  static const char* names[] = {"+x", "+x+y", "+y", "-x+y", "-x", "-x-y", "-y", "+x-y"};
  const double k = deg / 45.0;
  if (std::abs(k - std::round(k)) < 1e-9) return names[static_cast<int>(std::lround(k)) % 8];
  char b[32];
  std::snprintf(b, sizeof b, "%g deg", deg);
  return b;
}

PushTrial trialFor(const Options& o, const Cell& c, double force) {
  PushTrial t;
  t.profile = o.profile;
  t.speed = c.speed;
  t.directionDeg = c.direction;
  t.phase = c.phase;
  t.force = force;
  t.duration = o.duration;
  t.after = o.after;
  t.body = o.body;
  t.yawRate = o.yawRate;
  t.standBefore = o.standBefore;
  return t;
}

int trace(const Options& o) {
  Cell c;
  c.speed = o.speed;
  c.direction = o.direction;
  c.phase = o.phase;
  PushTrial t = trialFor(o, c, o.force);
  t.trace = stdout;
  t.tracePeriod = o.tracePeriod;
  const PushOutcome r = ballast::test::runPushTrial(t);
  std::printf("%s: %s\n", r.survived ? "survived" : "FELL", r.message.c_str());
  return r.survived ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  if (o.trace) return trace(o);
  if (o.unpushed) {
    // The largest horizontal push the estimator reads walking with none (3 s to reach the
    // speed, 5 s watched): what gait.recovery_walking_force must stay above.
    std::printf("speed m/s   raw N   past the deadband N   push switch N\n");
    for (double v : o.speeds) {
      if (v == 0.0) continue;
      const ballast::test::UnpushedPeak p = ballast::test::unpushedPeak(o.profile, v, 3.0, 5.0);
      std::printf("%8.2f  %6.1f  %20.1f  %14.1f%s\n", v, p.raw, p.reported, p.pushSwitch,
                  p.walked ? "" : "  (fell)");
      std::fflush(stdout);
    }
    return 0;
  }

  const int n = static_cast<int>(std::floor(o.max / o.step + 1e-9));
  const int guess = std::clamp(static_cast<int>(std::lround(o.guess / o.step)), 1, n);
  std::vector<Cell> cells;
  for (double v : o.speeds)
    for (double deg : o.angles)
      for (int p = 0; p < (v == 0.0 ? 1 : o.phases); ++p) {
        Cell c;
        c.speed = v;
        c.direction = deg;
        c.phase = v == 0.0 ? 0.0 : static_cast<double>(p) / o.phases;
        c.hi = n + 1;
        cells.push_back(c);
      }
  const int estimate = static_cast<int>(cells.size()) *
                       (1 + static_cast<int>(std::ceil(std::log2(static_cast<double>(n)))));
  std::fprintf(stderr, "ballast-push-map: %zu cells, about %d trials, %d at a time\n",
               cells.size(), estimate, o.jobs);

  const auto start = std::chrono::steady_clock::now();
  std::vector<Running> running;
  std::size_t next = 0;  // cells are started in order; each runs its trials one at a time
  int finishedTrials = 0;
  auto nextIndex = [&](const Cell& c) {
    if (c.trials == 0) return guess;
    return (c.lo + c.hi) / 2;
  };
  auto launch = [&](std::size_t ci) {
    Cell& c = cells[ci];
    const int index = nextIndex(c);
    c.pending = index;
    int fds[2];
    if (pipe(fds) != 0) throw std::runtime_error("pipe failed");
    std::fflush(nullptr);
    const pid_t pid = fork();
    if (pid < 0) throw std::runtime_error("fork failed");
    if (pid == 0) {
      close(fds[0]);
      PushOutcome r;
      try {
        r = ballast::test::runPushTrial(trialFor(o, c, index * o.step));
      } catch (const std::exception& e) {
        r.survived = false;
        r.message = std::string("error: ") + e.what();
      }
      const std::string line = (r.survived ? "1 " : "0 ") + r.message + "\n";
      [[maybe_unused]] ssize_t w = write(fds[1], line.data(), line.size());
      _exit(0);
    }
    close(fds[1]);
    running.push_back(Running{pid, fds[0], ci, index});
  };
  // Pick work: a cell with a trial to run and none running.
  auto schedule = [&]() {
    while (static_cast<int>(running.size()) < o.jobs) {
      std::size_t pick = cells.size();
      for (std::size_t i = 0; i < next && pick == cells.size(); ++i)
        if (!cells[i].done() && cells[i].pending == 0) pick = i;
      if (pick == cells.size() && next < cells.size()) pick = next++;
      if (pick == cells.size()) return;
      launch(pick);
    }
  };
  schedule();
  while (!running.empty()) {
    int status = 0;
    const pid_t pid = wait(&status);
    if (pid < 0) break;
    auto it = std::find_if(running.begin(), running.end(), [&](const Running& r) { return r.pid == pid; });
    if (it == running.end()) continue;
    std::string text;
    char buf[512];
    ssize_t k;
    while ((k = read(it->fd, buf, sizeof buf)) > 0) text.append(buf, static_cast<std::size_t>(k));
    close(it->fd);
    Cell& c = cells[it->cell];
    const bool ok = !text.empty() && text[0] == '1';
    ++c.trials;
    c.pending = 0;
    if (ok) c.lo = std::max(c.lo, it->index);
    else c.hi = std::min(c.hi, it->index);
    ++finishedTrials;
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    int doneCells = 0;
    for (const Cell& x : cells) doneCells += x.done();
    std::fprintf(stderr, "[%3d/%zu cells, %4d trials, %5.0f s] v %.1f %-5s phase %.3f: %5.0f N %s%s",
                 doneCells, cells.size(), finishedTrials, elapsed, c.speed,
                 directionName(c.direction).c_str(), c.phase, it->index * o.step,
                 ok ? "survived" : "FELL", text.size() > 2 ? (" (" + text.substr(2, text.size() - 3) + ")\n").c_str() : "\n");
    running.erase(it);
    schedule();
  }

  // Report.
  if (system(("mkdir -p '" + o.out + "'").c_str()) != 0) {
    std::fprintf(stderr, "cannot create %s\n", o.out.c_str());
    return 1;
  }
  std::ostringstream table;
  for (double v : o.speeds) {
    const int phases = v == 0.0 ? 1 : o.phases;
    table << (v == 0.0 ? std::string("standing")
                       : "walking at " + std::to_string(v).substr(0, 4) + " m/s")
          << (v != 0.0 && o.yawRate != 0.0
                  ? ", turning at " + std::to_string(o.yawRate).substr(0, 5) + " rad/s"
                  : "")
          << ": largest survived push (N, " << o.duration << " s, on " << o.body << "; grid "
          << o.step << " N up to " << o.max << " N)\n";
    table << "  direction";
    for (int p = 0; p < phases; ++p) {
      char b[32];
      if (phases == 1) std::snprintf(b, sizeof b, "     ");
      else std::snprintf(b, sizeof b, "  %4.2f", static_cast<double>(p) / phases);
      table << b;
    }
    table << "    min\n";
    for (double deg : o.angles) {
      char b[64];
      std::snprintf(b, sizeof b, "  %-9s", directionName(deg).c_str());
      table << b;
      double lowest = 1e9;
      for (const Cell& c : cells)
        if (c.speed == v && c.direction == deg) {
          const double f = c.lo * o.step;
          lowest = std::min(lowest, f);
          std::snprintf(b, sizeof b, "  %4.0f%s", f, c.hi > n ? "+" : " ");
          table << b;
        }
      std::snprintf(b, sizeof b, "  %5.0f\n", lowest);
      table << b;
    }
    table << "\n";
  }
  std::printf("%s", table.str().c_str());
  FILE* f = std::fopen((o.out + "/push_map.txt").c_str(), "w");
  if (f) {
    std::fprintf(f, "%s", table.str().c_str());
    std::fclose(f);
  }
  f = std::fopen((o.out + "/push_map.dat").c_str(), "w");
  if (f) {
    std::fprintf(f, "# speed_m_s direction_deg phase force_survived_N trials\n");
    for (const Cell& c : cells)
      std::fprintf(f, "%g %g %g %g %d\n", c.speed, c.direction, c.phase, c.lo * o.step, c.trials);
    std::fclose(f);
  }
  // Polar plots: per speed the per-phase points and the minimum over phases, closed curves.
  f = std::fopen((o.out + "/push_map.gp").c_str(), "w");
  if (f) {
    const int panels = static_cast<int>(o.speeds.size());
    std::fprintf(f, "set terminal pngcairo size %d,520 font ',10'\nset output '%s/push_map.png'\n",
                 460 * panels, o.out.c_str());
    std::fprintf(f, "set multiplot layout 1,%d title 'largest survived push, %g s on %s (N)'\n",
                 panels, o.duration, o.body.c_str());
    std::fprintf(f,
                 "set polar\nset angles degrees\nset size square\nset grid polar 45\nunset border\n"
                 "unset xtics\nunset ytics\nset rrange [0:%g]\nset rtics %g\nset ttics 0,45\n"
                 "set key bottom right\n",
                 o.max, o.max / 3.0 > 20 ? std::round(o.max / 3.0 / 10.0) * 10.0 : o.max / 3.0);
    for (double v : o.speeds) {
      const std::string label = v == 0.0 ? "standing" : "walking " + std::to_string(v).substr(0, 3) + " m/s";
      std::fprintf(f, "set title '%s'\n", label.c_str());
      std::fprintf(f, "$min%d << EOD\n", static_cast<int>(std::lround(v * 100)));
      const int na = static_cast<int>(o.angles.size());
      for (int d = 0; d <= na; ++d) {
        const double deg = o.angles[d % na];
        double lowest = 1e9;
        for (const Cell& c : cells)
          if (c.speed == v && c.direction == deg) lowest = std::min(lowest, c.lo * o.step);
        std::fprintf(f, "%g %g\n", deg, lowest);
      }
      std::fprintf(f, "EOD\n");
      std::fprintf(f,
                   "plot '%s/push_map.dat' using ($1==%g ? $2 : 1/0):4 with points pt 7 ps 0.6 "
                   "lc rgb '#8080c0' title 'each phase', $min%d using 1:2 with lines lw 2 "
                   "lc rgb '#c03030' title 'every phase', 60 with lines dt 2 lc rgb '#309030' "
                   "title 'paper: 60 N'\n",
                   o.out.c_str(), v, static_cast<int>(std::lround(v * 100)));
    }
    std::fprintf(f, "unset multiplot\n");
    std::fclose(f);
    if (system(("gnuplot '" + o.out + "/push_map.gp'").c_str()) != 0)
      std::fprintf(stderr, "gnuplot failed; the script is %s/push_map.gp\n", o.out.c_str());
    else
      std::fprintf(stderr, "wrote %s/push_map.{txt,dat,png}\n", o.out.c_str());
  }
  return 0;
}
