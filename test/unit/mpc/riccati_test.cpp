// The relaxed barrier, and the projected Riccati solver against a direct KKT solve.
#include <gtest/gtest.h>

#include "mpc/relaxed_barrier.hpp"
#include "mpc/riccati_solver.hpp"
#include "test/unit/mpc/lq_test_problems.hpp"
#define BALLAST_ALLOCATION_COUNTER_ELSEWHERE  // sqp_test.cpp defines the counting malloc
#include "test/unit/allocation_counter.hpp"

namespace ballast::mpc {
namespace {

TEST(RelaxedBarrier, IsTheLogBarrierAboveDeltaAndC2AcrossIt) {
  const RelaxedBarrier b{0.3, 0.05};
  for (double h : {0.05, 0.1, 1.0, 7.0}) {
    EXPECT_DOUBLE_EQ(b.value(h), -0.3 * std::log(h));
    EXPECT_DOUBLE_EQ(b.firstDerivative(h), -0.3 / h);
    EXPECT_DOUBLE_EQ(b.secondDerivative(h), 0.3 / (h * h));
  }
  // Value, slope and curvature continuous at δ.
  const double d = 0.05, eps = 1e-9;
  EXPECT_NEAR(b.value(d - eps), b.value(d + eps), 1e-7);
  EXPECT_NEAR(b.firstDerivative(d - eps), b.firstDerivative(d + eps), 1e-5);
  EXPECT_NEAR(b.secondDerivative(d - eps), b.secondDerivative(d + eps), 1e-3);
  // Derivatives by finite differences on both sides and far into the infeasible side.
  for (double h : {-1.0, -0.01, 0.0, 0.02, 0.049, 0.051, 0.2}) {
    const double s = 1e-6;
    EXPECT_NEAR((b.value(h + s) - b.value(h - s)) / (2 * s), b.firstDerivative(h), 1e-5) << h;
    EXPECT_NEAR((b.firstDerivative(h + s) - b.firstDerivative(h - s)) / (2 * s),
                b.secondDerivative(h), 1e-3 * b.secondDerivative(h))
        << h;
  }
  EXPECT_TRUE(std::isfinite(b.value(-10.0)));
  EXPECT_GT(b.value(-1.0), b.value(0.0));  // keeps pushing back toward feasibility
}

TEST(RelaxedBarrier, WithAReachIsZeroBeyondItAndTheShiftedLogWithin) {
  RelaxedBarrier b{2.0, 0.02};
  b.reach = 0.1;
  // Beyond the reach: no cost, no slope, no curvature.
  for (double h : {0.1, 0.2, 3.0}) {
    EXPECT_EQ(b.value(h), 0.0) << h;
    EXPECT_EQ(b.firstDerivative(h), 0.0) << h;
    EXPECT_EQ(b.secondDerivative(h), 0.0) << h;
  }
  // Within it, by hand: -2 ln h + 2 ln 0.1 + (-2/0.1)(h - 0.1)·(-1) = 2 ln(0.1/h) - 20 (0.1 - h).
  EXPECT_NEAR(b.value(0.05), 2.0 * std::log(2.0) - 1.0, 1e-12);          // 0.386294...
  EXPECT_NEAR(b.firstDerivative(0.05), -2.0 / 0.05 + 2.0 / 0.1, 1e-12);  // -20
  EXPECT_NEAR(b.secondDerivative(0.05), 2.0 / (0.05 * 0.05), 1e-9);      // 800
  // Below δ the quadratic continuation, shifted alike: slope 2 (h - 0.04)/0.0004 + 20.
  EXPECT_NEAR(b.firstDerivative(0.0), -200.0 + 20.0, 1e-9);
  EXPECT_NEAR(b.secondDerivative(0.0), 2.0 / (0.02 * 0.02), 1e-9);
  // Value and slope continuous at the reach; the slope is that of the finite differences.
  const double eps = 1e-9;
  EXPECT_NEAR(b.value(0.1 - eps), 0.0, 1e-12);
  EXPECT_NEAR(b.firstDerivative(0.1 - eps), 0.0, 1e-6);
  for (double h : {-0.5, 0.01, 0.03, 0.07, 0.099}) {
    const double s = 1e-6;
    EXPECT_NEAR((b.value(h + s) - b.value(h - s)) / (2 * s), b.firstDerivative(h), 1e-4) << h;
  }
  // Convex and non-negative: the plain barrier minus its tangent at the reach.
  for (double h : {-1.0, 0.0, 0.05, 0.09}) EXPECT_GT(b.value(h), 0.0) << h;
}

TEST(RiccatiSolver, MatchesTheKktSolutionWithEqualities) {
  std::mt19937 rng(3);
  const int N = 12, nx = 6, nu = 5, maxEq = 3;
  for (int trial = 0; trial < 10; ++trial) {
    const auto nodes =
        testing::randomLqProblem(N, nx, nu, maxEq, [](int k) { return k % 4; }, rng);
    const Eigen::VectorXd dx0 = Eigen::VectorXd::Random(nx);
    std::vector<Eigen::VectorXd> dx, du, dxRef, duRef;
    RiccatiSolver solver(N, nx, nu);
    ASSERT_TRUE(solver.solve(nodes, dx0, dx, du));
    testing::solveByKkt(nodes, dx0, dxRef, duRef);
    testing::expectKktSolution(dx, du, dxRef, duRef);
    for (int k = 0; k < N; ++k) {
      // Equalities hold, and the feedback reproduces the step.
      const int m = nodes[k].neq;
      EXPECT_LT((nodes[k].C.topRows(m) * dx[k] + nodes[k].D.topRows(m) * du[k] + nodes[k].e.head(m)).norm(), 1e-9);
    }
  }
}

TEST(RiccatiSolver, MatchesTheKktSolutionWithStructuredEqualities) {
  // As in the planner: some inputs fixed by unit rows (swing forces), some tied by rows over a
  // subset of inputs (contact velocities over joint velocities), the rest free (stance forces).
  std::mt19937 rng(5);
  const int N = 10, nx = 6, nu = 7, maxEq = 4;
  for (int trial = 0; trial < 10; ++trial) {
    auto nodes = testing::randomLqProblem(N, nx, nu, maxEq, [](int k) { return k % 3 == 0 ? 0 : 4; }, rng);
    for (int k = 0; k < N; ++k) {
      if (nodes[k].neq == 0) continue;
      nodes[k].D.topRows(4).leftCols(3).setZero();  // inputs 0..2 appear in no row: free
      nodes[k].D.row(0).setZero();                  // row 0 fixes input 3
      nodes[k].D(0, 3) = 1.5;
      nodes[k].C.row(0).setZero();
      nodes[k].D.col(3).tail(3).setZero();
      if (k % 2) {                                  // row 1 fixes input 6 too
        nodes[k].D.row(1).setZero();
        nodes[k].D(1, 6) = -0.7;
        nodes[k].C.row(1).setZero();
        nodes[k].neq = 3;
        nodes[k].D.col(6).segment(2, 2).setZero();
      }
    }
    const Eigen::VectorXd dx0 = Eigen::VectorXd::Random(nx);
    std::vector<Eigen::VectorXd> dx, du, dxRef, duRef;
    RiccatiSolver solver(N, nx, nu);
    ASSERT_TRUE(solver.solve(nodes, dx0, dx, du));
    testing::solveByKkt(nodes, dx0, dxRef, duRef);
    testing::expectKktSolution(dx, du, dxRef, duRef);
  }
}

// The SQP's preparation: a node's matrices projected and swept ahead, its vectors later. Kept
// sweeps give the solution of the whole solve to the bit, and the sweep keeps a node's matrices
// only on the same P after it: a node whose matrices changed is swept again, and so is every
// node before it.
TEST(RiccatiSolver, SweepsKeptOnTheSameMatricesGiveTheSolutionOfAFullSolve) {
  std::mt19937 rng(7);
  const int N = 12, nx = 6, nu = 7, maxEq = 4;
  auto nodes = testing::randomLqProblem(
      N, nx, nu, maxEq, [](int k) { return k % 3 == 0 ? 0 : 4; }, rng);
  for (int k = 0; k < N; ++k) {  // a unit row fixes input 3: projectVectors' own part
    if (nodes[k].neq == 0) continue;
    nodes[k].D.row(0).setZero();
    nodes[k].D(0, 3) = 1.5;
    nodes[k].C.row(0).setZero();
    nodes[k].D.col(3).tail(3).setZero();
  }
  const Eigen::VectorXd dx0 = Eigen::VectorXd::Random(nx);
  RiccatiSolver prepared(N, nx, nu);
  std::vector<Eigen::VectorXd> dx, du, dxRef, duRef;
  ASSERT_TRUE(prepared.solve(nodes, dx0, dx, du));  // as a preparation would leave it
  // New vectors on every node; node `changed`'s matrices too (at the end: none).
  for (const int changed : {N, 7, 0}) {
    SCOPED_TRACE(changed);
    for (auto& n : nodes) {
      n.b = Eigen::VectorXd::Random(nx);
      n.e = Eigen::VectorXd::Random(maxEq);
      n.q = Eigen::VectorXd::Random(nx);
      n.r = Eigen::VectorXd::Random(nu);
    }
    if (changed < N) nodes[changed].A += 0.1 * Eigen::MatrixXd::Random(nx, nx);
    prepared.beginSweep(nodes[N]);
    for (int k = N - 1; k >= 0; --k) {
      const bool same = k != changed;
      if (same) {
        prepared.projectVectors(k, nodes[k]);
      } else {
        ASSERT_TRUE(prepared.project(k, nodes[k]));
      }
      ASSERT_TRUE(prepared.sweepNode(k, same));
    }
    prepared.forwardPass(nodes, dx0, dx, du);
    EXPECT_EQ(prepared.keptSweeps(), changed == N ? N : N - 1 - changed);  // the nodes after it
    RiccatiSolver fresh(N, nx, nu);
    ASSERT_TRUE(fresh.solve(nodes, dx0, dxRef, duRef));
    for (int k = 0; k < N; ++k) {
      ASSERT_EQ(dx[k], dxRef[k]) << k;
      ASSERT_EQ(du[k], duRef[k]) << k;
    }
    // And it is the problem's solution.
    testing::solveByKkt(nodes, dx0, dxRef, duRef);
    testing::expectKktSolution(dx, du, dxRef, duRef);
  }
}

// A general row (nearly) dependent on the rows before it in its inputs is dropped, as if the
// node had not had it (the KKT solution of the problem without it), where a projection that met it
// would divide by its sine to the others (legs without hip yaw: both feet's yaw rates are the
// base's). Rows that fix one input twice are still refused.
TEST(RiccatiSolver, DropsDependentEqualityRowsAndRejectsAnInputFixedTwice) {
  std::mt19937 rng(4);
  auto nodes = testing::randomLqProblem(4, 4, 3, 2, [](int) { return 2; }, rng);
  const Eigen::VectorXd dx0 = Eigen::VectorXd::Random(4);
  std::vector<Eigen::VectorXd> dx, du, dxRef, duRef;
  RiccatiSolver solver(4, 4, 3);
  for (const double angle : {0.0, 1e-4}) {
    SCOPED_TRACE(angle);
    auto dependent = nodes;
    dependent[2].D.row(1) = 2.0 * nodes[2].D.row(0);
    dependent[2].D(1, 0) += angle * dependent[2].D.row(1).norm();
    ASSERT_TRUE(solver.solve(dependent, dx0, dx, du));
    auto without = dependent;
    without[2].neq = 1;
    testing::solveByKkt(without, dx0, dxRef, duRef);
    testing::expectKktSolution(dx, du, dxRef, duRef);
  }
  // More general rows than the inputs they act on (4 on 3): the 4th lies in the span of the
  // first three, the most dependent, and goes (its pivot is past the QR's rows, not read).
  auto over = testing::randomLqProblem(4, 4, 3, 4, [](int k) { return k == 2 ? 4 : 1; }, rng);
  ASSERT_TRUE(solver.solve(over, dx0, dx, du));
  auto withoutLast = over;
  withoutLast[2].neq = 3;
  testing::solveByKkt(withoutLast, dx0, dxRef, duRef);
  testing::expectKktSolution(dx, du, dxRef, duRef);
  // Two unit rows fixing the same input.
  nodes = testing::randomLqProblem(4, 4, 3, 2, [](int) { return 2; }, rng);
  nodes[1].D.setZero();
  nodes[1].C.topRows(2).setZero();
  nodes[1].D(0, 2) = 1.0;
  nodes[1].D(1, 2) = 3.0;
  EXPECT_FALSE(solver.solve(nodes, Eigen::VectorXd::Zero(4), dx, du));
}

// Walking takes each node through a few contact modes, and a mode sets the sizes of its node's
// projection. A node keeps its matrices of the modes it had: back in one of them, a solve
// allocates nothing. With more modes than a node keeps, it still solves exactly.
TEST(RiccatiSolver, ANodeBackInAModeItHadAllocatesNothing) {
  std::mt19937 rng(7);
  const int N = 6, nx = 5, nu = 6, maxEq = 4;
  // Modes 0-4: that many general rows over all inputs; 5 and 6: one and two inputs fixed by unit
  // rows, beside one general row over the rest.
  std::vector<std::vector<LqNode>> modes;
  for (int m = 0; m <= maxEq; ++m)
    modes.push_back(testing::randomLqProblem(N, nx, nu, maxEq, [m](int) { return m; }, rng));
  for (int fixed : {1, 2}) {
    auto nodes = testing::randomLqProblem(N, nx, nu, maxEq, [&](int) { return fixed + 1; }, rng);
    for (int k = 0; k < N; ++k)
      for (int j = 0; j < fixed; ++j) {
        nodes[k].D.row(j).setZero();
        nodes[k].D(j, j) = 1.0 + j;
        nodes[k].C.row(j).setZero();
      }
    modes.push_back(nodes);
  }
  const Eigen::VectorXd dx0 = Eigen::VectorXd::Random(nx);
  std::vector<Eigen::VectorXd> dx, du, dxRef, duRef;
  auto solveExactly = [&](RiccatiSolver& solver, int m) {
    SCOPED_TRACE(m);
    bool ok = false;
    const long allocations = test::allocationsIn([&] { ok = solver.solve(modes[m], dx0, dx, du); });
    EXPECT_TRUE(ok);
    testing::solveByKkt(modes[m], dx0, dxRef, duRef);
    testing::expectKktSolution(dx, du, dxRef, duRef);
    return allocations;
  };
  RiccatiSolver solver(N, nx, nu);
  for (int m : {2, 5, 4}) solveExactly(solver, m);
  for (int round = 0; round < 2; ++round)
    for (int m : {2, 5, 4}) EXPECT_EQ(solveExactly(solver, m), 0) << "mode " << m;
  // Seven modes in turn, two more than a node keeps: the least recently used is resized.
  RiccatiSolver cycling(N, nx, nu);
  for (int round = 0; round < 3; ++round)
    for (int m = 0; m < static_cast<int>(modes.size()); ++m) solveExactly(cycling, m);
}

}  // namespace
}  // namespace ballast::mpc
