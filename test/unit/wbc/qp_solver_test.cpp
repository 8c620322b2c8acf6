// The dense QP solver against the KKT conditions, on problems of the whole-body controller's size
// (42 variables, 30 equalities, 40 two-sided inequalities, bounds) and on degenerate ones.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "test/unit/wbc/qp_test_support.hpp"

namespace ballast::test {
namespace {

using wbc::QpCapacity;
using wbc::QpSolver;
using wbc::QpStatus;

constexpr double kTol = 1e-8;

TEST(QpSolver, RandomWbcSizedProblemsMeetTheKktConditions) {
  QpSolver qp(QpCapacity{42, 30, 40});
  std::mt19937 rng(7);
  int activeTotal = 0;
  for (int trial = 0; trial < 200; ++trial) {
    qp.clearWarmStart();
    randomFeasibleQp(qp, 42, 30, 40, rng);
    ASSERT_EQ(qp.solve(), QpStatus::kOptimal) << "trial " << trial << ": " << qp.result().reason;
    const KktReport k = kkt(qp);
    EXPECT_LT(k.worst(), kTol) << "trial " << trial << ": " << k.str();
    EXPECT_NEAR(qp.result().maxViolation, 0.0, kTol);
    activeTotal += qp.result().activeConstraints - 30;
  }
  // The problems are not trivially unconstrained: inequalities and bounds do bind.
  EXPECT_GT(activeTotal, 200 * 3);
}

TEST(QpSolver, SmallerProblemsInTheSameSolver) {
  QpSolver qp(QpCapacity{42, 30, 40});
  std::mt19937 rng(11);
  for (int trial = 0; trial < 100; ++trial) {
    std::uniform_int_distribution<int> dn(1, 42);
    const int n = dn(rng);
    const int me = std::uniform_int_distribution<int>(0, std::min(30, n - 1))(rng);
    const int mi = std::uniform_int_distribution<int>(0, 40)(rng);
    randomFeasibleQp(qp, n, me, mi, rng, trial % 2 == 0);
    ASSERT_EQ(qp.solve(), QpStatus::kOptimal) << n << " " << me << " " << mi;
    EXPECT_LT(kkt(qp).worst(), kTol) << kkt(qp).str();
  }
}

TEST(QpSolver, UnconstrainedAndEqualityOnlyAgreeWithLinearAlgebra) {
  QpSolver qp(QpCapacity{10, 4, 0});
  std::mt19937 rng(3);
  randomFeasibleQp(qp, 10, 0, 0, rng, false);
  ASSERT_EQ(qp.solve(), QpStatus::kOptimal);
  const Eigen::MatrixXd H = qp.H();
  const Eigen::VectorXd g = qp.g();
  EXPECT_LT((qp.x() - (-H.ldlt().solve(g))).norm(), 1e-10);

  randomFeasibleQp(qp, 10, 4, 0, rng, false);
  ASSERT_EQ(qp.solve(), QpStatus::kOptimal);
  // The KKT system [H −Aᵀ; A 0][x; λ] = [−g; b], solved by full-pivot LU.
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(14, 14);
  K.topLeftCorner(10, 10) = qp.H();
  K.topRightCorner(10, 4) = -qp.A().transpose();
  K.bottomLeftCorner(4, 10) = qp.A();
  Eigen::VectorXd rhs(14);
  rhs << -qp.g(), qp.b();
  const Eigen::VectorXd sol = K.fullPivLu().solve(rhs);
  EXPECT_LT((qp.x() - sol.head(10)).norm(), 1e-10);
  EXPECT_LT((qp.equalityMultipliers() - sol.tail(4)).norm(), 1e-9);
}

TEST(QpSolver, WarmStartGivesTheColdAnswerInFewerIterations) {
  QpSolver warm(QpCapacity{42, 30, 40}), cold(QpCapacity{42, 30, 40});
  cold.settings().warmStart = false;
  std::mt19937 rng(5), rngCopy(5);
  randomFeasibleQp(warm, 42, 30, 40, rng);
  ASSERT_EQ(warm.solve(), QpStatus::kOptimal);
  std::normal_distribution<double> small(0.0, 0.05);
  int warmIterations = 0, coldIterations = 0;
  for (int tick = 0; tick < 50; ++tick) {
    // A sequence of nearby problems, as from one control tick to the next.
    for (int i = 0; i < 42; ++i) warm.g()[i] += small(rng);
    for (int i = 0; i < 40; ++i) warm.C()(i, tick % 42) += small(rng);
    cold.resize(42, 30, 40);
    cold.H() = warm.H();
    cold.g() = warm.g();
    cold.A() = warm.A();
    cold.b() = warm.b();
    cold.C() = warm.C();
    cold.lower() = warm.lower();
    cold.upper() = warm.upper();
    cold.lowerBound() = warm.lowerBound();
    cold.upperBound() = warm.upperBound();
    ASSERT_EQ(warm.solve(), QpStatus::kOptimal);
    ASSERT_EQ(cold.solve(), QpStatus::kOptimal);
    EXPECT_LT((warm.x() - cold.x()).cwiseAbs().maxCoeff(), 1e-9) << "tick " << tick;
    EXPECT_LT(kkt(warm).worst(), kTol);
    warmIterations += warm.result().iterations;
    coldIterations += cold.result().iterations;
  }
  EXPECT_LT(warmIterations, coldIterations / 2) << warmIterations << " vs " << coldIterations;
}

TEST(QpSolver, WarmStartFromAnUnrelatedActiveSetStillFindsTheOptimum) {
  QpSolver qp(QpCapacity{42, 30, 40}), reference(QpCapacity{42, 30, 40});
  std::mt19937 rng(21), rng2(21);
  for (int trial = 0; trial < 30; ++trial) {
    randomFeasibleQp(qp, 42, 30, 40, rng);  // warm-started from the previous, unrelated problem
    randomFeasibleQp(reference, 42, 30, 40, rng2);
    reference.clearWarmStart();
    ASSERT_EQ(qp.solve(), QpStatus::kOptimal);
    ASSERT_EQ(reference.solve(), QpStatus::kOptimal);
    EXPECT_LT((qp.x() - reference.x()).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_LT(kkt(qp).worst(), kTol);
  }
}

TEST(QpSolver, ContradictoryInequalitiesAreInfeasible) {
  QpSolver qp(QpCapacity{5, 2, 6});
  qp.resize(5, 0, 2);
  qp.H().setIdentity();
  qp.C().row(0) << 1, 1, 0, 0, 0;  // x0 + x1 ≥ 2
  qp.lower()[0] = 2;
  qp.C().row(1) << 1, 1, 0, 0, 0;  // x0 + x1 ≤ 1
  qp.upper()[1] = 1;
  EXPECT_EQ(qp.solve(), QpStatus::kInfeasible);
  EXPECT_TRUE(qp.x().allFinite());
  EXPECT_GT(qp.result().maxViolation, 0.5);
  EXPECT_STRNE(qp.result().reason, "");
}

TEST(QpSolver, InequalitiesIncompatibleWithEqualitiesAreInfeasible) {
  QpSolver qp(QpCapacity{4, 2, 4});
  qp.resize(4, 1, 2);
  qp.H().setIdentity();
  qp.A().row(0) << 1, 1, 1, 1;  // Σx = 4
  qp.b()[0] = 4;
  qp.lowerBound().setConstant(-1);
  qp.upperBound().setConstant(0.9);  // Σx ≤ 3.6
  EXPECT_EQ(qp.solve(), QpStatus::kInfeasible);
  EXPECT_TRUE(qp.x().allFinite());
  // A random infeasible box inside a feasible-looking problem of WBC size.
  QpSolver big(QpCapacity{42, 30, 40});
  std::mt19937 rng(9);
  randomFeasibleQp(big, 42, 30, 40, rng);
  big.C().row(3) = big.C().row(4);
  big.lower()[3] = big.upper()[4] + 0.5;
  big.upper()[3] = kInf;
  EXPECT_EQ(big.solve(), QpStatus::kInfeasible);
  EXPECT_TRUE(big.x().allFinite());
}

TEST(QpSolver, DependentEqualityRows) {
  QpSolver qp(QpCapacity{6, 5, 2});
  std::mt19937 rng(4);
  randomFeasibleQp(qp, 6, 3, 2, rng, false);
  // Rows 3 and 4: a combination of rows 0..2, consistent.
  const Eigen::MatrixXd A3 = qp.A();
  const Eigen::VectorXd b3 = qp.b();
  const Eigen::MatrixXd H = qp.H();
  const Eigen::VectorXd g = qp.g();
  const Eigen::MatrixXd C = qp.C();
  const Eigen::VectorXd lo = qp.lower(), hi = qp.upper();
  qp.resize(6, 5, 2);
  qp.H() = H;
  qp.g() = g;
  qp.C() = C;
  qp.lower() = lo;
  qp.upper() = hi;
  qp.A().topRows(3) = A3;
  qp.b().head(3) = b3;
  qp.A().row(3) = A3.row(0) + 2.0 * A3.row(2);
  qp.b()[3] = b3[0] + 2.0 * b3[2];
  qp.A().row(4) = -A3.row(1);
  qp.b()[4] = -b3[1];
  ASSERT_EQ(qp.solve(), QpStatus::kOptimal) << qp.result().reason;
  EXPECT_EQ(qp.result().dependentEqualities, 2);
  EXPECT_LT(kkt(qp).worst(), kTol) << kkt(qp).str();
  // The same rows made inconsistent.
  qp.b()[4] += 0.1;
  EXPECT_EQ(qp.solve(), QpStatus::kInfeasible);
  EXPECT_TRUE(qp.x().allFinite());
}

TEST(QpSolver, SemidefiniteHessianIsRegularised) {
  // H = 0: a linear program on a box; the optimum is the corner opposite to g.
  QpSolver qp(QpCapacity{8, 0, 0});
  qp.resize(8, 0, 0);
  qp.g() << 1, -2, 3, -4, 5, -6, 7, -8;
  qp.lowerBound().setConstant(-1);
  qp.upperBound().setConstant(2);
  ASSERT_EQ(qp.solve(), QpStatus::kOptimal);
  EXPECT_TRUE(qp.result().regularized);
  for (int i = 0; i < 8; ++i) EXPECT_NEAR(qp.x()[i], qp.g()[i] > 0 ? -1.0 : 2.0, 1e-7);

  // Rank-deficient H made definite by the equalities on its null space: the unique optimum.
  QpSolver qp2(QpCapacity{4, 2, 0});
  qp2.resize(4, 2, 0);
  qp2.H().diagonal() << 1, 1, 0, 0;
  qp2.g() << 1, 1, 0, 0;
  qp2.A() << 0, 0, 1, 0, 0, 0, 0, 1;
  qp2.b() << 3, -2;
  ASSERT_EQ(qp2.solve(), QpStatus::kOptimal);
  EXPECT_TRUE(qp2.result().regularized);
  const Eigen::Vector4d expected(-1, -1, 3, -2);
  EXPECT_LT((qp2.x() - expected).norm(), 1e-8);
}

TEST(QpSolver, DegenerateVertexWithRedundantActiveConstraints) {
  // Four constraints pass through the optimum (1, 1) in the plane, two of them duplicates.
  QpSolver qp(QpCapacity{2, 0, 5});
  qp.resize(2, 0, 5);
  qp.H().setIdentity();
  qp.g() << 0, 0;
  qp.C() << 1, 0, 0, 1, 1, 1, 1, 1, 2, 2;
  qp.lower() << 1, 1, 2, 2, 4;
  ASSERT_EQ(qp.solve(), QpStatus::kOptimal);
  EXPECT_LT((qp.x() - Eigen::Vector2d(1, 1)).norm(), 1e-10);
  EXPECT_LT(kkt(qp).worst(), 1e-10) << kkt(qp).str();
  // Equal lower and upper sides: an equality written as an inequality.
  qp.resize(2, 0, 1);
  qp.H().setIdentity();
  qp.C() << 1, -1;
  qp.lower() << 0.5;
  qp.upper() << 0.5;
  qp.g() << -3, -3;
  ASSERT_EQ(qp.solve(), QpStatus::kOptimal);
  EXPECT_LT((qp.x() - Eigen::Vector2d(3.25, 2.75)).norm(), 1e-10);
}

TEST(QpSolver, BadInputGivesAFlaggedZeroResult) {
  QpSolver qp(QpCapacity{3, 1, 1});
  qp.resize(3, 1, 1);
  qp.H().setIdentity();
  qp.H()(1, 1) = std::nan("");
  EXPECT_EQ(qp.solve(), QpStatus::kInvalidInput);
  EXPECT_TRUE(qp.x().isZero());

  qp.resize(3, 0, 1);
  qp.H().setIdentity();
  qp.C() << 1, 0, 0;
  qp.lower() << 1;
  qp.upper() << 0;
  EXPECT_EQ(qp.solve(), QpStatus::kInvalidInput);
  EXPECT_NE(std::string(qp.result().reason).find("lower > upper"), std::string::npos);

  qp.resize(3, 0, 0);
  qp.H().diagonal() << 1, -1, 1;  // indefinite
  EXPECT_EQ(qp.solve(), QpStatus::kInvalidInput);
  EXPECT_TRUE(qp.x().allFinite());

  EXPECT_THROW(qp.resize(4, 0, 0), std::invalid_argument);
}

TEST(QpSolver, IterationLimitGivesAFlaggedFiniteResult) {
  QpSolver qp(QpCapacity{42, 30, 40});
  std::mt19937 rng(8);
  randomFeasibleQp(qp, 42, 30, 40, rng);
  qp.settings().maxIterations = 2;
  EXPECT_EQ(qp.solve(), QpStatus::kIterationLimit);
  EXPECT_TRUE(qp.x().allFinite());
  EXPECT_GT(qp.result().maxViolation, 0.0);
  // The equalities hold at every iterate of the dual method.
  EXPECT_LT((qp.A() * qp.x() - qp.b()).cwiseAbs().maxCoeff(), 1e-9);
}

}  // namespace
}  // namespace ballast::test
