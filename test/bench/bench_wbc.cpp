// Whole-body controller speed. Compare with the paper's hierarchy: 0.58 ms (qpOASES, i7-13650HX)
// and legged_control's HoQp: 0.53 ms. Goal here: the whole hierarchy ≤ 0.2 ms median on 2 cores.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "test/unit/settings_support.hpp"
#include "test/unit/wbc/qp_test_support.hpp"
#include "test/unit/wbc/wbc_test_support.hpp"

namespace {

using namespace ballast;
using namespace ballast::wbc;

/// One QP of the WBC size: 42 variables, 30 equalities, 40 two-sided inequalities, bounds.
void BM_QpSolve(benchmark::State& st) {
  QpSolver qp(QpCapacity{42, 30, 40});
  std::mt19937 rng(42);
  test::randomFeasibleQp(qp, 42, 30, 40, rng);
  for (auto _ : st) {
    qp.clearWarmStart();
    benchmark::DoNotOptimize(qp.solve());
  }
  st.counters["iterations"] = qp.result().iterations;
  st.counters["active"] = qp.result().activeConstraints;
}
BENCHMARK(BM_QpSolve);

/// The same QP re-solved from the previous active set (consecutive control ticks).
void BM_QpSolveWarm(benchmark::State& st) {
  QpSolver qp(QpCapacity{42, 30, 40});
  std::mt19937 rng(42);
  test::randomFeasibleQp(qp, 42, 30, 40, rng);
  qp.solve();
  for (auto _ : st) benchmark::DoNotOptimize(qp.solve());
  st.counters["iterations"] = qp.result().iterations;
}
BENCHMARK(BM_QpSolveWarm);

/// Ticks of the balance experiment: standing, both arms swinging ±60° at 1 Hz out of phase,
/// base held, force reference m·g/4. 50 ticks spread over one swing period (each with a small
/// tracking error), taken in turn, so that consecutive solves differ as from tick to tick.
struct BalanceTicks {
  const model::Model& m = test::humanoid();
  WholeBodyController wbc;
  std::vector<WbcState> states;
  std::vector<WbcReference> refs;
  WbcOutput out;

  explicit BalanceTicks(WbcSettings settings) : wbc(test::humanoid(), settings) {
    out = wbc.makeOutput();
    const int left = m.jointId("left_shoulder_pitch"), right = m.jointId("right_shoulder_pitch");
    const double w = 2.0 * M_PI, amplitude = M_PI / 3.0;
    for (int k = 0; k < 50; ++k) {
      const double t = 0.02 * k;
      WbcState state = wbc.makeState();
      state.q = test::standingConfiguration(m);
      WbcReference ref = wbc.makeReference();
      ref.basePosition = state.q.head<3>();
      ref.jointPosition = state.q.tail(m.nj());
      for (int i = 0; i < 4; ++i) ref.contactForce[3 * i + 2] = m.totalMass() * 9.81 / 4;
      for (auto [j, sign] : {std::pair{left, 1.0}, std::pair{right, -1.0}}) {
        ref.jointPosition[j] = sign * amplitude * std::sin(w * t);
        ref.jointVelocity[j] = sign * amplitude * w * std::cos(w * t);
        ref.jointAcceleration[j] = -sign * amplitude * w * w * std::sin(w * t);
        state.q[model::Model::qIndexOfJoint(j)] = ref.jointPosition[j] + 0.01 * std::cos(w * t);
        state.v[model::Model::vIndexOfJoint(j)] = ref.jointVelocity[j] - 0.05 * std::sin(w * t);
      }
      state.q[2] -= 0.001 * std::sin(w * t);  // the base moving a little
      state.v.head<3>() << 0.01 * std::cos(w * t), -0.02 * std::sin(w * t), 0.005;
      states.push_back(state);
      refs.push_back(ref);
    }
  }
};

void runTicks(benchmark::State& st, BalanceTicks& b) {
  std::size_t k = 0;
  int qpLevels = 0, iterations = 0, ticks = 0;
  for (auto _ : st) {
    benchmark::DoNotOptimize(b.wbc.update(b.states[k], b.refs[k], b.out));
    qpLevels += b.out.qpSolves;
    iterations += b.out.iterations;
    ++ticks;
    k = (k + 1) % b.states.size();
  }
  st.counters["qp_levels"] = static_cast<double>(qpLevels) / ticks;
  st.counters["qp_iterations"] = static_cast<double>(iterations) / ticks;
}

/// Assembling (M, n, Jacobians, J̇v, the task stack) and solving all levels, torques included.
void BM_WbcHierarchy(benchmark::State& st) {
  BalanceTicks b{test::wbcSettings()};
  runTicks(st, b);
}
BENCHMARK(BM_WbcHierarchy);

/// The same tick under the weighted single-QP variant (cNH).
void BM_WbcWeighted(benchmark::State& st) {
  WbcSettings s = test::wbcSettings();
  s.variant = WbcVariant::kWeighted;
  BalanceTicks b{s};
  runTicks(st, b);
}
BENCHMARK(BM_WbcWeighted);

/// Harder ticks: a sideways base demand beyond what the feet allow, so limits bind and QPs run.
void BM_WbcHierarchyLimitsActive(benchmark::State& st) {
  BalanceTicks b{test::wbcSettings()};
  for (auto& ref : b.refs) ref.baseLinearAcceleration.y() = 3.0;
  runTicks(st, b);
}
BENCHMARK(BM_WbcHierarchyLimitsActive);

}  // namespace
