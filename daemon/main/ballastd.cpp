// ballastd: the whole-body control daemon. Read top to bottom:
//
//   1. options; --dump-schema answers without a profile
//   2. the profile (validated), the robot model, the control settings
//   3. the backend plugin: load, configure with its own profile section, start
//   4. the control loop (its own thread), the telemetry writer (its own thread)
//   5. the socket server on this thread until SIGTERM/SIGINT; SIGHUP reloads the profile
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

#include "backend/plugin_loader.hpp"
#include "control/control_loop.hpp"
#include "control/mpc_planner.hpp"
#include "control/telemetry.hpp"
#include "profile/profile.hpp"
#include "profile/schema.hpp"
#include "profile/settings.hpp"
#include "server/server.hpp"

using namespace ballast;

namespace {

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
  bool lockstep = false, check = false;
  app.add_option("--profile", profilePath,
                 "profile (YAML); default: sim-flat from the profile directories");
  app.add_option("--socket", socketPath,
                 std::string("socket path (default: the profile's ") +
                     profile::table().keyOf<&profile::Settings::server,
                                            &server::ServerConfig::socket_path>() +
                     ", else $XDG_RUNTIME_DIR/ballast/ballastd.sock)");
  app.add_flag("--lockstep", lockstep,
               "step the simulation once per tick: deterministic, as fast as it runs");
  app.add_option("--log-level", logLevel, "trace, debug, info, warn, error or off")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "off"}));
  app.add_option("--dump-schema", dumpSchema,
                 "print every profile key: man (ballast-profile(5)) or yaml, and exit")
      ->check(CLI::IsMember({"man", "yaml"}));
  app.add_flag("--check", check, "validate the profile (and the robot model) and exit");
  app.set_version_flag("--version", BALLAST_VERSION);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  if (dumpSchema == "man") {
    std::cout << profile::schemaManPage();
    return 0;
  }
  if (dumpSchema == "yaml") {
    std::cout << profile::schemaYaml();
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

  // ---- 2. profile, model, settings
  server::DaemonContext ctx;
  ctx.profile_dirs = profile::defaultProfileDirs();
  std::unique_ptr<model::Model> model;
  profile::Settings settings;
  try {
    if (profilePath.empty()) profilePath = profile::resolveProfile("sim-flat", ctx.profile_dirs);
    ctx.profile =
        std::make_unique<profile::Profile>(profile::Profile::load(profilePath, ctx.profile_dirs));
    model = std::make_unique<model::Model>(profile::loadModel(*ctx.profile));
    settings = profile::settingsFor(*ctx.profile, *model);
    ctx.settings = std::make_shared<const control::ControlSettings>(settings.control);
    ctx.keeper.keep(ctx.settings, 0);
  } catch (const profile::ProfileError& e) {
    return startupError("profile " + profilePath + " refused:\n" + e.what());
  }
  const profile::Profile& prof = *ctx.profile;
  auto problem = [&](const void* field, const std::string& what) {
    return prof.problem(profile::keyOf(settings, field), what);
  };
  // The terrain map and the planner's height grid from it (a flat floor at the ground height
  // without one).
  const double ground = settings.control.ground_height;
  ctx.map = server::TerrainMap(ground);
  if (const std::string& map = settings.terrain_map; !map.empty()) {
    std::string error;
    if (!ctx.map.load(map, ground, error)) return startupError(problem(&settings.terrain_map, error));
  }
  if (check) {
    std::printf("profile %s is valid (%zu file%s; robot %s, %d joints)\n", prof.path().c_str(),
                prof.files().size(), prof.files().size() == 1 ? "" : "s", model->name.c_str(),
                model->nj());
    return 0;
  }

  // ---- 3. backend
  std::shared_ptr<backend::Plugin> plugin;
  backend::BackendPtr backend;
  try {
    plugin = backend::Plugin::load(settings.backend.name, settings.backend.plugin_dirs);
    backend = plugin->create();
  } catch (const backend::PluginError& e) {
    return startupError(problem(&settings.backend.name, e.what()));
  }
  if (!backend) return startupError("backend " + plugin->path() + ": create() returned nothing");
  const profile::Profile::BackendSection section = prof.backendSection();
  const std::string urdf = settings.urdf, terrain = settings.terrain_map;
  std::vector<const char*> contactNames;
  for (const auto& f : ctx.settings->contact_frames) contactNames.push_back(f.c_str());
  backend::Config config;
  config.section_yaml = section.yaml.c_str();
  config.section_origin = section.origin.c_str();
  config.urdf_path = urdf.c_str();
  config.terrain_map = terrain.c_str();
  config.contact_frames = contactNames.data();
  config.num_contacts = static_cast<int>(contactNames.size());
  std::vector<backend::JointModel> jointModels(static_cast<std::size_t>(model->nj()));
  for (int j = 0; j < model->nj(); ++j) {
    jointModels[j].name = model->jointName[j + 1].c_str();
    jointModels[j].armature = model->armature[j];
  }
  config.joints = jointModels.data();
  config.num_joint_models = model->nj();
  config.period = 1.0 / ctx.settings->rate;
  config.lockstep = lockstep;
  config.seed = settings.backend.seed;
  backend::Error error;
  if (!backend->configure(config, error))
    return startupError("backend " + settings.backend.name + " refused its configuration:\n" +
                        prof.locateBackendProblem(error.message));
  const backend::Capabilities& caps = backend->capabilities();
  if (lockstep && !caps.lockstep)
    return startupError("--lockstep: backend " + std::string(caps.name) +
                        " cannot run in lockstep (it is not a simulation): drop --lockstep");
  if (!backend->start(error))
    return startupError("backend " + std::string(caps.name) + " failed to start: " + error.message);
  ctx.backend_name = caps.name;
  ctx.simulation = caps.simulation;

  // ---- 4. planner, control loop, telemetry
  // The planner reads the terrain map's height grid; `map load` and profile switches hand it
  // new ones (server.cpp).
  std::unique_ptr<control::MpcPlanner> planner;
  try {
    planner = std::make_unique<control::MpcPlanner>(*model, *ctx.settings, ctx.map.heights());
  } catch (const std::exception& e) {
    backend->stop();
    return startupError(std::string("planner: ") + e.what());
  }
  control::LoopOptions options;
  options.lockstep = lockstep;
  options.planner_priority = 60;  // below the loop's 80 (tryRealtime)
  options.telemetry_capacity = settings.telemetry_ring_frames;
  std::unique_ptr<control::ControlLoop> loop;
  try {
    loop = std::make_unique<control::ControlLoop>(*model, *backend, ctx.settings, options);
  } catch (const std::exception& e) {
    backend->stop();
    return startupError(e.what());
  }
  control::TelemetryWriter writer(loop->telemetryRing(), loop->jointNames());
  loop->setTelemetryWriter(&writer);
  writer.start();
  if (const std::string& file = settings.record_on_start; !file.empty()) {
    std::string why;
    if (!writer.startRecording(file, why)) {
      backend->stop();
      return startupError(problem(&settings.record_on_start, why));
    }
  }
  loop->attachPlanner(planner.get());
  ctx.planner = planner.get();
  ctx.model = model.get();
  ctx.loop = loop.get();
  ctx.writer = &writer;

  // ---- 5. server (this thread), loop thread
  server::Server server(ctx, server::serverConfig(settings, socketPath));
  try {
    server.open();
  } catch (const std::exception& e) {
    backend->stop();
    return startupError(e.what());
  }
  spdlog::info("ballastd {}: profile {}, backend {} ({}{}, {}), robot {} ({} joints), {} Hz",
               BALLAST_VERSION, prof.name(), caps.name, caps.simulation ? "simulation" : "hardware",
               lockstep ? ", lockstep" : "", plugin->path(), model->name, model->nj(),
               ctx.settings->rate);
  if (!lockstep) {
    lockMemory();
    reportKernelPreemption();
  }
  std::atomic<bool> stop{false};
  std::thread control([&] { loop->run(stop); });
  if (!lockstep) tryRealtime(control);

  int status = 0;
  try {
    server.run();
  } catch (const std::exception& e) {
    spdlog::error("server: {}", e.what());
    status = 1;
  }

  // ---- 6. shutdown: damp and stop the backend, flush telemetry, remove the socket
  stop = true;
  control.join();
  writer.stop();
  server.close();
  const control::LoopStatus last = loop->status();
  spdlog::info("stopped at t={:.3f} s in {} ({} ticks, {} late, {} periods skipped)", last.t,
               control::modeName(last.mode), last.ticks, last.timing.late_ticks,
               last.timing.skipped_periods);
  loop.reset();
  return status;
}
