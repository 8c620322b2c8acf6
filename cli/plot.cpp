#include "cli/plot.hpp"

#include <sys/wait.h>

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

bool readTelemetry(const std::string& path, TelemetryTable& t, std::string& error) {
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
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    ++t.rows;
    std::size_t start = 0;
    for (std::size_t c = 0; c < t.columns.size() && start <= line.size(); ++c) {
      std::size_t end = line.find('\t', start);
      if (end == std::string::npos) end = line.size();
      if (!t.has_data[c]) {
        const std::string cell = line.substr(start, end - start);
        char* stop = nullptr;
        const double v = std::strtod(cell.c_str(), &stop);
        t.has_data[c] = stop != cell.c_str() && std::isfinite(v);
      }
      start = end + 1;
    }
  }
  if (t.rows == 0) {
    error = path + " holds no frames: record for a while before `ballast record stop`";
    return false;
  }
  return true;
}

namespace {

struct Series {
  const char* column;
  const char* title;
  const char* style;  // gnuplot line style
  bool degrees;
};

std::string quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

/// One panel: the series that exist and hold data.
void panel(std::ostringstream& g, const TelemetryTable& t, const std::string& data,
           const char* title, const char* ylabel, std::initializer_list<Series> series) {
  g << "set title " << quoted(title) << "\nset ylabel " << quoted(ylabel) << "\n";
  std::string plots;
  for (const Series& s : series) {
    const int c = t.column(s.column);
    if (!c || !t.has_data[c - 1]) continue;
    plots += plots.empty() ? "plot " + quoted(data) : ", ''";
    plots += " using 1:" + (s.degrees ? "($" + std::to_string(c) + "*180/pi)" : std::to_string(c)) +
             " with lines " + s.style + " title " + quoted(s.title);
  }
  if (plots.empty())
    g << "set label 1 'no data in this recording' at graph 0.5,0.5 center\n"
         "plot [0:1][0:1] -1 notitle\nunset label 1\n";
  else
    g << plots << "\n";
}

}  // namespace

std::string plotScript(const TelemetryTable& t, const std::string& data, const std::string& out,
                       const std::string& title) {
  const char* est = "lw 1.5 lc rgb '#d62728'";
  const char* tru = "lw 1.2 lc rgb '#1f77b4'";
  const char* cmd = "lw 1.2 dt 2 lc rgb '#2ca02c'";
  std::ostringstream g;
  g << "set terminal pngcairo size 1500,900 enhanced font ',10'\n"
    << "set output " << quoted(out) << "\n"
    << "set datafile separator '\\t'\nset datafile missing 'NaN'\n"
    << "set grid\nset key top right\nset xlabel 't (s)'\n"
    << "set multiplot layout 2,3 title " << quoted(title) << "\n";
  panel(g, t, data, "(a) velocity tracking", "forward velocity (m/s)",
        {{"v_fwd", "estimate", est, false},
         {"true_v_fwd", "truth", tru, false},
         {"cmd_vx", "command", cmd, false}});
  panel(g, t, data, "(b) limb tracking error", "RMS joint error against the reference (deg)",
        {{"limb_err", "all joints", est, true}});
  panel(g, t, data, "(c) height", "base height (m)",
        {{"z", "estimate", est, false},
         {"true_z", "truth", tru, false},
         {"cmd_height", "command", cmd, false}});
  panel(g, t, data, "(d) roll", "roll (deg)",
        {{"roll", "estimate", est, true},
         {"true_roll", "truth", tru, true},
         {"cmd_roll", "command", cmd, true}});
  panel(g, t, data, "(e) pitch", "pitch (deg)",
        {{"pitch", "estimate", est, true},
         {"true_pitch", "truth", tru, true},
         {"cmd_pitch", "command", cmd, true}});
  panel(g, t, data, "(f) yaw", "yaw (deg)",
        {{"yaw", "estimate", est, true},
         {"true_yaw", "truth", tru, true},
         {"cmd_yaw", "command", cmd, true}});
  g << "unset multiplot\n";
  return g.str();
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
