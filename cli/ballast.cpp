// ballast: the operator console for ballastd (ballast(1)). It speaks only the protocol
// (daemon/server/protocol.hpp): each verb is one request, its reply printed for people, or as
// JSON with --json. Exit status: 0 done, 1 refused (the reply says why and what to do next),
// 2 usage, 3 no daemon to talk to.
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/client.hpp"
#include "blog/blog.hpp"
#include "cli/plot.hpp"
#include "cli/status_view.hpp"
#include "cli/units.hpp"
#include "cli/verbs.hpp"
#include "server/protocol.hpp"

using nlohmann::json;
namespace fs = std::filesystem;
using namespace ballast;

namespace {

enum Exit { kOk = 0, kRefused = 1, kUsage = 2, kNoDaemon = 3 };

std::atomic<bool> interrupted{false};

/// JSON for stdout; invalid UTF-8 from the daemon is replaced, never thrown on.
std::string text(const json& j) {
  return j.dump(-1, ' ', false, json::error_handler_t::replace);
}

struct Options {
  std::string socket, lease_file;
  bool json = false;
  double timeout = 10.0;
};

/// A refusal the CLI itself reports (or passes on): JSON on stdout with --json, else a line on
/// stderr. Returns kRefused.
int refuse(const Options& o, const std::string& code, const std::string& message) {
  if (o.json)
    std::cout << text(json{{"ok", false}, {"error", {{"code", code}, {"message", message}}}})
              << "\n";
  else
    std::fprintf(stderr, "ballast: %s\n", message.c_str());
  return kRefused;
}

int usage(const std::string& message) {
  std::fprintf(stderr, "ballast: %s (see `ballast --help` or ballast(1))\n", message.c_str());
  return kUsage;
}

/// A session with the daemon: the connection, the lease token, and printing.
class Session {
 public:
  explicit Session(const Options& o)
      : opt_(o),
        socket_(cli::socketPath(o.socket)),
        lease_path_(cli::leaseFile(o.lease_file, socket_)) {}

  int connect() {
    std::string error;
    if (conn_.open(socket_, error)) return kOk;
    return noDaemon(error);
  }

  int noDaemon(const std::string& error) {
    if (opt_.json)
      std::cout << text(json{{"ok", false}, {"error", {{"code", "no_daemon"}, {"message", error}}}})
                << "\n";
    else
      std::fprintf(stderr, "ballast: %s\n", error.c_str());
    return kNoDaemon;
  }

  /// One request; motion commands carry the lease token and take the lease when it is free.
  /// Returns the exit status; reply holds the daemon's answer when it came.
  int call(json request, json& reply) {
    const protocol::Command* spec = protocol::findCommand(request["cmd"].get<std::string>());
    const bool motion = spec && spec->needs_lease;
    if (motion || request["cmd"] == "lease_acquire" || request["cmd"] == "lease_return") {
      if (const std::string token = readToken(); !token.empty()) request["lease"] = token;
    }
    std::string error;
    if (!conn_.request(request, reply, error, opt_.timeout)) return noDaemon(error);
    if (motion && !reply.value("ok", false) && errorCode(reply) == protocol::kNoLease) {
      json lease;
      if (!conn_.request({{"cmd", "lease_acquire"}}, lease, error, opt_.timeout))
        return noDaemon(error);
      if (!lease.value("ok", false)) {
        reply = lease;
        return kRefused;
      }
      saveToken(lease["lease"].get<std::string>());
      request["lease"] = lease["lease"];
      if (!conn_.request(request, reply, error, opt_.timeout)) return noDaemon(error);
    }
    return reply.value("ok", false) ? kOk : kRefused;
  }

  /// Runs a request and prints the outcome: JSON, or `human(reply)` on success and the
  /// daemon's message on refusal.
  template <typename Human>
  int run(json request, Human human, json* out = nullptr) {
    if (const int c = connect(); c != kOk) return c;
    json reply;
    const int code = call(std::move(request), reply);
    if (out) *out = reply;
    if (code == kNoDaemon) return code;
    if (opt_.json) {
      std::cout << text(reply) << "\n";
    } else if (code == kOk) {
      human(reply);
    } else {
      std::fprintf(stderr, "ballast: %s: %s\n", errorCode(reply).c_str(),
                   reply["error"].value("message", "").c_str());
    }
    return code;
  }

  static std::string errorCode(const json& reply) {
    return reply.contains("error") ? reply["error"].value("code", "") : "";
  }

  std::string readToken() const {
    std::ifstream in(lease_path_);
    std::string token;
    std::getline(in, token);
    return token;
  }
  void saveToken(const std::string& token) const {
    std::error_code ec;
    fs::create_directories(fs::path(lease_path_).parent_path(), ec);
    ::chmod(fs::path(lease_path_).parent_path().c_str(), 0700);
    const mode_t old = ::umask(0077);
    std::ofstream(lease_path_) << token << "\n";
    ::umask(old);
  }
  void forgetToken() const { std::remove(lease_path_.c_str()); }
  const std::string& leasePath() const { return lease_path_; }
  cli::Connection& connection() { return conn_; }

 private:
  const Options& opt_;
  std::string socket_, lease_path_;
  cli::Connection conn_;
};

void printMode(const std::string& verb, const json& r) {
  std::printf("%s: ok, mode %s%s%s\n", verb.c_str(), r.value("mode", "?").c_str(),
              r.contains("message") ? "; " : "", r.value("message", "").c_str());
}

int watch(Session& s, const Options& o, double rate, bool joints, int count) {
  if (const int c = s.connect(); c != kOk) return c;
  json reply;
  const int code = s.call({{"cmd", "watch"}, {"rate", rate}, {"joints", joints}}, reply);
  if (code != kOk)
    return code == kRefused ? refuse(o, Session::errorCode(reply), reply["error"].value("message", ""))
                            : code;
  signal(SIGINT, [](int) { interrupted = true; });
  const bool tty = ::isatty(STDOUT_FILENO) && !o.json;
  for (int n = 0; !interrupted && (count <= 0 || n < count);) {
    json line;
    std::string error;
    if (!s.connection().readLine(line, error, 200)) {
      if (!error.empty()) return s.noDaemon(error);
      continue;
    }
    if (!line.contains("event")) continue;
    ++n;
    if (o.json) {
      std::cout << text(line["status"]) << std::endl;
    } else {
      if (tty) std::printf("\033[H\033[2J");
      std::printf("%s", cli::renderStatus(line["status"]).c_str());
      if (tty) std::printf("\n(ballast status --watch: Ctrl-C to quit)\n");
      std::fflush(stdout);
    }
  }
  return kOk;
}

struct PlotRequest {
  std::string file, out, title, figure = "fig3", from, to;
};

/// `ballast plot FILE -o OUT.png [--fig NAME] [--from T] [--to T] [--title TEXT]`: a text
/// recording as it is, a .blog through a TSV of the figure's columns in the window.
int plot(const PlotRequest& r, const Options& o) {
  cli::PlotOptions p;
  p.figure = cli::findFigure(r.figure);
  if (!p.figure) {
    std::string names;
    for (const auto& f : cli::kFigures) names += std::string(names.empty() ? "" : ", ") + f.name;
    return usage("--fig: no figure '" + r.figure + "' (" + names + ")");
  }
  std::string error;
  if (!r.from.empty() && !cli::parseTime(r.from, p.from, error)) return usage("--from: " + error);
  if (!r.to.empty() && !cli::parseTime(r.to, p.to, error)) return usage("--to: " + error);
  if (p.from > p.to) return usage("ballast plot: --from is after --to");
  p.title = !r.title.empty() ? r.title
                             : "ballast: " + fs::path(r.file).filename().string() + ", " + r.figure;
  std::string data = r.file, temp;
  if (blog::isBinaryLog(r.file)) {
    blog::Reader reader;
    if (!reader.open(r.file, error)) return refuse(o, "bad_recording", error);
    blog::Slice slice;
    slice.from = p.from;
    slice.to = p.to;
    // The figure's columns this recording has (an older one may lack some: "no data" panels).
    std::stringstream patterns(p.figure->columns);
    std::vector<std::size_t> unused;
    for (std::string pattern; std::getline(patterns, pattern, ',');)
      if (blog::selectColumns(reader.header().columns, {pattern}, unused, error))
        slice.columns.push_back(pattern);
    if (slice.columns.empty()) slice.columns.push_back("t");
    temp = (fs::temp_directory_path() / ("ballast-plot-" + std::to_string(::getpid()) + ".tsv"))
               .string();
    std::FILE* f = std::fopen(temp.c_str(), "w");
    if (!f) return refuse(o, "io_error", "cannot write " + temp + ": " + std::strerror(errno));
    std::string truncation;
    std::uint64_t frames = 0;
    const bool ok = blog::convert(r.file, f, slice, error, &truncation, &frames) == blog::Converted::kOk;
    std::fclose(f);
    if (!ok || frames == 0) {
      std::remove(temp.c_str());
      return refuse(o, "bad_recording",
                    ok ? "no frame of " + r.file + " lies in the window (`ballast log " + r.file +
                             " --info` shows its times)"
                       : error);
    }
    if (!truncation.empty())
      std::fprintf(stderr, "ballast plot: %s is truncated (%s): plotted up to its last complete block\n",
                   r.file.c_str(), truncation.c_str());
    data = temp;
    p.sliced = true;
  }
  cli::TelemetryTable table;
  const double inf = HUGE_VAL;
  if (!cli::readTelemetry(data, table, error, p.sliced ? -inf : p.from, p.sliced ? inf : p.to)) {
    if (!temp.empty()) {  // the message names the converted file: say where it came from
      std::remove(temp.c_str());
      error = r.file + " (the figure's columns in the window): " + error;
    }
    return refuse(o, "bad_recording", error);
  }
  const bool ok = cli::runGnuplot(cli::plotScript(table, data, r.out, p), error);
  if (!temp.empty()) std::remove(temp.c_str());
  if (!ok) return refuse(o, "plot_failed", error);
  if (o.json)
    std::cout << json{{"ok", true}, {"output", r.out}, {"figure", r.figure}, {"frames", table.rows}}.dump()
              << "\n";
  else
    std::printf("plot: %s (%s, %zu frames from %s)\n", r.out.c_str(), r.figure.c_str(), table.rows,
                r.file.c_str());
  return kOk;
}

/// `ballast log FILE [--info] [--to tsv|csv] [--columns PATTERNS] [--from T] [--to T] [-o OUT]`.
struct LogOptions {
  std::string file, out, from;
  bool info = false;
  std::vector<std::string> to;       // each a format (tsv, csv) or a time, as typed
  std::vector<std::string> columns;  // shell patterns
};

/// How much of a column's value a recording keeps: "exact (f64)", "f32" (format 1), or the
/// resolution ("0.001").
std::string kept(const blog::Column& c) {
  if (c.type == blog::Type::kF32) return "f32";
  if (c.type != blog::Type::kI32) return std::string("exact (") + blog::typeName(c.type) + ")";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", c.resolution);
  return buf;
}

/// --info: the header, frames, duration, size and the (selected) columns.
int logInfo(const LogOptions& l, const Options& o) {
  std::string error;
  blog::Summary s;
  if (!blog::summarize(l.file, s, error)) return refuse(o, "bad_recording", error);
  std::vector<std::size_t> selected;
  if (!blog::selectColumns(s.header.columns, l.columns, selected, error))
    return refuse(o, "no_such_column", error);
  const double duration = s.frames > 0 ? s.t_last - s.t_first : 0.0;
  const double per_frame = s.frames > 0 ? double(s.bytes) / double(s.frames) : 0.0;
  // What ten minutes of this recording take, at its own frame rate (telemetry.decimation).
  const double mb_per_10min = duration > 0 ? double(s.bytes) / duration * 600.0 / 1e6 : 0.0;
  if (o.json) {
    json cols = json::array();
    for (std::size_t i : selected) {
      const auto& c = s.header.columns[i];
      json col = {{"name", c.name}, {"unit", c.unit}, {"type", blog::typeName(c.type)}};
      if (c.type == blog::Type::kI32) col["resolution"] = c.resolution;
      if (!c.doc.empty()) col["doc"] = c.doc;
      cols.push_back(col);
    }
    json j = {{"ok", true},          {"file", l.file},
              {"format", s.header.version}, {"profile", s.header.profile},
              {"robot", s.header.robot},    {"start", blog::utcTime(s.header.start_unix_ns)},
              {"frames", s.frames},         {"t_first", s.t_first},
              {"t_last", s.t_last},         {"duration", duration},
              {"bytes", s.bytes},           {"bytes_per_frame", per_frame},
              {"mb_per_10min", mb_per_10min}, {"columns", cols},
              {"truncated", s.truncated}};
    if (s.truncated) j["truncation"] = s.truncation;
    std::cout << j.dump() << "\n";
    return kOk;
  }
  std::printf("file      %s\nformat    ballast binary log, version %u\n", l.file.c_str(),
              s.header.version);
  std::printf("profile   %s\nrobot     %s\nstart     %s\n", s.header.profile.c_str(),
              s.header.robot.c_str(), blog::utcTime(s.header.start_unix_ns).c_str());
  std::printf("frames    %llu (t %.3f to %.3f s: %.3f s)\n",
              static_cast<unsigned long long>(s.frames), s.t_first, s.t_last, duration);
  std::printf("size      %llu bytes (%.1f bytes per frame, %.1f MB per 10 minutes)\n",
              static_cast<unsigned long long>(s.bytes), per_frame, mb_per_10min);
  if (s.truncated)
    std::printf("truncated %s: read up to the last complete block\n", s.truncation.c_str());
  std::printf("columns   %zu%s\n", selected.size(),
              selected.size() < s.header.columns.size()
                  ? (" of " + std::to_string(s.header.columns.size())).c_str()
                  : "");
  std::size_t width = 4;
  for (std::size_t i : selected) width = std::max(width, s.header.columns[i].name.size());
  for (std::size_t i : selected) {
    const auto& c = s.header.columns[i];
    std::printf("  %-*s %-6s %-12s%s%s\n", static_cast<int>(width), c.name.c_str(),
                c.unit.c_str(), kept(c).c_str(), c.doc.empty() ? "" : " ", c.doc.c_str());
  }
  return kOk;
}

/// Converts (and slices) a binary recording to TSV or CSV.
int logCmd(const LogOptions& l, const Options& o) {
  blog::Slice slice;
  slice.columns = l.columns;
  bool format_given = false, to_given = false;
  std::string error;
  for (const std::string& to : l.to) {
    if (to == "tsv" || to == "csv") {
      if (format_given) return usage("ballast log: --to names two formats");
      slice.format = to == "csv" ? blog::Slice::Format::kCsv : blog::Slice::Format::kTsv;
      format_given = true;
    } else {
      if (to_given) return usage("ballast log: --to names two times");
      if (!cli::parseTime(to, slice.to, error))
        return usage("--to: " + error + ", or a format (tsv, csv)");
      to_given = true;
    }
  }
  if (!l.from.empty() && !cli::parseTime(l.from, slice.from, error))
    return usage("--from: " + error);
  if (l.info) {
    if (format_given || to_given || !l.from.empty() || !l.out.empty())
      return usage("ballast log: --info takes --columns, not --to, --from or -o");
    return logInfo(l, o);
  }
  if (slice.from > slice.to) return usage("ballast log: --from is after --to");
  std::FILE* f = stdout;
  if (!l.out.empty() && l.out != "-") {
    f = std::fopen(l.out.c_str(), "w");
    if (!f) return refuse(o, "io_error", "cannot write " + l.out + ": " + std::strerror(errno));
  }
  std::string truncation;
  std::uint64_t frames = 0;
  const blog::Converted done = blog::convert(l.file, f, slice, error, &truncation, &frames);
  if (f != stdout) std::fclose(f);
  if (done != blog::Converted::kOk) {
    if (f != stdout) std::remove(l.out.c_str());
    return refuse(o,
                  done == blog::Converted::kNoSuchColumn ? "no_such_column"
                  : done == blog::Converted::kCannotWrite ? "io_error"
                                                          : "bad_recording",
                  error);
  }
  if (!truncation.empty())
    std::fprintf(stderr, "ballast log: %s is truncated (%s): converted up to its last complete block\n",
                 l.file.c_str(), truncation.c_str());
  if (frames == 0)
    std::fprintf(stderr, "ballast log: no frame of %s lies in the window (`ballast log %s --info` "
                 "shows its times)\n", l.file.c_str(), l.file.c_str());
  return kOk;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "ballast: operator console for ballastd, the whole-body control daemon (ballast(1))"};
  app.require_subcommand(1);
  app.fallthrough();
  Options o;
  app.add_option(
      "--socket", o.socket,
      "daemon socket (default: $BALLAST_SOCKET, else $XDG_RUNTIME_DIR/ballast/ballastd.sock)");
  app.add_flag("--json", o.json, "print the daemon's replies as JSON (one object per line)");
  app.add_option("--lease-file", o.lease_file,
                 "where the command lease token is kept (default: $BALLAST_LEASE_FILE, else per "
                 "socket under $XDG_RUNTIME_DIR/ballast)");
  app.add_option("--timeout", o.timeout, "seconds to wait for an answer (default 10)")
      ->check(CLI::PositiveNumber);
  app.set_version_flag("--version", BALLAST_VERSION);

  auto* status = app.add_subcommand(
      "status", cli::help("status") + std::string("; --watch: ") + cli::help("watch"));
  bool watchFlag = false, joints = false;
  double rate = 10.0;
  int count = 0;
  std::string get;
  status->add_flag("--watch", watchFlag, "keep showing the status (Ctrl-C to quit)");
  status->add_option("--rate", rate, "--watch: updates per second (default 10)")
      ->check(CLI::Range(0.1, 1000.0));
  status->add_option("--count", count, "--watch: stop after this many updates");
  status->add_option("--get", get,
                     "print one field, e.g. mode, base.position, timing.tick_overruns");
  status->add_flag("--joints", joints, "include joint positions and torques");

  app.add_subcommand("stand", cli::help("stand"));
  auto* walk = app.add_subcommand("walk", cli::help("walk"));
  std::string vx = "0", vy = "0", yawRate = "0", forDuration;
  walk->add_option("--vx", vx, protocol::fieldDoc("walk", "vx"));
  walk->add_option("--vy", vy, protocol::fieldDoc("walk", "vy"));
  walk->add_option("--yaw-rate", yawRate,
                   protocol::fieldDoc("walk", "yaw_rate") + std::string(" (or deg with a deg suffix)"));
  walk->add_option("--for", forDuration,
                   protocol::fieldDoc("walk", "ttl") + std::string(" (3, 2.5s, 500ms)"));
  auto* pose = app.add_subcommand("pose", cli::help("pose"));
  std::string height, roll, pitch, yaw;
  pose->add_option("--height", height, protocol::fieldDoc("pose", "height"));
  pose->add_option("--roll", roll, "rad, or deg with a deg suffix (5deg)");
  pose->add_option("--pitch", pitch, "rad, or deg with a deg suffix");
  pose->add_option("--yaw", yaw, "rad, or deg with a deg suffix");
  app.add_subcommand("stop", cli::help("stop"));
  app.add_subcommand("estop", cli::help("estop"));
  app.add_subcommand("reset", cli::help("reset"));
  app.add_subcommand("passive", cli::help("passive"));

  auto* profile = app.add_subcommand("profile", "list, show or switch profiles");
  profile->require_subcommand(1);
  profile->add_subcommand("list", cli::help("profile_list"));
  std::string showName, useName;
  profile->add_subcommand("show", cli::help("profile_show"))
      ->add_option("name", showName, protocol::fieldDoc("profile_show", "name"));
  profile->add_subcommand("use", cli::help("profile_use"))
      ->add_option("name", useName, protocol::fieldDoc("profile_use", "name"))
      ->required();

  auto* map = app.add_subcommand("map", "the terrain map");
  map->require_subcommand(1);
  std::string mapFile;
  map->add_subcommand("load", cli::help("map_load"))
      ->add_option("file", mapFile)
      ->required();
  map->add_subcommand("info", cli::help("map_info"));
  map->add_subcommand("clear", cli::help("map_clear"));
  std::string saveFile;
  map->add_subcommand("save", cli::help("map_save"))->add_option("file", saveFile)->required();

  auto* push = app.add_subcommand("push", cli::help("push"));
  std::string force, duration, body;
  push->add_option("--force", force, "FX,FY,FZ in N, world frame, e.g. 40,0,0")->required();
  push->add_option("--duration", duration,
                   protocol::fieldDoc("push", "duration") + std::string(" (1, 0.5s, 200ms)"))
      ->required();
  push->add_option("--body", body, protocol::fieldDoc("push", "body"));

  auto* advance = app.add_subcommand("advance", cli::help("advance"));
  std::string advanceTo;
  bool noWait = false;
  advance->add_option("time", advanceTo,
                      "controller time to run to (12, 12.5s, 2min), or +DURATION from now")
      ->required();
  advance->add_flag("--no-wait", noWait, "return at once; by default wait until the loop is there");

  auto* record = app.add_subcommand("record", "record telemetry at the control rate");
  record->require_subcommand(1);
  std::string recordFile;
  record->add_subcommand("start", cli::help("record_start"))
      ->add_option("file", recordFile)
      ->required();
  record->add_subcommand("stop", cli::help("record_stop"));

  auto* plotCmd = app.add_subcommand(
      "plot", "plot a recording (.tsv or .blog) as a PNG: the paper's Fig. 3 or another figure");
  PlotRequest plotReq;
  plotCmd->add_option("file", plotReq.file, "telemetry recording (text or .blog)")->required();
  plotCmd->add_option("-o,--output", plotReq.out, "PNG to write")->required();
  std::string figures;
  for (const auto& f : cli::kFigures)
    figures += std::string(figures.empty() ? "" : "; ") + f.name + ": " + f.doc;
  plotCmd->add_option("--fig", plotReq.figure, "the figure (default fig3): " + figures);
  plotCmd->add_option("--from", plotReq.from, "the window's first t (0, 12.5, 12.5s, 2min)");
  plotCmd->add_option("--to", plotReq.to, "the window's last t");
  plotCmd->add_option("--title", plotReq.title, "title above the panels");

  auto* logCmdApp = app.add_subcommand(
      "log", "a binary recording (.blog): its header, or converted to TSV or CSV, sliced");
  LogOptions logOpt;
  logCmdApp->add_option("file", logOpt.file, "binary recording (.blog)")->required();
  logCmdApp->add_flag("--info", logOpt.info,
                      "print the header, frames, duration, size and columns (unit, resolution)");
  logCmdApp
      ->add_option("--to", logOpt.to,
                   "a format, tsv (default) or csv; or a time: the last frame's t (12, 12.5s, 2min)")
      ->allow_extra_args(false);
  logCmdApp
      ->add_option("--columns", logOpt.columns,
                   "only these columns (shell patterns, comma-separated: 't,q_*,tau_left_*'); t is "
                   "always first")
      ->delimiter(',')
      ->allow_extra_args(false);
  logCmdApp->add_option("--from", logOpt.from, "the first frame's t (0, 12.5, 12.5s, 2min)");
  logCmdApp->add_option("-o,--output", logOpt.out, "file to write (default: standard output)");

  auto* lease = app.add_subcommand("lease", "the command lease (motion commands need it)");
  lease->require_subcommand(1);
  lease->add_subcommand("acquire", cli::help("lease_acquire"));
  lease->add_subcommand("take", cli::help("lease_take"));
  lease->add_subcommand("return", cli::help("lease_return"));

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? kOk : kUsage;
  }

  Session s(o);
  std::string error;
  const CLI::App* verb = app.get_subcommands().front();
  const std::string name = verb->get_name();
  auto sub = [&](const CLI::App* a) { return a->get_subcommands().front()->get_name(); };

  if (name == "status") {
    if (watchFlag) return watch(s, o, rate, joints, count);
    if (const int c = s.connect(); c != kOk) return c;
    json reply;
    const int code = s.call({{"cmd", "status"}, {"joints", joints}}, reply);
    if (code == kNoDaemon) return code;
    if (code != kOk)
      return refuse(o, Session::errorCode(reply), reply["error"].value("message", ""));
    const json& st = reply["status"];
    if (!get.empty()) {
      std::string value;
      if (!cli::lookup(st, get, value))
        return refuse(o, "no_field",
                      "status has no field '" + get + "' (see `ballast status --json`)");
      std::printf("%s\n", value.c_str());
    } else if (o.json) {
      std::cout << text(st) << "\n";
    } else {
      std::printf("%s", cli::renderStatus(st).c_str());
    }
    return kOk;
  }
  if (name == "stand" || name == "stop" || name == "reset" || name == "passive")
    return s.run({{"cmd", name}}, [&](const json& r) { printMode(name, r); });
  if (name == "estop")
    return s.run({{"cmd", "estop"}}, [](const json&) {
      std::printf("estop: every joint damped and latched; `ballast reset` clears it\n");
    });
  if (name == "walk") {
    json req = {{"cmd", "walk"}};
    double v;
    if (!cli::parseNumber(vx, v, error)) return usage("--vx: " + error);
    req["vx"] = v;
    if (!cli::parseNumber(vy, v, error)) return usage("--vy: " + error);
    req["vy"] = v;
    if (!cli::parseAngle(yawRate, v, error)) return usage("--yaw-rate: " + error);
    req["yaw_rate"] = v;
    if (!forDuration.empty()) {
      if (!cli::parseDuration(forDuration, v, error)) return usage("--for: " + error);
      req["ttl"] = v;
    }
    return s.run(req, [&](const json& r) { printMode("walk", r); });
  }
  if (name == "pose") {
    json req = {{"cmd", "pose"}};
    double v;
    if (!height.empty()) {
      if (!cli::parseNumber(height, v, error)) return usage("--height: " + error);
      req["height"] = v;
    }
    const std::pair<const char*, std::string*> angles[] = {
        {"roll", &roll}, {"pitch", &pitch}, {"yaw", &yaw}};
    for (const auto& [key, text] : angles) {
      if (text->empty()) continue;
      if (!cli::parseAngle(*text, v, error)) return usage(std::string("--") + key + ": " + error);
      req[key] = v;
    }
    return s.run(req, [&](const json& r) { printMode("pose", r); });
  }
  if (name == "push") {
    std::array<double, 3> f{};
    double d;
    if (!cli::parseVector3(force, f, error)) return usage("--force: " + error);
    if (!cli::parseDuration(duration, d, error)) return usage("--duration: " + error);
    json req = {{"cmd", "push"}, {"force", f}, {"duration", d}};
    if (!body.empty()) req["body"] = body;
    return s.run(req, [&](const json&) {
      std::printf("push: %g,%g,%g N for %g s on %s\n", f[0], f[1], f[2], d,
                  body.empty() ? "the base" : body.c_str());
    });
  }
  if (name == "profile") {
    const std::string what = sub(verb);
    if (what == "list")
      return s.run({{"cmd", "profile_list"}}, [](const json& r) {
        for (const auto& p : r["profiles"])
          std::printf("%s %-22s %s\n", p.value("running", false) ? "*" : " ",
                      p["name"].get<std::string>().c_str(),
                      p.value("valid", false) ? p.value("description", "").c_str()
                                              : ("INVALID: " + p.value("problem", "")).c_str());
      });
    auto nameOrPath = [](const std::string& n) {
      return n.find('/') != std::string::npos || fs::exists(n) ? fs::absolute(n).string() : n;
    };
    if (what == "show") {
      json req = {{"cmd", "profile_show"}};
      if (!showName.empty()) req["name"] = nameOrPath(showName);
      return s.run(req,
                   [](const json& r) { std::printf("%s", r["text"].get<std::string>().c_str()); });
    }
    return s.run({{"cmd", "profile_use"}, {"name", nameOrPath(useName)}}, [](const json& r) {
      std::printf("profile %s in force (%s)\n", r.value("profile", "?").c_str(),
                  r.value("message", "").c_str());
    });
  }
  if (name == "map") {
    auto show = [](const json& r) {
      auto num = [](const json& v) { return v.is_number() ? v.get<double>() : 0.0; };
      const json& m = r["map"];
      if (r.contains("saved")) std::printf("saved %s\n", r["saved"].get<std::string>().c_str());
      if (m.is_null()) {
        std::printf("file map: none\n");
      } else {
        std::printf("file map %s: resolution %g m, %s leaves, from [%.2f, %.2f, %.2f] to [%.2f, %.2f, %.2f] m\n",
                    m["path"].get<std::string>().c_str(), num(m["resolution"]),
                    m["leaves"].dump().c_str(), num(m["min"][0]), num(m["min"][1]),
                    num(m["min"][2]), num(m["max"][0]), num(m["max"][1]), num(m["max"][2]));
      }
      if (!r.contains("live")) return;
      const json& l = r["live"];
      const json& h = l["heights"];
      std::printf("live map: %s, resolution %g m, %s leaves%s%s\n",
                  l.value("mapping", false) ? "mapping from the lidar" : "not mapping",
                  num(l["resolution"]), l["leaves"].dump().c_str(),
                  l.value("seeded_from", "").empty() ? "" : ", seeded from ",
                  l.value("seeded_from", "").c_str());
      std::printf("  heights: %s x %s columns, %s known%s", h["columns"][0].dump().c_str(),
                  h["columns"][1].dump().c_str(), h["known"].dump().c_str(),
                  h.value("floor_known", false) ? " (elsewhere the profile's flat floor)" : "");
      if (h.contains("extent"))
        std::printf(", x %.2f..%.2f m, y %.2f..%.2f m", num(h["extent"][0]), num(h["extent"][2]),
                    num(h["extent"][1]), num(h["extent"][3]));
      std::printf("; ground reference %.2f m, clearance %.2f m\n", num(h["reference"]),
                  num(h["clearance"]));
      const json& sc = l["scans"];
      std::printf("  scans: %s inserted, %s skipped\n", sc["inserted"].dump().c_str(),
                  sc["skipped"].dump().c_str());
      if (l.contains("last_scan")) {
        const json& ls = l["last_scan"];
        std::printf("  last scan: t = %.2f s, %s points, %s columns changed, insert %.2f ms + grid %.2f ms (max %.2f ms)\n",
                    num(ls["t"]), ls["points"].dump().c_str(), ls["columns"].dump().c_str(),
                    num(ls["insert_ms"]), num(ls["grid_ms"]), num(ls["max_ms"]));
      }
      if (l.contains("latency_ms"))
        std::printf("  scan to planner: %.1f ms (max %.1f ms)\n", num(l["latency_ms"]["last"]),
                    num(l["latency_ms"]["max"]));
      if (l.contains("problem")) std::printf("  problem: %s\n", l["problem"].get<std::string>().c_str());
    };
    if (sub(verb) == "info") return s.run({{"cmd", "map_info"}}, show);
    if (sub(verb) == "clear") return s.run({{"cmd", "map_clear"}}, show);
    if (sub(verb) == "save")
      return s.run({{"cmd", "map_save"}, {"path", fs::absolute(saveFile).string()}}, show);
    return s.run({{"cmd", "map_load"}, {"path", fs::absolute(mapFile).string()}}, show);
  }
  if (name == "record") {
    if (sub(verb) == "stop")
      return s.run({{"cmd", "record_stop"}}, [](const json& r) {
        std::printf("recorded %s frames in %s\n", r["frames"].dump().c_str(),
                    r["path"].get<std::string>().c_str());
      });
    return s.run({{"cmd", "record_start"}, {"path", fs::absolute(recordFile).string()}},
                 [](const json& r) {
                   std::printf("recording to %s; `ballast record stop` ends it\n",
                               r["path"].get<std::string>().c_str());
                 });
  }
  if (name == "advance") {
    const bool relative = !advanceTo.empty() && advanceTo[0] == '+';
    double until;
    if (!cli::parseDuration(relative ? advanceTo.substr(1) : advanceTo, until, error))
      return usage("advance: " + error);
    if (const int c = s.connect(); c != kOk) return c;
    json reply;
    auto failed = [&](int code) {
      return code == kNoDaemon ? code
                               : refuse(o, Session::errorCode(reply), reply["error"].value("message", ""));
    };
    // The controller time now: the start of +DURATION, and where a wait ends at once.
    auto now = [&](double& t) {
      const int code = s.call({{"cmd", "status"}}, reply);
      if (code == kOk) t = reply["status"].value("t", 0.0);
      return code;
    };
    double t = 0.0;
    if (relative) {
      if (const int code = now(t); code != kOk) return failed(code);
      until += t;
    }
    if (const int code = s.call({{"cmd", "advance"}, {"until", until}}, reply); code != kOk)
      return failed(code);
    // A held loop stands still at `until`; each command there takes one more tick. A loop whose
    // backend failed stands still anywhere (a simulation that failed has no next step): the
    // wait ends with the fault, or after kNoProgress s of wall time without a tick.
    constexpr double kNoProgress = 10.0;
    double lastT = -1.0;
    auto lastMove = std::chrono::steady_clock::now();
    while (!noWait) {
      if (const int code = now(t); code != kOk) return failed(code);
      if (t + 5e-4 >= until) break;
      const auto wall = std::chrono::steady_clock::now();
      if (t != lastT) {
        lastT = t;
        lastMove = wall;
      } else {
        const double still = std::chrono::duration<double>(wall - lastMove).count();
        const json& faults = reply["status"]["faults"];
        const bool faulted = faults.is_array() && !faults.empty();
        if ((still > 0.5 && faulted) || still > kNoProgress) {
          char at[64];
          std::snprintf(at, sizeof at, "the controller's clock stopped at t = %.3f s", t);
          std::string why = faulted ? ": fault " + faults.back().value("kind", "") + ": " +
                                      faults.back().value("message", "")
                                : " (no tick for " + std::to_string(static_cast<int>(kNoProgress)) +
                                      " s)";
          return refuse(o, "stalled", std::string(at) + why);
        }
      }
      ::usleep(10000);
    }
    if (o.json)
      std::cout << text(json{{"ok", true}, {"until", until}, {"t", t}}) << "\n";
    else if (noWait)
      std::printf("advancing to t = %.3f s\n", until);
    else
      std::printf("advanced to t = %.3f s\n", t);
    return kOk;
  }
  if (name == "plot") return plot(plotReq, o);
  if (name == "log") return logCmd(logOpt, o);
  if (name == "lease") {
    const std::string what = sub(verb);
    if (what == "return") {
      const int code =
          s.run({{"cmd", "lease_return"}}, [](const json&) { std::printf("lease returned\n"); });
      if (code == kOk) s.forgetToken();
      return code;
    }
    json reply;
    const int code = s.run(
        {{"cmd", "lease_" + what}},
        [&](const json& r) {
          std::printf("lease %s (token kept in %s)\n",
                      r.value("renewed", false) ? "renewed" : "held", s.leasePath().c_str());
        },
        &reply);
    if (code == kOk) s.saveToken(reply["lease"].get<std::string>());
    return code;
  }
  return usage("unknown verb " + name);
}
