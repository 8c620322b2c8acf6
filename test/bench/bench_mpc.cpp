// The MPC (paper Sec. II-A): one node's linearisation and projection, the Riccati sweep, and a
// whole SQP iteration, unprepared and prepared for. Paper: 6.85 ms per SQP iteration (OCS2,
// i7-13650HX); goal here ≤ 3 ms median on 2 cores, with a 1 s horizon.
#include <benchmark/benchmark.h>

#include <chrono>

#include "control/settings.hpp"
#include "locomotion/locomotion_planner.hpp"
#include "model/algorithms.hpp"
#include "model/base_conventions.hpp"
#include "mpc/kinodynamic_problem.hpp"
#include "mpc/riccati_solver.hpp"
#include "mpc/sqp_solver.hpp"
#include "profile/settings.hpp"
#include "test/unit/settings_support.hpp"

namespace {

using namespace ballast;
using model::CentroidalLayout;

struct Setup {
  const model::Model& m = test::humanoid();
  std::array<int, 4> frames{m.frameId("left_toe"), m.frameId("left_heel"), m.frameId("right_toe"),
                            m.frameId("right_heel")};
  CentroidalLayout L{m.nj(), 4};
  mpc::ProblemSettings settings = test::controlDefaults().locomotion.problem;
  mpc::NodeReference ref;
  Eigen::VectorXd x, u;
  Setup() {
    settings.stateWeights = Eigen::VectorXd::Constant(L.nx(), 10.0);
    settings.inputWeights = Eigen::VectorXd::Constant(L.nu(), 1e-2);
    model::VecX<double> q = model::neutralConfiguration(m);
    for (const char* side : {"left_", "right_"}) {
      q[7 + m.jointId(std::string(side) + "hip_pitch")] = -0.4;
      q[7 + m.jointId(std::string(side) + "knee")] = 0.8;
      q[7 + m.jointId(std::string(side) + "ankle_pitch")] = -0.4;
    }
    x = Eigen::VectorXd::Zero(L.nx());
    x[8] = 0.85;
    x.tail(m.nj()) = q.tail(m.nj());
    x[0] = 0.8 * m.totalMass();  // walking forward at 0.8 m/s
    u = Eigen::VectorXd::Zero(L.nu());
    for (int c = 2; c < 4; ++c) u[L.force(c) + 2] = m.totalMass() * 9.81 / 2;
    ref.x = x;
    ref.u = u;
    ref.stance = {false, false, true, true};  // single support: the walking case
    for (int c = 0; c < 2; ++c) {
      ref.swingPosition[c] = Eigen::Vector3d(0.1, 0.1, 0.05);
      ref.swingVelocity[c] = Eigen::Vector3d(1.0, 0.0, 0.2);
    }
  }
};

void BM_MpcLinearizeNode(benchmark::State& st) {
  Setup s;
  mpc::KinodynamicProblem problem(s.m, s.frames, s.settings);
  auto ws = problem.makeWorkspace();
  mpc::LqNode node(s.L.nx(), s.L.nu(), problem.maxEqualities());
  mpc::NodeValue value;
  for (auto _ : st) {
    problem.linearize(*ws, s.ref, s.x, s.u, 0.02, node, value);
    benchmark::DoNotOptimize(node.A.data());
  }
}
BENCHMARK(BM_MpcLinearizeNode);

void BM_MpcProjectNode(benchmark::State& st) {
  Setup s;
  mpc::KinodynamicProblem problem(s.m, s.frames, s.settings);
  auto ws = problem.makeWorkspace();
  mpc::LqNode node(s.L.nx(), s.L.nu(), problem.maxEqualities());
  mpc::NodeValue value;
  problem.linearize(*ws, s.ref, s.x, s.u, 0.02, node, value);
  mpc::RiccatiSolver riccati(1, s.L.nx(), s.L.nu());
  for (auto _ : st) benchmark::DoNotOptimize(riccati.project(0, node));
}
BENCHMARK(BM_MpcProjectNode);

/// The backward sweep and forward pass over N = 50 projected nodes (1 s horizon at 20 ms).
void BM_MpcRiccatiSweep(benchmark::State& st) {
  Setup s;
  const int N = 50;
  mpc::KinodynamicProblem problem(s.m, s.frames, s.settings);
  auto ws = problem.makeWorkspace();
  std::vector<mpc::LqNode> nodes(N + 1, mpc::LqNode(s.L.nx(), s.L.nu(), problem.maxEqualities()));
  mpc::NodeValue value;
  mpc::RiccatiSolver riccati(N, s.L.nx(), s.L.nu());
  for (int k = 0; k < N; ++k) {
    problem.linearize(*ws, s.ref, s.x, s.u, 0.02, nodes[k], value);
    riccati.project(k, nodes[k]);
  }
  problem.terminalCost(*ws, s.ref, s.x, &nodes[N]);
  std::vector<Eigen::VectorXd> dx, du;
  const Eigen::VectorXd dx0 = Eigen::VectorXd::Zero(s.L.nx());
  for (auto _ : st) benchmark::DoNotOptimize(riccati.sweep(nodes, dx0, dx, du));
}
BENCHMARK(BM_MpcRiccatiSweep)->Unit(benchmark::kMillisecond);

}  // namespace

namespace {

/// One real-time SQP iteration of the planner as ballastd runs it (sim-flat's settings: 1 s
/// horizon, 20 ms nodes, both cores), from walking states: the robot walks at 1.0 m/s along its
/// own plan (a perfect tracker), one planner period (10 ms) per benchmark iteration. The split
/// is reported as counters (ms per iteration, averaged): linearisation and projection (the
/// parallel pass over the nodes, its wall time split by the CPU time of each), Riccati sweep,
/// line search. prepared: each iteration is prepared for beforehand, untimed (the SQP's
/// preparation, as ballastd's planner does it in lockstep between a plan and the next state):
/// the time is the iteration's feedback part, prepare_ms the preparation's, and prepared_nodes
/// and prepared_sweeps say on how many of the nodes it was used (mean per iteration).
void mpcIteration(benchmark::State& st, const char* profilePath, bool prepared = false) {
  using namespace ballast;
  const model::Model& m = test::humanoid();
  const profile::Profile p = profile::Profile::load(std::string(BALLAST_SOURCE_DIR) + profilePath);
  const control::ControlSettings settings = profile::buildSettings(p, m);
  const gait::FlatTerrain ground;
  locomotion::LocomotionPlanner planner(m, settings.locomotion, ground);
  locomotion::PlanSampler sampler(m, locomotion::contactFrameIds(m, settings.locomotion));
  locomotion::Plan plan;
  locomotion::PlanSample sample;
  locomotion::LocomotionCommand command;
  command.walk = true;
  command.vx = 1.0;
  Eigen::VectorXd q = model::neutralConfiguration(m), v = Eigen::VectorXd::Zero(m.nv);
  q.tail(m.nj()) = settings.locomotion.nominalJoints;
  q[2] = settings.locomotion.nominalHeight;
  double t = 0.0;
  auto follow = [&] {  // the state one planner period along the plan
    t += 0.01;
    sampler.sample(plan, t, sample);
    const Eigen::Matrix3d R = model::rotationFromZyx<double>(sample.baseZyx);
    q.head<3>() = sample.basePosition;
    q.segment<4>(3) = model::quaternionXyzwFromRotation(R);
    v.head<3>() = R.transpose() * sample.baseLinearVelocity;
    v.segment<3>(3) = R.transpose() * sample.baseAngularVelocity;
    for (int j = 0; j < m.nj(); ++j) {
      q[7 + j] = sample.jointPositions[j];
      v[6 + j] = sample.jointVelocities[j];
    }
  };
  for (int i = 0; i < 200; ++i) {  // 2 s: up to speed, in the middle of the gait
    planner.update(t, q, v, command, plan);
    follow();
  }
  double linearize = 0, projection = 0, riccati = 0, lineSearch = 0, prepare = 0;
  double preparedNodes = 0, preparedSweeps = 0;
  int failures = 0;
  if (prepared) planner.prepare(t);
  for (auto _ : st) {
    failures += !planner.update(t, q, v, command, plan);
    st.PauseTiming();
    const mpc::SqpStatistics& s = planner.statistics();
    linearize += s.linearizeMs;
    projection += s.projectionMs;
    riccati += s.riccatiMs;
    lineSearch += s.lineSearchMs;
    preparedNodes += s.preparedNodes;
    preparedSweeps += s.preparedSweeps;
    follow();
    if (prepared) {
      const auto begin = std::chrono::steady_clock::now();
      planner.prepare(t);
      prepare += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin)
                     .count();
    }
    st.ResumeTiming();
  }
  const double n = static_cast<double>(st.iterations());
  st.counters["linearize_ms"] = linearize / n;
  st.counters["projection_ms"] = projection / n;
  st.counters["riccati_ms"] = riccati / n;
  st.counters["line_search_ms"] = lineSearch / n;
  st.counters["failures"] = failures;
  st.counters["nodes"] = settings.locomotion.sqp.nodes;
  if (!prepared) return;
  st.counters["prepare_ms"] = prepare / n;
  st.counters["prepared_nodes"] = preparedNodes / n;
  st.counters["prepared_sweeps"] = preparedSweeps / n;
}
void BM_MpcIteration(benchmark::State& st) { mpcIteration(st, "/profiles/sim-flat.yaml"); }
BENCHMARK(BM_MpcIteration)->Unit(benchmark::kMillisecond)->UseRealTime();

/// The same iteration prepared for (see mpcIteration): what is left of it once the state comes.
void BM_MpcPreparedIteration(benchmark::State& st) {
  mpcIteration(st, "/profiles/sim-flat.yaml", true);
}
BENCHMARK(BM_MpcPreparedIteration)->Unit(benchmark::kMillisecond)->UseRealTime();

/// The same for the paper's cI planner (planner.model single_rigid_body, profiles/study/cI.yaml):
/// the convex MPC of one rigid body on the same grid, gait and threads.
void BM_MpcIterationSingleRigidBody(benchmark::State& st) {
  mpcIteration(st, "/profiles/study/cI.yaml");
}
BENCHMARK(BM_MpcIterationSingleRigidBody)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
