// Rigid-body algorithms on the humanoid (30 DoF). Compare with Pinocchio on Atlas (laptop):
// CRBA ≈ 2.3 µs, RNEA ≈ 2.7 µs. Goal here: M and n ≤ 5 µs each on 2 cores.
#include <benchmark/benchmark.h>

#include <random>

#include "model/algorithms.hpp"
#include "model/autodiff.hpp"
#include "test/unit/test_support.hpp"

namespace {

using namespace ballast::model;
using ballast::test::humanoid;

struct State {
  VecX<double> q, v, a;
};
State randomState() {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(-1, 1);
  State s;
  s.q = randomConfiguration(humanoid(), rng);
  s.v = VecX<double>::NullaryExpr(humanoid().nv, [&] { return u(rng); });
  s.a = VecX<double>::NullaryExpr(humanoid().nv, [&] { return u(rng); });
  return s;
}
std::vector<int> contactFrames() {
  const Model& m = humanoid();
  return {m.frameId("left_toe"), m.frameId("left_heel"), m.frameId("right_toe"),
          m.frameId("right_heel")};
}

void BM_ForwardKinematics(benchmark::State& st) {
  Data<double> d(humanoid());
  const State s = randomState();
  for (auto _ : st) {
    forwardKinematics(humanoid(), d, s.q);
    benchmark::DoNotOptimize(d.oMi.back());
  }
}
BENCHMARK(BM_ForwardKinematics);

void BM_MassMatrix(benchmark::State& st) {
  Data<double> d(humanoid());
  const State s = randomState();
  for (auto _ : st) benchmark::DoNotOptimize(crba(humanoid(), d, s.q).data());
}
BENCHMARK(BM_MassMatrix);

void BM_NonlinearEffects(benchmark::State& st) {
  Data<double> d(humanoid());
  const State s = randomState();
  for (auto _ : st) benchmark::DoNotOptimize(nonLinearEffects(humanoid(), d, s.q, s.v).data());
}
BENCHMARK(BM_NonlinearEffects);

void BM_InverseDynamics(benchmark::State& st) {
  Data<double> d(humanoid());
  const State s = randomState();
  for (auto _ : st) benchmark::DoNotOptimize(rnea(humanoid(), d, s.q, s.v, s.a).data());
}
BENCHMARK(BM_InverseDynamics);

/// The four contact points: Jacobians (3 x 30) and J̇·v, as the WBC needs them each tick.
void BM_ContactJacobians(benchmark::State& st) {
  const Model& m = humanoid();
  Data<double> d(m);
  const State s = randomState();
  const std::vector<int> contacts = contactFrames();
  Mat3X<double> J(3, m.nv);
  for (auto _ : st) {
    forwardKinematicsBias(m, d, s.q, s.v);
    for (int c : contacts) {
      frameJacobian(m, d, c, J);
      benchmark::DoNotOptimize(J.data());
      benchmark::DoNotOptimize(frameClassicalAcceleration(m, d, c));
    }
  }
}
BENCHMARK(BM_ContactJacobians);

void BM_CentroidalMomentumMatrix(benchmark::State& st) {
  Data<double> d(humanoid());
  const State s = randomState();
  for (auto _ : st) benchmark::DoNotOptimize(ccrba(humanoid(), d, s.q, s.v).data());
}
BENCHMARK(BM_CentroidalMomentumMatrix);

void BM_CentroidalMomentumBias(benchmark::State& st) {
  Data<double> d(humanoid());
  const State s = randomState();
  for (auto _ : st)
    benchmark::DoNotOptimize(centroidalMomentumBias(humanoid(), d, s.q, s.v).data());
}
BENCHMARK(BM_CentroidalMomentumBias);

/// ẋ = f(x, u) of the paper's eq. (1) at one node.
void BM_CentroidalDynamics(benchmark::State& st) {
  const Model& m = humanoid();
  Data<double> d(m);
  const std::vector<int> contacts = contactFrames();
  const CentroidalLayout L{m.nj(), 4};
  const State s = randomState();
  VecX<double> x = VecX<double>::Zero(L.nx()), u = VecX<double>::Constant(L.nu(), 0.1), xdot(L.nx());
  x.tail(m.nj()) = s.q.tail(m.nj());
  for (auto _ : st) {
    centroidalDynamics(m, d, contacts, x, u, xdot);
    benchmark::DoNotOptimize(xdot.data());
  }
}
BENCHMARK(BM_CentroidalDynamics);

/// ∂f/∂x and ∂f/∂u of eq. (1) at one node (36 x 36 and 36 x 36), analytic O(n): what the
/// MPC's linearisation uses.
void BM_CentroidalDynamicsDerivatives(benchmark::State& st) {
  const Model& m = humanoid();
  Data<double> d(m);
  const std::vector<int> contacts = contactFrames();
  const CentroidalLayout L{m.nj(), 4};
  const State s = randomState();
  VecX<double> x = VecX<double>::Constant(L.nx(), 0.1), u = VecX<double>::Constant(L.nu(), 0.1);
  x.tail(m.nj()) = s.q.tail(m.nj());
  VecX<double> xdot(L.nx());
  MatX<double> Ax(L.nx(), L.nx()), Bu(L.nx(), L.nu());
  for (auto _ : st) {
    centroidalDynamicsDerivatives(m, d, contacts, x, u, xdot, Ax, Bu);
    benchmark::DoNotOptimize(Ax.data());
    benchmark::DoNotOptimize(Bu.data());
  }
}
BENCHMARK(BM_CentroidalDynamicsDerivatives);

/// The same Jacobians by forward-mode ceres::Jet in chunks of 8 (the tests' reference path).
void BM_CentroidalDynamicsDerivativesJet(benchmark::State& st) {
  const Model& m = humanoid();
  constexpr int kChunk = 8;
  Data<ceres::Jet<double, kChunk>> d(m);
  const std::vector<int> contacts = contactFrames();
  const CentroidalLayout L{m.nj(), 4};
  const State s = randomState();
  VecX<double> z = VecX<double>::Constant(L.nx() + L.nu(), 0.1);
  z.segment(L.kJoints, m.nj()) = s.q.tail(m.nj());
  ForwardJacobianWorkspace<kChunk> ws(z.size(), L.nx());
  MatX<double> J(L.nx(), z.size());
  for (auto _ : st) {
    forwardJacobian(
        [&](const auto& zj, auto& yj) {
          centroidalDynamics(m, d, contacts, zj.head(L.nx()), zj.tail(L.nu()), yj);
        },
        z, ws, J);
    benchmark::DoNotOptimize(J.data());
  }
}
BENCHMARK(BM_CentroidalDynamicsDerivativesJet);

}  // namespace
