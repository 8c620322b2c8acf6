// The MPC (paper Sec. II-A): one node's linearisation and projection, the Riccati sweep, and a
// whole SQP iteration. Paper: 6.85 ms per SQP iteration (OCS2, i7-13650HX); goal here ≤ 3 ms
// median on 2 cores, with a 1 s horizon.
#include <benchmark/benchmark.h>

#include "model/algorithms.hpp"
#include "mpc/kinodynamic_problem.hpp"
#include "mpc/riccati_solver.hpp"
#include "mpc/sqp_solver.hpp"

namespace {

using namespace ballast;
using model::CentroidalLayout;

const model::Model& robot() {
  static const model::Model m =
      model::loadUrdfFile(std::string(BALLAST_SOURCE_DIR) + "/urdf/humanoid.urdf");
  return m;
}

struct Setup {
  const model::Model& m = robot();
  std::array<int, 4> frames{m.frameId("left_toe"), m.frameId("left_heel"), m.frameId("right_toe"),
                            m.frameId("right_heel")};
  CentroidalLayout L{m.nj(), 4};
  mpc::ProblemSettings settings;
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
  problem.terminalCost(s.ref, s.x, &nodes[N]);
  std::vector<Eigen::VectorXd> dx, du;
  const Eigen::VectorXd dx0 = Eigen::VectorXd::Zero(s.L.nx());
  for (auto _ : st) benchmark::DoNotOptimize(riccati.sweep(nodes, dx0, dx, du));
}
BENCHMARK(BM_MpcRiccatiSweep)->Unit(benchmark::kMillisecond);

}  // namespace
