// BM_LockstepWalk: ballastd's control core in lockstep (test/integration/daemon_stack: the
// profile, the backend plugin, the planner thread, the control loop), walking at 1.0 m/s on flat
// ground with the whole controller: simulated seconds per wall second (x_real_time; goal >= 3 on
// this project's 2-core machine, issue 12) and where each tick's wall time goes, in ms per tick:
// sim (the backend's step), wbc (plan sampling and whole-body controller), estimator, planner
// (the loop posting and waiting for plans), mapping (handing lidar scans to the mapping thread and
// waiting for their maps, mapping.latency), other (status, telemetry, commands).
// One iteration: one second of simulated walking, after standing up and a second of walking.
// BM_LockstepWalkWithoutLiveMap: the same with mapping.enabled false, the control pipeline alone
// (the lidar's OctoMap insertion costs about 2 ms of CPU per scan, 10 scans a second, on cores
// the loop and the planner share). BM_LockstepWalkMujoco: the same on the MuJoCo backend (where its
// plugin is built).
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "test/integration/daemon_stack/daemon_stack.hpp"

namespace {

using namespace ballast;

void lockstepWalk(benchmark::State& state, const std::string& profilePath, double vx) {
  std::unique_ptr<test::DaemonStack> stack;
  try {
    stack = std::make_unique<test::DaemonStack>(profilePath);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  if (!stack->waitForMode(control::Mode::kStand, 5.0) ||
      stack->walk(vx) != control::Refusal::kNone || !stack->run(1.0)) {
    state.SkipWithError("the robot did not stand and start walking");
    return;
  }
  const control::LoopStatus before = stack->status();
  for (auto _ : state)
    if (!stack->run(1.0)) {
      state.SkipWithError("the robot fell or was damped while walking");
      return;
    }
  const control::LoopStatus after = stack->status();
  const double ticks = static_cast<double>(after.ticks - before.ticks);
  const control::LoopProfile& a = after.profile;
  const control::LoopProfile& b = before.profile;
  auto perTick = [&](double x, double y) { return (x - y) / ticks * 1e3; };
  state.counters["x_real_time"] =
      benchmark::Counter(after.t - before.t, benchmark::Counter::kIsRate);
  state.counters["sim_ms"] = perTick(a.backend, b.backend);
  state.counters["wbc_ms"] = perTick(a.controller, b.controller);
  state.counters["estimator_ms"] = perTick(a.estimator, b.estimator);
  state.counters["planner_ms"] = perTick(a.planner, b.planner);
  state.counters["mapping_ms"] = perTick(a.mapping, b.mapping);
  auto other = [](const control::LoopProfile& p) {
    return p.total - p.backend - p.controller - p.estimator - p.planner - p.mapping;
  };
  state.counters["other_ms"] = perTick(other(a), other(b));
  state.counters["fell"] = after.fallen;
}

std::string profilePath(const std::string& name) {
  return std::string(BALLAST_SOURCE_DIR) + "/profiles/" + name;
}

void BM_LockstepWalk(benchmark::State& state) {
  lockstepWalk(state, profilePath("sim-flat.yaml"), 1.0);
}
BENCHMARK(BM_LockstepWalk)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(5);

void BM_LockstepWalkWithoutLiveMap(benchmark::State& state) {
  const std::filesystem::path profile =
      std::filesystem::temp_directory_path() /
      ("ballast-lockstep-bench-" + std::to_string(getpid()) + ".yaml");
  std::ofstream(profile) << "extends: " << profilePath("sim-flat.yaml") << "\n"
                         << "mapping: {enabled: false}\n";
  lockstepWalk(state, profile.string(), 1.0);
  std::filesystem::remove(profile);
}
BENCHMARK(BM_LockstepWalkWithoutLiveMap)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(5);

#ifdef BALLAST_LOCKSTEP_MUJOCO
// The same walk on the MuJoCo backend (profiles/sim-flat-mujoco.yaml: only the backend differs).
void BM_LockstepWalkMujoco(benchmark::State& state) {
  lockstepWalk(state, profilePath("sim-flat-mujoco.yaml"), 1.0);
}
BENCHMARK(BM_LockstepWalkMujoco)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(5);
#endif

}  // namespace
