// The simulation's speed: simulated seconds per wall second (counter "x_real_time") for the
// humanoid standing under joint PD with 1 kHz commands, as ballastd drives it in lockstep
// (sensors with noise, rolling lidar scan, ground truth). Goal (issue 3): >= 4x real time.
#include <benchmark/benchmark.h>

#include <string>

#include "simbody_backend.hpp"
#include "test/integration/simbody/sim_test_support.hpp"

namespace {

using namespace ballast;

void standing(benchmark::State& state, const std::string& yaml) {
  simbody::test::SimConfig config;
  config.yaml = yaml;
  simbody::SimbodyBackend sim;
  backend::Error error;
  if (!sim.configure(config.config(), error) || !sim.start(error)) {
    state.SkipWithError(error.message);
    return;
  }
  backend::Sensors sensors;
  sim.read(sensors);
  backend::Commands commands;
  simbody::test::holdPosture(sim.capabilities(), sensors.q, commands);
  const int stepsBefore = sim.world().integrator().getNumStepsTaken();
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
  state.counters["steps_per_tick"] =
      (sim.world().integrator().getNumStepsTaken() - stepsBefore) / std::max(ticks, 1.0);
  state.counters["standing"] = sensors.truth.contact[0] && sensors.truth.contact[2] &&
                               !sensors.truth.non_foot_contact;
}

void BM_SimRealTimeFactor(benchmark::State& state) { standing(state, ""); }
BENCHMARK(BM_SimRealTimeFactor)->Unit(benchmark::kMicrosecond)->UseRealTime();

// The same with Runge-Kutta-Merson (energy-exact, 2.5x the dynamics evaluations).
void BM_SimRealTimeFactorRkm(benchmark::State& state) { standing(state, "integrator: rkm\n"); }
BENCHMARK(BM_SimRealTimeFactorRkm)->Unit(benchmark::kMicrosecond)->UseRealTime();

// Without the lidar and ground truth work: the physics alone.
void BM_SimRealTimeFactorNoLidar(benchmark::State& state) {
  standing(state, "lidar: {enabled: false}\n");
}
BENCHMARK(BM_SimRealTimeFactorNoLidar)->Unit(benchmark::kMicrosecond)->UseRealTime();

}  // namespace
