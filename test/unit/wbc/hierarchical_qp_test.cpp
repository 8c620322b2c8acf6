// The hierarchical solver on random task stacks, against independent formulations: lexicographic
// least squares by SVD (equalities only), and one full-space QP per level that fixes what the
// levels above achieved (with inequalities).
#include <gtest/gtest.h>

#include <Eigen/SVD>

#include "test/unit/wbc/qp_test_support.hpp"
#include "wbc/hierarchical_qp.hpp"

namespace ballast::test {
namespace {

using namespace wbc;

/// Fills a random stack: `levels` levels of `rows` equality rows each over n variables, plus
/// `ineq` inequality rows on level `ineqLevel` (random two-sided rows around a point x0 that also
/// meets the levels above it).
void randomStack(TaskStack& stack, int levels, int rows, int ineq, int ineqLevel, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int n = stack.variables();
  const Eigen::VectorXd x0 = Eigen::VectorXd::NullaryExpr(n, [&] { return u(rng); });
  stack.clear();
  for (int k = 0; k < levels; ++k) {
    stack.beginLevel();
    auto eq = stack.addEqualities(rows);
    eq.A = Eigen::MatrixXd::NullaryExpr(rows, n, [&] { return u(rng); });
    eq.b = Eigen::VectorXd::NullaryExpr(rows, [&] { return 3.0 * u(rng); });
    if (k < ineqLevel) eq.b = eq.A * x0;  // so that x0 is feasible on the levels above
    if (k == ineqLevel && ineq > 0) {
      auto in = stack.addInequalities(ineq);
      in.D = Eigen::MatrixXd::NullaryExpr(ineq, n, [&] { return u(rng); });
      const Eigen::VectorXd d0 = in.D * x0;
      for (int i = 0; i < ineq; ++i) {
        in.lower[i] = i % 3 == 1 ? -kInf : d0[i] - 0.1 - 0.2 * (u(rng) + 1.0);
        in.upper[i] = i % 3 == 2 ? kInf : d0[i] + 0.1 + 0.2 * (u(rng) + 1.0);
      }
    }
  }
}

/// Lexicographic least squares by SVD null spaces (no inequalities).
Eigen::VectorXd lexicographicLeastSquares(const TaskStack& t) {
  const int n = t.variables();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd N = Eigen::MatrixXd::Identity(n, n);
  for (int k = 0; k < t.levels() && N.cols() > 0; ++k) {
    const Eigen::MatrixXd A = t.A().middleRows(t.equalityBegin(k), t.equalityRows(k));
    const Eigen::VectorXd b = t.b().segment(t.equalityBegin(k), t.equalityRows(k));
    const Eigen::MatrixXd AN = A * N;
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(AN, Eigen::ComputeFullU | Eigen::ComputeFullV);
    svd.setThreshold(1e-9);
    x += N * svd.solve(b - A * x);
    N = (N * svd.matrixV().rightCols(N.cols() - svd.rank())).eval();
  }
  return x;
}

TEST(HierarchicalQp, EqualityLevelsMatchLexicographicLeastSquares) {
  std::mt19937 rng(1);
  const int n = 42;
  TaskStack stack(n, 6, 60, 0);
  HierarchicalQp hqp(n, 6, 10, 0);
  for (int trial = 0; trial < 20; ++trial) {
    const int rows = std::uniform_int_distribution<int>(3, 10)(rng);
    randomStack(stack, 6, rows, 0, 0, rng);
    ASSERT_EQ(hqp.solve(stack), HqpStatus::kOk);
    const Eigen::VectorXd expected = lexicographicLeastSquares(stack);
    // With 6 × rows ≥ n the solution is unique; otherwise both are the minimum-norm choice.
    EXPECT_LT((hqp.solution() - expected).cwiseAbs().maxCoeff(), 1e-8) << "trial " << trial;
    for (int k = 0; k < 6; ++k)
      EXPECT_NEAR(hqp.level(k).residual, stack.residual(k, expected), 1e-8);
  }
}

TEST(HierarchicalQp, DependentRowsWithinAndAcrossLevels) {
  std::mt19937 rng(2);
  const int n = 12;
  TaskStack stack(n, 3, 30, 0);
  randomStack(stack, 3, 5, 0, 0, rng);
  // Rebuild with level 1 = a copy of two rows of level 0 (consistent) plus one new row, and
  // level 2 with a row repeated inside it (inconsistently: least squares averages).
  const Eigen::MatrixXd A0 = stack.A().topRows(5);
  const Eigen::VectorXd b0 = stack.b().head(5);
  stack.clear();
  stack.beginLevel();
  auto l0 = stack.addEqualities(5);
  l0.A = A0;
  l0.b = b0;
  stack.beginLevel();
  auto l1 = stack.addEqualities(3);
  l1.A.topRows(2) = A0.topRows(2);
  l1.b.head(2) = b0.head(2);
  l1.A.row(2).setOnes();
  l1.b[2] = 1.0;
  stack.beginLevel();
  auto l2 = stack.addEqualities(2);
  l2.A.row(0) = Eigen::RowVectorXd::LinSpaced(n, 0.0, 1.0);
  l2.A.row(1) = l2.A.row(0);
  l2.b << 1.0, 2.0;
  HierarchicalQp hqp(n, 3, 5, 0);
  ASSERT_EQ(hqp.solve(stack), HqpStatus::kOk);
  EXPECT_EQ(hqp.level(0).rank, 5);
  EXPECT_EQ(hqp.level(1).rank, 1);
  EXPECT_EQ(hqp.level(2).rank, 1);
  EXPECT_LT(hqp.level(0).residual, 1e-10);
  EXPECT_LT(hqp.level(1).residual, 1e-10);
  EXPECT_NEAR(hqp.level(2).residual, std::sqrt(0.5), 1e-10);  // both rows meet at 1.5
  EXPECT_LT((hqp.solution() - lexicographicLeastSquares(stack)).norm(), 1e-9);
}

/// Orthonormal basis of the null space of M (by SVD, independent of the solver's QR).
Eigen::MatrixXd nullSpace(const Eigen::MatrixXd& M) {
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(M, Eigen::ComputeFullV);
  svd.setThreshold(1e-9);
  return svd.matrixV().rightCols(M.cols() - svd.rank());
}

// A level of rank 4 in 8 rows whose targets contradict each other, with rows of norms from 1e-2
// to 1e3, above two ordinary levels: each level's answer must satisfy its optimality (KKT)
// conditions in the set the levels above leave. Level 0 is plain least squares, A₀ᵀ(A₀x − b₀) = 0;
// level k minimises ‖A_k x − b_k‖ over the x that keep A_j x (j < k) where they are, so its
// gradient A_kᵀ(A_k x − b_k) has no part in the null space N of the rows above.
TEST(HierarchicalQp, RankDeficientContradictoryLevelMeetsTheLeastSquaresKktConditions) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int n = 12;
  auto random = [&](int rows, int cols) {
    return Eigen::MatrixXd(Eigen::MatrixXd::NullaryExpr(rows, cols, [&] { return u(rng); }));
  };
  for (int trial = 0; trial < 20; ++trial) {
    TaskStack stack(n, 3, 18, 0);
    stack.beginLevel();
    auto l0 = stack.addEqualities(8);
    l0.A = random(8, 4) * random(4, n);
    for (int i = 0; i < 8; ++i) l0.A.row(i) *= std::pow(10.0, -2.0 + 5.0 * i / 7.0);
    l0.b = 10.0 * Eigen::VectorXd::NullaryExpr(8, [&] { return u(rng); });
    stack.beginLevel();
    auto l1 = stack.addEqualities(6);
    l1.A = random(6, n);
    l1.b = Eigen::VectorXd::NullaryExpr(6, [&] { return u(rng); });
    stack.beginLevel();
    auto l2 = stack.addEqualities(4);
    l2.A = random(4, n);
    l2.b = Eigen::VectorXd::NullaryExpr(4, [&] { return u(rng); });

    HierarchicalQp hqp(n, 3, 8, 0);
    ASSERT_EQ(hqp.solve(stack), HqpStatus::kOk);
    const Eigen::VectorXd& x = hqp.solution();
    ASSERT_TRUE(x.allFinite());
    EXPECT_EQ(hqp.level(0).rank, 4);
    EXPECT_EQ(hqp.level(1).rank, 6);
    EXPECT_EQ(hqp.level(2).rank, 2);
    Eigen::MatrixXd above(0, n);
    for (int k = 0; k < 3; ++k) {
      const Eigen::MatrixXd A = stack.A().middleRows(stack.equalityBegin(k), stack.equalityRows(k));
      const Eigen::VectorXd b = stack.b().segment(stack.equalityBegin(k), stack.equalityRows(k));
      const Eigen::VectorXd gradient = A.transpose() * (A * x - b);
      const Eigen::MatrixXd N =
          k == 0 ? Eigen::MatrixXd(Eigen::MatrixXd::Identity(n, n)) : nullSpace(above);
      EXPECT_LT((N.transpose() * gradient).norm(), 1e-8 * std::max(1.0, A.norm() * b.norm()))
          << "trial " << trial << " level " << k;
      above.conservativeResize(above.rows() + A.rows(), n);
      above.bottomRows(A.rows()) = A;
    }
    EXPECT_GT(hqp.level(0).residual, 1.0);  // the contradiction is real
    EXPECT_LT((x - lexicographicLeastSquares(stack)).norm(), 1e-8 * std::max(1.0, x.norm()));
  }
}

// Rows that are nearly, not exactly, dependent on the rows before them (a leg without hip yaw on
// both feet: the feet's relative yaw): solved exactly they would ask for a step of the targets'
// disagreement over the sine of their angle. Below settings.dependentBelow they count as
// dependent (least squares, as the exactly dependent rows); between that and
// settings.dampingBelow their direction is damped. Either way the answer stays of the size of the
// targets, the other rows are met, and without either rule the step is huge.
TEST(HierarchicalQp, NearlyDependentRowsGiveStepsOfTheTargetsSizeNotOfOneOverTheirAngle) {
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int n = 10;
  const Eigen::MatrixXd A4 = Eigen::MatrixXd::NullaryExpr(4, n, [&] { return u(rng); });
  const Eigen::VectorXd b4 = Eigen::VectorXd::NullaryExpr(4, [&] { return u(rng); });
  Eigen::RowVectorXd direction = Eigen::RowVectorXd::NullaryExpr(n, [&] { return u(rng); });
  // The part of `direction` outside the rows' span, of unit norm.
  direction -= (A4.transpose() * A4.transpose().colPivHouseholderQr().solve(direction.transpose())).transpose();
  direction.normalize();
  const double disagreement = 0.01;
  auto stackWith = [&](double angle) {
    TaskStack stack(n, 2, 5 + n, 0);
    stack.beginLevel();
    auto l0 = stack.addEqualities(5);
    l0.A.topRows(4) = A4;
    l0.b.head(4) = b4;
    const double norm = A4.row(0).norm();
    l0.A.row(4) = A4.row(0) + angle * norm * direction;
    l0.b[4] = b4[0] + disagreement * norm;
    stack.beginLevel();
    auto l1 = stack.addEqualities(n);
    l1.A.setIdentity();  // and the rest as small as it can be
    return stack;
  };
  const Eigen::VectorXd xLs = lexicographicLeastSquares(stackWith(0.0));
  for (const double angle : {1e-7, 3e-5, 2e-4}) {
    SCOPED_TRACE(angle);
    const TaskStack stack = stackWith(angle);
    HierarchicalQp hqp(n, 2, n, 0);
    ASSERT_EQ(hqp.solve(stack), HqpStatus::kOk);
    const Eigen::VectorXd& x = hqp.solution();
    ASSERT_TRUE(x.allFinite());
    EXPECT_LT((A4 * x - b4).tail(3).norm(), 1e-9);  // the rows that are not in question
    EXPECT_LT(x.norm(), 2.0 * xLs.norm() + 1.0);
    EXPECT_LT(hqp.level(0).residual, disagreement * A4.row(0).norm());
    if (angle < 1e-4) {
      EXPECT_EQ(hqp.level(0).rank, 4);  // dependent: the least squares of the dependent rows
      EXPECT_LT((x - xLs).norm(), 1e-3 * xLs.norm());
    } else {
      EXPECT_EQ(hqp.level(0).rank, 5);
      EXPECT_TRUE(hqp.level(0).damped);
    }
    // Without the two rules, the exact solve: a step of disagreement / angle.
    HqpSettings exact;
    exact.dependentBelow = 0.0;
    exact.dampingBelow = 0.0;
    HierarchicalQp plain(n, 2, n, 0, exact);
    ASSERT_EQ(plain.solve(stack), HqpStatus::kOk);
    EXPECT_GT(plain.solution().norm(), 0.2 * disagreement / angle);
  }
}

/// For each level, the best residual over x meeting the levels above as the solver did and
/// every inequality row in force (those of levels ≤ k), by one QP in the full space.
double fullSpaceBest(const TaskStack& t, int level, const Eigen::VectorXd& x) {
  const int n = t.variables();
  int me = 0;
  for (int j = 0; j < level; ++j) me += t.equalityRows(j);
  const int p = t.inequalityBegin(level) + t.inequalityRows(level);
  QpSolver qp(QpCapacity{n, std::max(me, 1), std::max(p, 1)});
  qp.resize(n, me, p);
  const Eigen::MatrixXd Ak = t.A().middleRows(t.equalityBegin(level), t.equalityRows(level));
  const Eigen::VectorXd bk = t.b().segment(t.equalityBegin(level), t.equalityRows(level));
  qp.H() = Ak.transpose() * Ak + 1e-12 * Eigen::MatrixXd::Identity(n, n);
  qp.g() = -Ak.transpose() * bk;
  qp.A() = t.A().topRows(me);
  qp.b() = qp.A() * x;
  qp.C() = t.D().topRows(p);
  qp.lower() = t.lower().head(p);
  qp.upper() = t.upper().head(p);
  EXPECT_EQ(qp.solve(), QpStatus::kOptimal) << qp.result().reason;
  return (Ak * qp.x() - bk).norm();
}

TEST(HierarchicalQp, InequalitiesMatchAFullSpaceQpPerLevel) {
  std::mt19937 rng(3);
  const int n = 20;
  TaskStack stack(n, 4, 40, 30);
  HierarchicalQp hqp(n, 4, 10, 30);
  hqp.settings().regularization = 1e-10;
  int qpLevels = 0;
  for (int trial = 0; trial < 30; ++trial) {
    randomStack(stack, 4, 4, 30, trial % 2, rng);  // inequalities on level 0 or 1
    ASSERT_NE(hqp.solve(stack), HqpStatus::kFailed) << "trial " << trial;
    for (int k = 0; k < 4; ++k) {
      qpLevels += hqp.level(k).qpSolved ? 1 : 0;
      EXPECT_NEAR(hqp.level(k).residual, fullSpaceBest(stack, k, hqp.solution()), 1e-6)
          << "trial " << trial << " level " << k;
    }
    // The inequalities of every level hold (none of these needed slack).
    EXPECT_EQ(hqp.slack().norm(), 0.0);
    for (int k = 0; k < 4; ++k) EXPECT_LT(stack.violation(k, hqp.solution()), 1e-8);
  }
  EXPECT_GT(qpLevels, 30);  // the inequalities did bind
}

TEST(HierarchicalQp, InfeasibleInequalitiesGetMinimalSlackAndStayRelaxedBelow) {
  // Level 0: x0 ≥ 1 and x0 ≤ 0 (contradictory), x1 ≤ 2. Level 1: x = (5, 5).
  TaskStack stack(2, 2, 4, 4);
  stack.beginLevel();
  auto in = stack.addInequalities(3);
  in.D << 1, 0, 1, 0, 0, 1;
  in.lower << 1, -kInf, -kInf;
  in.upper << kInf, 0, 2;
  stack.beginLevel();
  auto eq = stack.addEqualities(2);
  eq.A.setIdentity();
  eq.b << 5, 5;
  HierarchicalQp hqp(2, 2, 2, 4);
  ASSERT_EQ(hqp.solve(stack), HqpStatus::kRelaxed);
  EXPECT_TRUE(hqp.level(0).relaxed);
  EXPECT_NEAR(hqp.solution()[0], 0.5, 1e-6);  // the contradiction split evenly
  EXPECT_NEAR(hqp.solution()[1], 2.0, 1e-6);  // level 1 pushes x1 only up to its bound
  EXPECT_NEAR(hqp.slack()[0], 0.5, 1e-6);
  EXPECT_NEAR(hqp.slack()[1], 0.5, 1e-6);
  EXPECT_NEAR(hqp.slack()[2], 0.0, 1e-12);
}

TEST(HierarchicalQp, VariableScaleSetsTheMinimumNormChoice) {
  TaskStack stack(2, 1, 1, 0);
  stack.beginLevel();
  auto eq = stack.addEqualities(1);
  eq.A << 1, 1;
  eq.b << 2;
  HierarchicalQp hqp(2, 1, 1, 0);
  ASSERT_EQ(hqp.solve(stack), HqpStatus::kOk);
  EXPECT_NEAR(hqp.solution()[0], 1.0, 1e-12);
  hqp.setVariableScale(Eigen::Vector2d(1.0, 10.0));  // x1 is "cheap": min (x0² + (x1/10)²)
  ASSERT_EQ(hqp.solve(stack), HqpStatus::kOk);
  EXPECT_NEAR(hqp.solution()[0], 2.0 / 101.0, 1e-12);
  EXPECT_NEAR(hqp.solution()[1], 200.0 / 101.0, 1e-12);
  EXPECT_THROW(hqp.setVariableScale(Eigen::Vector2d(1.0, 0.0)), std::invalid_argument);
}

TEST(HierarchicalQp, AFailedLevelKeepsTheAnswerOfTheLevelsAbove) {
  std::mt19937 rng(4);
  const int n = 20;
  TaskStack stack(n, 3, 30, 30);
  HierarchicalQp hqp(n, 3, 10, 30);
  // Find a stack whose level 1 needs a QP, then starve that QP of iterations.
  for (int trial = 0; trial < 50; ++trial) {
    randomStack(stack, 3, 6, 30, 1, rng);
    hqp.settings().qp.maxIterations = 200;
    ASSERT_NE(hqp.solve(stack), HqpStatus::kFailed);
    if (!hqp.level(1).qpSolved || hqp.level(1).iterations < 2 || hqp.level(0).qpSolved) continue;
    HierarchicalQp fresh(n, 3, 10, 30);
    fresh.settings().qp.maxIterations = 1;
    ASSERT_EQ(fresh.solve(stack), HqpStatus::kFailed);
    EXPECT_EQ(fresh.level(1).qpStatus, QpStatus::kIterationLimit);
    EXPECT_TRUE(fresh.level(2).skipped);
    EXPECT_TRUE(fresh.solution().allFinite());
    EXPECT_LT(fresh.level(0).residual, 1e-9);  // level 0's answer survives
    // ... and it is exactly level 0's minimum-norm least-squares answer.
    const Eigen::MatrixXd A0 = stack.A().topRows(stack.equalityRows(0));
    const Eigen::VectorXd x0 =
        A0.jacobiSvd(Eigen::ComputeThinU | Eigen::ComputeThinV).solve(stack.b().head(A0.rows()));
    EXPECT_LT((fresh.solution() - x0).cwiseAbs().maxCoeff(), 1e-9);
    return;
  }
  FAIL() << "no stack needed a QP on level 1";
}

TEST(HierarchicalQp, RepeatedSolvesAreWarmAndIdentical) {
  std::mt19937 rng(6);
  const int n = 30;
  TaskStack stack(n, 3, 40, 30);
  HierarchicalQp hqp(n, 3, 12, 30);
  randomStack(stack, 3, 8, 30, 0, rng);
  hqp.solve(stack);
  const Eigen::VectorXd first = hqp.solution();
  const int coldIterations = hqp.totalIterations();
  hqp.solve(stack);
  EXPECT_LT((hqp.solution() - first).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LE(hqp.totalIterations(), coldIterations);
}

}  // namespace
}  // namespace ballast::test
