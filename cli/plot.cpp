#include "cli/plot.hpp"

#include <sys/wait.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

namespace ballast::cli {

int TelemetryTable::column(const std::string& name) const {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == name) return static_cast<int>(i) + 1;
  return 0;
}

bool readTelemetry(const std::string& path, TelemetryTable& t, std::string& error, double from,
                   double to) {
  t = {};
  std::ifstream in(path);
  if (!in) {
    error = "cannot read " + path + ": " + std::strerror(errno);
    return false;
  }
  std::string line;
  if (!std::getline(in, line) || line.rfind("# ballast telemetry", 0) != 0) {
    error = path +
            " is not a ballast telemetry recording (no \"# ballast telemetry\" first line): "
            "record one with `ballast record start FILE`";
    return false;
  }
  if (!std::getline(in, line) || line.rfind("# ", 0) != 0) {
    error = path + ":2: expected the column names after \"# \"";
    return false;
  }
  std::stringstream header(line.substr(2));
  for (std::string c; std::getline(header, c, '\t');) t.columns.push_back(c);
  if (t.column("t") != 1) {
    error = path + ":2: the first column must be t";
    return false;
  }
  t.has_data.assign(t.columns.size(), false);
  t.max.assign(t.columns.size(), -HUGE_VAL);
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    if (line[0] == '#') {
      blog::Group limb;
      if (blog::parseTextLimb(line, limb)) t.limbs.push_back(std::move(limb));
      continue;
    }
    const double time = std::strtod(line.c_str(), nullptr);
    if (!(time >= from && time <= to)) continue;
    ++t.rows;
    std::size_t start = 0;
    for (std::size_t c = 0; c < t.columns.size() && start <= line.size(); ++c) {
      std::size_t end = line.find('\t', start);
      if (end == std::string::npos) end = line.size();
      char* stop = nullptr;
      const double v = std::strtod(line.c_str() + start, &stop);
      if (stop != line.c_str() + start && std::isfinite(v)) {
        t.has_data[c] = true;
        t.max[c] = std::max(t.max[c], v);
      }
      start = end + 1;
    }
  }
  if (t.rows == 0) {
    error = std::isfinite(from) || std::isfinite(to)
                ? "no frame of " + path + " lies in the window"
                : path + " holds no frames: record for a while before `ballast record stop`";
    return false;
  }
  return true;
}

std::string gnuplotQuoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

const Figure* findFigure(const std::string& name) {
  for (const Figure& f : kFigures)
    if (name == f.name) return &f;
  return nullptr;
}

namespace {

/// One line of a panel: a gnuplot expression of columns (@0, @1, ... stand for them).
struct Series {
  std::string title;
  const char* style;
  std::vector<std::string> columns;
  std::string expr = "@0";
};

const char* const kEstimate = "lw 1.5 lc rgb '#d62728'";
const char* const kTruth = "lw 1.2 lc rgb '#1f77b4'";
const char* const kCommand = "lw 1.2 dt 2 lc rgb '#2ca02c'";
const char* const kPalette[] = {"lw 1.2 lc rgb '#1f77b4'", "lw 1.2 lc rgb '#ff7f0e'",
                                "lw 1.2 lc rgb '#2ca02c'", "lw 1.2 lc rgb '#d62728'",
                                "lw 1.2 lc rgb '#9467bd'", "lw 1.2 lc rgb '#8c564b'"};
const char* const kBars[] = {"lc rgb '#1f77b4'", "lc rgb '#ff7f0e'", "lc rgb '#2ca02c'",
                             "lc rgb '#d62728'"};

std::string number(double x) {
  std::ostringstream o;
  o.precision(12);
  o << x;
  return o.str();
}

/// The panels of one figure, written as a gnuplot script.
class Script {
 public:
  Script(const TelemetryTable& t, const std::string& data, const PlotOptions& o, std::size_t every)
      : t_(t), data_(data), every_(every > 1 ? "every " + std::to_string(every) + " " : ""),
        window_("[" + (std::isfinite(o.from) ? number(o.from) : "*") + ":" +
                                    (std::isfinite(o.to) ? number(o.to) : "*") + "]") {
    const bool filter = !o.sliced;
    g_ << "tmin = " << (filter && std::isfinite(o.from) ? number(o.from) : "-1e300")
       << "\ntmax = " << (filter && std::isfinite(o.to) ? number(o.to) : "1e300")
       << "\ninwin(t) = t >= tmin && t <= tmax\nbin(x, w) = w * floor(x / w) + w / 2\n";
  }

  /// The series' expression with its columns' numbers; "" if one is absent or holds no data.
  std::string expression(const Series& s) const {
    std::string out;
    for (std::size_t i = 0; i < s.expr.size(); ++i) {
      if (s.expr[i] != '@' || i + 1 == s.expr.size() || !std::isdigit(s.expr[i + 1])) {
        out += s.expr[i];
        continue;
      }
      const std::size_t k = std::size_t(s.expr[++i] - '0');
      const int c = k < s.columns.size() ? t_.column(s.columns[k]) : 0;
      if (!c || !t_.has_data[c - 1]) return "";
      out += "$" + std::to_string(c);
    }
    return "(" + out + ")";
  }

  /// A panel over time: each series that has data, in the window. gnuplot draws a line across
  /// a NaN, so a series that has gaps (a ratio in swing) takes points.
  void lines(const std::string& title, const std::string& ylabel,
             const std::vector<Series>& series, const char* with = "with lines") {
    start(title, ylabel);
    g_ << "set xlabel 't (s)'\nset xrange " << window_ << "\n";
    plot(series, [](const std::string& e) { return "1:" + e; }, with, every_);
  }

  /// A histogram of the series' values in the window, bins of width w, counts on a log scale.
  void histogram(const std::string& title, const std::string& xlabel, double w,
                 const std::vector<Series>& series) {
    start(title, "frames");
    // From under one frame up: one full bin (lockstep's lateness, all 0) is still a range.
    g_ << "set xlabel " << gnuplotQuoted(xlabel)
       << "\nset xrange [*:*]\nset logscale y\nset yrange [0.8:*]\n"
       << "set style fill solid 0.4 border\nset boxwidth " << number(w) << " absolute\n";
    const std::string width = number(w);
    plot(
        series, [&](const std::string& e) { return "(inwin($1) ? bin(" + e + ", " + width + ") : NaN):(1)"; },
        "smooth frequency with boxes", "");
    g_ << "unset logscale y\n";
  }

  /// Bars where each flag is set, one row per flag (a Gantt chart), over time.
  void schedule(const std::string& title, const std::vector<std::string>& flags,
                const std::vector<std::string>& labels) {
    start(title, "");
    g_ << "set xlabel 't (s)'\nset xrange " << window_ << "\nset yrange [-0.5:"
       << flags.size() - 0.5 << "]\nset ytics (";
    std::vector<Series> series;
    for (std::size_t i = 0; i < flags.size(); ++i) {
      g_ << (i ? ", " : "") << gnuplotQuoted(labels[i]) << " " << i;
      series.push_back({"", kBars[i % 4], {flags[i]}, "@0 > 0.5 ? " + std::to_string(i) + " : NaN"});
    }
    g_ << ")\n";
    plot(series, [](const std::string& e) { return "1:" + e; }, "with points pt 5 ps 0.6", every_);
    g_ << "set ytics autofreq\n";
  }

  std::string text() const { return g_.str(); }
  std::ostringstream& out() { return g_; }

 private:
  void start(const std::string& title, const std::string& ylabel) {
    g_ << "set title " << gnuplotQuoted(title) << "\nset ylabel " << gnuplotQuoted(ylabel)
       << "\nset autoscale y\n";
  }

  template <typename Using>
  void plot(const std::vector<Series>& series, Using using_, const char* with,
            const std::string& every) {
    std::string plots;
    for (const Series& s : series) {
      const std::string e = expression(s);
      if (e.empty()) continue;
      plots += plots.empty() ? "plot " + gnuplotQuoted(data_) : ", ''";
      plots += " " + every + "using " + using_(e) + " " + with + " " + s.style +
               (s.title.empty() ? " notitle" : " title " + gnuplotQuoted(s.title));
    }
    if (plots.empty())
      g_ << "set label 1 'no data in this recording' at graph 0.5,0.5 center\n"
            "plot [0:1][0:1] -1 notitle\nunset label 1\n";
    else
      g_ << plots << "\n";
  }

  const TelemetryTable& t_;
  std::string data_, every_, window_;
  std::ostringstream g_;
};

/// The estimate, the ground truth and the command of one quantity; in degrees if degrees.
std::vector<Series> tracked(const std::string& name, const std::string& command, bool degrees) {
  const std::string e = degrees ? "@0*180/pi" : "@0";
  return {{"estimate", kEstimate, {name}, e},
          {"truth", kTruth, {"true_" + name}, e},
          {"command", kCommand, {command}, e}};
}

void fig3(Script& s) {
  s.lines("(a) velocity tracking", "forward velocity (m/s)", tracked("v_fwd", "cmd_vx", false));
  s.lines("(b) limb tracking error", "RMS joint error against the reference (deg)",
          {{"all joints", kEstimate, {"limb_err"}, "@0*180/pi"}});
  s.lines("(c) height", "base height (m)", tracked("z", "cmd_height", false));
  s.lines("(d) roll", "roll (deg)", tracked("roll", "cmd_roll", true));
  s.lines("(e) pitch", "pitch (deg)", tracked("pitch", "cmd_pitch", true));
  s.lines("(f) yaw", "yaw (deg)", tracked("yaw", "cmd_yaw", true));
}

void fig6(Script& s) {
  s.lines("(a) height", "base height (m)", tracked("z", "cmd_height", false));
  s.lines("(b) yaw", "yaw (deg)", tracked("yaw", "cmd_yaw", true));
  s.lines("(c) pitch", "pitch (deg)", tracked("pitch", "cmd_pitch", true));
  s.lines("(d) roll", "roll (deg)", tracked("roll", "cmd_roll", true));
}

void contacts(Script& s) {
  // Contact points 0..3: left toe, left heel, right toe, right heel (model/contact_points.hpp).
  for (int foot = 0; foot < 2; ++foot) {
    const std::string toe = std::to_string(2 * foot), heel = std::to_string(2 * foot + 1);
    s.lines(foot == 0 ? "(a) left foot: normal force" : "(b) right foot: normal force", "N",
            {{"toe", kPalette[0], {"fz_" + toe}},
             {"heel", kPalette[1], {"fz_" + heel}},
             {"foot", kEstimate, {"fz_" + toe, "fz_" + heel}, "@0 + @1"}});
  }
  // The plan's schedule above the estimator's, point by point: a late or early touchdown shows
  // as the two rows disagreeing.
  std::vector<std::string> flags, labels;
  const char* const points[] = {"left toe", "left heel", "right toe", "right heel"};
  for (int c = 0; c < 4; ++c) {
    flags.push_back("contact_" + std::to_string(c));
    labels.push_back(points[c]);
    flags.push_back("planned_" + std::to_string(c));
    labels.push_back(std::string(points[c]) + " (plan)");
  }
  s.schedule("(c) contact schedule: plan and estimator", flags, labels);
  std::vector<Series> friction;
  for (int foot = 0; foot < 2; ++foot) {
    const std::string a = std::to_string(2 * foot), b = std::to_string(2 * foot + 1);
    friction.push_back({foot == 0 ? "left foot" : "right foot", kBars[foot],
                        {"fx_" + a, "fx_" + b, "fy_" + a, "fy_" + b, "fz_" + a, "fz_" + b},
                        "sqrt((@0 + @1)**2 + (@2 + @3)**2) / (@4 + @5 > 1 ? @4 + @5 : NaN)"});
  }
  s.lines("(d) friction used: |f_t| / f_z per foot", "", friction, "with points pt 7 ps 0.2");
}

void timing(Script& s, const TelemetryTable& t) {
  auto width = [&](std::initializer_list<const char*> names) {
    double top = 0.0;
    for (const char* n : names)
      if (const int c = t.column(n)) top = std::max(top, t.max[c - 1]);
    return std::max(top / 60.0, 1e-3);  // 60 bins, none under the resolution (1 µs)
  };
  s.lines("(a) solve times", "ms",
          {{"MPC", kPalette[0], {"mpc_ms"}}, {"WBC", kPalette[1], {"wbc_ms"}}});
  s.lines("(b) tick work and lateness", "ms",
          {{"tick work", kPalette[2], {"tick_ms"}}, {"lateness", kEstimate, {"lateness_ms"}}});
  s.histogram("(c) tick lateness", "lateness (ms)", width({"lateness_ms"}),
              {{"lateness", kEstimate, {"lateness_ms"}}});
  s.histogram("(d) solve times", "ms", width({"mpc_ms", "wbc_ms"}),
              {{"MPC", kPalette[0], {"mpc_ms"}}, {"WBC", kPalette[1], {"wbc_ms"}}});
}

/// The limbs of the recording, or (one from before limbs were recorded) its joints six at a time.
std::vector<blog::Group> limbsOf(const TelemetryTable& t) {
  if (!t.limbs.empty()) return t.limbs;
  std::vector<std::string> joints;
  for (const std::string& c : t.columns)
    if (c.rfind("q_", 0) == 0) joints.push_back(c.substr(2));
  std::vector<blog::Group> out;
  for (std::size_t first = 0; first < joints.size(); first += 6) {
    const std::size_t last = std::min(first + 6, joints.size());
    out.push_back({"joints " + std::to_string(first + 1) + "-" + std::to_string(last),
                   {joints.begin() + first, joints.begin() + last}});
  }
  return out;
}

void joints(Script& s, const std::vector<blog::Group>& limbs) {
  for (std::size_t l = 0; l < limbs.size(); ++l) {
    std::vector<Series> series;
    for (std::size_t j = 0; j < limbs[l].members.size(); ++j) {
      const std::string& joint = limbs[l].members[j];
      series.push_back({joint, kPalette[j % 6], {"q_" + joint, "qref_" + joint}, "(@0 - @1)*180/pi"});
    }
    s.lines(std::string("(") + char('a' + l % 26) + ") " + limbs[l].name, "q - qref (deg)", series);
  }
}

}  // namespace

std::string plotScript(const TelemetryTable& t, const std::string& data, const std::string& out,
                       const PlotOptions& o) {
  const std::string name = o.figure->name;
  const std::vector<blog::Group> limbs = name == "joints" ? limbsOf(t) : std::vector<blog::Group>{};
  const std::size_t panels = name == "fig3" ? 6 : name == "joints" ? std::max<std::size_t>(limbs.size(), 1) : 4;
  const std::size_t cols = panels == 6 ? 3 : panels == 1 ? 1 : 2, rows = (panels + cols - 1) / cols;
  // A time panel of more frames than its pixels can show draws every Nth: a 10-minute
  // recording's joints took gnuplot 200 s, and a window shows every frame. The histograms count
  // every frame, and the timing figure, whose single late ticks matter, draws them all.
  constexpr std::size_t kMaxPoints = 50000;
  const std::size_t every =
      name != "timing" && t.rows > kMaxPoints ? (t.rows + kMaxPoints - 1) / kMaxPoints : 1;
  const std::string title =
      every > 1 ? o.title + " (1 frame in " + std::to_string(every) + " drawn)" : o.title;
  Script s(t, data, o, every);
  s.out() << "set terminal pngcairo size 1500," << 450 * rows << " noenhanced font ',10'\n"
          << "set output " << gnuplotQuoted(out) << "\n"
          << "set datafile separator '\\t'\nset datafile missing 'NaN'\n"
          << "set grid\nset key top right\n"
          << "set multiplot layout " << rows << "," << cols << " title " << gnuplotQuoted(title)
          << "\n";
  if (name == "fig3") fig3(s);
  else if (name == "fig6") fig6(s);
  else if (name == "contacts") contacts(s);
  else if (name == "timing") timing(s, t);
  else if (limbs.empty()) s.lines("(a) joints", "q - qref (deg)", {});
  else joints(s, limbs);
  s.out() << "unset multiplot\n";
  return s.text();
}

bool runGnuplot(const std::string& script, std::string& error) {
  const char* env = std::getenv("BALLAST_GNUPLOT");
  const std::string program = env && *env ? env : "gnuplot";
  std::FILE* pipe = ::popen((program + " -").c_str(), "w");
  if (!pipe) {
    error = "cannot run " + program + ": " + std::strerror(errno);
    return false;
  }
  std::fwrite(script.data(), 1, script.size(), pipe);
  const int status = ::pclose(pipe);
  if (status == -1 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    error =
        WIFEXITED(status) && WEXITSTATUS(status) == 127
            ? program + " not found: install gnuplot (Debian: gnuplot-nox), or set BALLAST_GNUPLOT"
            : program + " failed (its messages are above)";
    return false;
  }
  return true;
}

}  // namespace ballast::cli
