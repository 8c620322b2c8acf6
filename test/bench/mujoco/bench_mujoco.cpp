// The MuJoCo simulation's speed, as test/bench/sim measures Simbody's: simulated seconds per
// wall second (counter "x_real_time") for the humanoid standing under joint PD with 1 kHz
// commands, as ballastd drives it in lockstep (sensors with noise, rolling lidar scan, ground
// truth).
#include <benchmark/benchmark.h>

#include <fstream>
#include <string>

#include "mujoco_backend.hpp"
#include "test/integration/simbody/sim_test_support.hpp"

namespace {

using namespace ballast;

void standing(benchmark::State& state, const std::string& yaml) {
  simbody::test::SimConfig config;
  config.yaml = yaml;
  mujoco::MujocoBackend sim;
  backend::Error error;
  if (!sim.configure(config.config(), error) || !sim.start(error)) {
    state.SkipWithError(error.message);
    return;
  }
  backend::Sensors sensors;
  sim.read(sensors);
  backend::Commands commands;
  simbody::test::holdPosture(sim.capabilities(), sensors.q, commands);
  for (auto _ : state) {  // one 1 ms control tick
    sim.write(commands);
    if (sim.advance() != backend::Status::kOk) {
      state.SkipWithError(sim.lastError().message);
      break;
    }
    sim.read(sensors);
  }
  const double ticks = static_cast<double>(state.iterations());
  state.counters["x_real_time"] = benchmark::Counter(ticks * config.period, benchmark::Counter::kIsRate);
  state.counters["standing"] = sensors.truth.contact[0] && sensors.truth.contact[2] &&
                               !sensors.truth.non_foot_contact;
}

void BM_MujocoRealTimeFactor(benchmark::State& state) { standing(state, ""); }
BENCHMARK(BM_MujocoRealTimeFactor)->Unit(benchmark::kMicrosecond)->UseRealTime();

// Without the lidar: the physics, sensors and truth alone.
void BM_MujocoRealTimeFactorNoLidar(benchmark::State& state) {
  standing(state, "lidar: {enabled: false}\n");
}
BENCHMARK(BM_MujocoRealTimeFactorNoLidar)->Unit(benchmark::kMicrosecond)->UseRealTime();

// Standing in the corridor of a real building's lidar map (profiles/sim-building-mujoco.yaml's
// map and place): about 5800 terrain boxes. Registered where the map is installed (Debian's
// liboctomap-dev ships it), as acceptance.map.building skips without it.
const char* const kBuildingMap = "/usr/share/doc/liboctomap-dev/examples/data/geb079.bt";
void BM_MujocoRealTimeFactorBuilding(benchmark::State& state) {
  standing(state, std::string("terrain_map: ") + kBuildingMap + "\ninitial_xy: [4.0, -0.4]\n");
}
const bool kBuilding = std::ifstream(kBuildingMap) &&
                       benchmark::RegisterBenchmark("BM_MujocoRealTimeFactorBuilding",
                                                    BM_MujocoRealTimeFactorBuilding)
                           ->Unit(benchmark::kMicrosecond)
                           ->UseRealTime();

}  // namespace
