// ballastd: the whole-body control daemon. Read top to bottom:
//
//   1. options; --dump-schema answers without a profile
//   2-4. the daemon put together (main/daemon.hpp): the profile (validated), the robot model, the
//      settings, the backend plugin (loaded, configured with its own profile section, started),
//      the planner, the control loop, the telemetry writer, the socket server
//   5. the loop on its own thread, the server on this one until SIGTERM/SIGINT; SIGHUP reloads
//      the profile
//   6. shutdown: the loop damps and stops the backend, telemetry is flushed, the socket removed
//
// Any problem before the loop starts is printed (file:line:column: key: what is wrong for a
// profile) and ballastd exits 1 without touching the robot; a bad command line exits 2.
#include <linux/capability.h>
#include <malloc.h>
#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <sys/utsname.h>
#include <unistd.h>

#include <cerrno>

#include <atomic>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <memory>
#include <thread>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "main/daemon.hpp"
#include "main/describe_robot.hpp"
#include "profile/schema.hpp"

using namespace ballast;

namespace {

/// A line for each joint of the URDF the model holds fixed, and why, for the start-up log and
/// --check: a joint the URDF locks by itself (a mimic joint, a massless sensor's) is news to
/// whoever wrote the profile.
std::vector<std::string> lockedJointLines(const model::Model& model) {
  std::vector<std::string> lines;
  for (const model::LockedJoint& j : model.lockedJoints)
    lines.push_back(fmt::format("robot: joint {} held at {:.3f} {}: {}", j.name, j.position,
                                j.prismatic ? "m" : "rad", j.reason));
  return lines;
}

int startupError(const std::string& what) {
  std::fprintf(stderr, "ballastd: %s\n", what.c_str());
  return 1;
}

/// Real-time priority for the control thread when the system grants it (it rarely does without
/// CAP_SYS_NICE; the loop then runs at normal priority, and overruns are counted).
void tryRealtime(std::thread& t) {
  sched_param param{};
  param.sched_priority = 80;
  if (pthread_setschedparam(t.native_handle(), SCHED_FIFO, &param) != 0)
    spdlog::warn(
        "control thread: no SCHED_FIFO priority (needs CAP_SYS_NICE or an rtprio limit); "
        "running at normal priority: late ticks are more likely");
  else
    spdlog::info("control thread: SCHED_FIFO priority 80");
}

/// True when the effective capability set has `cap` (CAP_IPC_LOCK, CAP_SYS_NICE).
bool hasCapability(int cap) {
  __user_cap_header_struct header{_LINUX_CAPABILITY_VERSION_3, 0};
  __user_cap_data_struct data[_LINUX_CAPABILITY_U32S_3] = {};
  if (syscall(SYS_capget, &header, data) != 0) return false;
  return (data[cap / 32].effective >> (cap % 32)) & 1u;
}

/// Real time: the daemon's memory stays in RAM (no page fault delays a tick), and malloc keeps
/// what it has instead of returning it. Only where every future allocation can be locked too
/// (CAP_IPC_LOCK, or no RLIMIT_MEMLOCK); otherwise a warning, as for SCHED_FIFO.
///
/// What is mapped now (the model, the controller's and the backend's buffers, the threads
/// started so far) is made resident and locked; what is mapped later is locked as it is first
/// touched (MCL_ONFAULT). Filled in when mapped, a thread's heap growth zeroes its new pages
/// holding the process's address-space lock, yielding the CPU midway: a background thread that
/// other programs starve (the mapping thread, nice 19) then holds up every thread that maps
/// memory, as the planner's solves do when a walk brings contact modes they have not met, for
/// as long as it waits to run (90 ms under a busy host: a plan too old, the robot damped).
/// Touched on first use, a page costs its toucher a minor fault under no lock another thread
/// holds; the threads started after this (the control loop's) touch their stacks at start.
void lockMemory() {
  rlimit limit{};
  getrlimit(RLIMIT_MEMLOCK, &limit);
  if (limit.rlim_cur != RLIM_INFINITY && !hasCapability(CAP_IPC_LOCK)) {
    spdlog::warn(
        "memory not locked: RLIMIT_MEMLOCK is {} KiB and there is no CAP_IPC_LOCK (`ulimit -l "
        "unlimited`, or the capability): a page fault may delay a tick",
        limit.rlim_cur / 1024);
    return;
  }
  if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0) {
    spdlog::warn("memory not locked: mlockall: {}", std::strerror(errno));
    return;
  }
  if (mlockall(MCL_CURRENT | MCL_FUTURE | MCL_ONFAULT) != 0)  // before Linux 4.4: filled in
    spdlog::warn(
        "mlockall: MCL_ONFAULT refused ({}): a thread's heap growth fills its pages "
        "holding the address-space lock the planner may wait for",
        std::strerror(errno));
  mallopt(M_TRIM_THRESHOLD, -1);
  mallopt(M_MMAP_MAX, 0);
  spdlog::info("memory locked (mlockall)");
}

/// Whether the kernel can preempt itself for the control thread. Without PREEMPT_RT (or
/// preempt=full) another process's time in the kernel (a compiler's page faults, a large exit)
/// holds off even the highest-priority thread for milliseconds: cyclictest shows the same stalls
/// as the loop's timing. Said once at start, so a stall in the log can be told from our own.
void reportKernelPreemption() {
  std::ifstream realtime("/sys/kernel/realtime");
  int rt = 0;
  if (realtime >> rt && rt == 1) {
    spdlog::info("kernel: PREEMPT_RT");
    return;
  }
  utsname name{};
  uname(&name);
  spdlog::warn(
      "kernel {} is not PREEMPT_RT ({}): kernel work of other processes can delay the control "
      "thread by milliseconds whatever its priority; measure with cyclictest (ballastd(8), REAL "
      "TIME)",
      name.release, name.version);
}

}  // namespace

int main(int argc, char** argv) {
  // ---- 1. options
  CLI::App app{"ballastd: whole-body control daemon for humanoids with heavy limbs (ballastd(8))"};
  std::string profilePath, socketPath, logLevel = "info", dumpSchema;
  bool lockstep = false, hold = false, check = false;
  app.add_option("--profile", profilePath,
                 "profile (YAML); default: sim-flat from the profile directories");
  app.add_option("--socket", socketPath,
                 std::string("socket path (default: the profile's ") +
                     profile::table().keyOf<&profile::Settings::server,
                                            &server::ServerConfig::socket_path>() +
                     ", else $XDG_RUNTIME_DIR/ballast/ballastd.sock)");
  app.add_flag("--lockstep", lockstep,
               "step the simulation once per tick: deterministic, as fast as it runs");
  app.add_flag("--hold", hold,
               "with --lockstep: controller time advances only as far as a client asks "
               "(protocol command advance), so scripted commands land at exact times")
      ->needs("--lockstep");
  app.add_option("--log-level", logLevel, "trace, debug, info, warn, error or off")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "off"}));
  app.add_option("--dump-schema", dumpSchema,
                 "print every profile key, the sections of the backend plugins found included: man "
                 "(ballast-profile(5)) or yaml, and exit")
      ->check(CLI::IsMember({"man", "yaml"}));
  app.add_flag("--check", check,
               "validate the profile as a start would (the robot model, the terrain map, the "
               "backend's own section through its plugin) without starting anything, and exit");
  std::string describe;
  app.add_option("--describe-robot", describe,
                 "describe the robot of this URDF (mass, limbs, joints, feet) and print a starter "
                 "profile for it, and exit");
  app.set_version_flag("--version", BALLAST_VERSION);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  if (!describe.empty()) {
    try {
      std::cout << daemon::describeRobot(describe);
      return 0;
    } catch (const std::exception& e) {
      std::cerr << "ballastd: " << e.what() << "\n";
      return 1;
    }
  }
  if (dumpSchema == "man" || dumpSchema == "yaml") {
    std::vector<profile::BackendSectionDoc> backends;
    for (const std::string& name : backend::availablePlugins()) {
      try {
        const auto plugin = backend::Plugin::load(name);
        const char* text =
            plugin->entry().section_doc ? plugin->entry().section_doc(dumpSchema.c_str()) : nullptr;
        if (text) backends.push_back({name, text});
      } catch (const backend::PluginError& e) {
        std::cerr << "ballastd: backend " << name << " left out: " << e.what() << "\n";
      }
    }
    std::cout << (dumpSchema == "man" ? profile::schemaManPage(backends)
                                      : profile::schemaYaml(backends));
    return 0;
  }
  auto logger = spdlog::stderr_color_mt("ballastd");
  spdlog::set_default_logger(logger);
  spdlog::set_level(spdlog::level::from_str(logLevel));
  spdlog::set_pattern("%Y-%m-%d %H:%M:%S.%e %^%l%$ %v");

  // SIGTERM/SIGINT/SIGHUP go to the server's signalfd: block them before any thread starts.
  sigset_t signals;
  sigemptyset(&signals);
  for (int s : {SIGTERM, SIGINT, SIGHUP}) sigaddset(&signals, s);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  signal(SIGPIPE, SIG_IGN);

  // ---- 2-4. profile, model, settings, terrain map; backend; planner, loop, telemetry, server
  daemon::DaemonOptions options;
  options.profile = profilePath;
  options.lockstep = lockstep;
  options.hold = hold;
  options.check_only = check;
  options.socket = socketPath;
  options.planner_priority = 60;  // below the loop's 80 (tryRealtime)
  std::unique_ptr<daemon::Daemon> d;
  try {
    d = std::make_unique<daemon::Daemon>(options);
    if (check) {
      const profile::Profile& prof = d->profile();
      std::printf("profile %s is valid (%zu file%s; robot %s, %d joints; backend %s: %s)\n",
                  prof.path().c_str(), prof.files().size(), prof.files().size() == 1 ? "" : "s",
                  d->model().name.c_str(), d->model().nj(), d->settings().backend.name.c_str(),
                  d->backendChecked() ? "its section checked by the plugin"
                                      : ("not checked: " + d->backendNote()).c_str());
      for (const std::string& line : lockedJointLines(d->model())) std::printf("%s\n", line.c_str());
      return 0;
    }
    d->startTelemetry();
    d->server()->open();
  } catch (const daemon::StartupError& e) {
    return startupError(e.what());
  } catch (const std::exception& e) {  // the server's socket
    return startupError(e.what());
  }

  // ---- 5. server (this thread), loop thread
  const backend::Capabilities& caps = d->backend().capabilities();
  spdlog::info("ballastd {}: profile {}, backend {} ({}{}, {}), robot {} ({} joints), {} Hz",
               BALLAST_VERSION, d->profile().name(), caps.name,
               caps.simulation ? "simulation" : "hardware", lockstep ? ", lockstep" : "",
               d->pluginPath(), d->model().name, d->model().nj(), d->settings().control.rate);
  if (!d->backendNote().empty()) spdlog::info("backend {}: {}", caps.name, d->backendNote());
  for (const std::string& line : lockedJointLines(d->model())) spdlog::info("{}", line);
  if (!lockstep) {
    lockMemory();
    reportKernelPreemption();
  }
  std::atomic<bool> stop{false};
  std::thread control([&] { d->run(stop); });
  if (!lockstep) tryRealtime(control);

  int status = 0;
  try {
    d->server()->run();
  } catch (const std::exception& e) {
    spdlog::error("server: {}", e.what());
    status = 1;
  }

  // ---- 6. shutdown: damp and stop the backend, flush telemetry, remove the socket
  stop = true;
  control.join();
  d->writer().stop();
  d->server()->close();
  const control::LoopStatus last = d->loop().status();
  spdlog::info("stopped at t={:.3f} s in {} ({} ticks, {} late, {} periods skipped, {} host "
               "stalls the simulated world waited for)",
               last.t, control::modeName(last.mode), last.ticks, last.timing.late_ticks,
               last.timing.skipped_periods, last.timing.host_stalls);
  d.reset();
  return status;
}
