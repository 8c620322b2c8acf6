// The SQP: on a linear-quadratic problem one iteration gives the KKT solution; on the paper's
// kino-dynamic problem the linearisation matches finite differences and a standing robot
// converges to static equilibrium.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <tuple>

#include "model/algorithms.hpp"
#include "mpc/kinodynamic_problem.hpp"
#include "mpc/sqp_solver.hpp"
#include "test/unit/allocation_counter.hpp"
#include "test/unit/mpc/lq_test_problems.hpp"
#include "test/unit/settings_support.hpp"
#include "test/unit/test_support.hpp"

namespace ballast::mpc {
namespace {

using model::CentroidalLayout;

/// ẋ = A x + B u + c,  C x + D u + e = 0,  tracking cost.
class LinearProblem final : public OptimalControlProblem {
 public:
  Eigen::MatrixXd Ac, Bc, C, D, Q, R, QN;
  Eigen::VectorXd c, e;
  int nx() const override { return static_cast<int>(Ac.rows()); }
  int nu() const override { return static_cast<int>(Bc.cols()); }
  int maxEqualities() const override { return static_cast<int>(C.rows()); }
  std::unique_ptr<ProblemWorkspace> makeWorkspace() const override {
    return std::make_unique<ProblemWorkspace>();
  }
  void evaluate(ProblemWorkspace&, const NodeReference& ref, const Eigen::VectorXd& x,
                const Eigen::VectorXd& u, double dt, NodeValue& v) const override {
    v.xdot = Ac * x + Bc * u + c;
    v.cost = 0.5 * dt * ((x - ref.x).dot(Q * (x - ref.x)) + (u - ref.u).dot(R * (u - ref.u)));
    v.equalityNorm2 = (C * x + D * u + e).squaredNorm();
  }
  void linearize(ProblemWorkspace& ws, const NodeReference& ref, const Eigen::VectorXd& x,
                 const Eigen::VectorXd& u, double dt, LqNode& n, NodeValue& v) const override {
    evaluate(ws, ref, x, u, dt, v);
    n.A = Eigen::MatrixXd::Identity(nx(), nx()) + dt * Ac;
    n.B = dt * Bc;
    n.neq = maxEqualities();
    n.C = C;
    n.D = D;
    n.e = C * x + D * u + e;
    n.Q = dt * Q;
    n.R = dt * R;
    n.S.setZero();
    n.q = dt * Q * (x - ref.x);
    n.r = dt * R * (u - ref.u);
  }
  double terminalCost(ProblemWorkspace& /*ws*/, const NodeReference& ref, const Eigen::VectorXd& x,
                      LqNode* n) const override {
    if (n) {
      n->setZero();
      n->Q = QN;
      n->q = QN * (x - ref.x);
    }
    return 0.5 * (x - ref.x).dot(QN * (x - ref.x));
  }
};

TEST(Sqp, OneIterationSolvesALinearQuadraticProblem) {
  std::mt19937 rng(9);
  std::normal_distribution<double> n(0, 1);
  auto rnd = [&](int r, int c) { return Eigen::MatrixXd::NullaryExpr(r, c, [&] { return n(rng); }); };
  LinearProblem p;
  const int nx = 5, nu = 4, N = 20;
  p.Ac = 0.5 * rnd(nx, nx);
  p.Bc = rnd(nx, nu);
  p.c = rnd(nx, 1);
  p.C = rnd(2, nx);
  p.D = rnd(2, nu);
  p.e = rnd(2, 1);
  const Eigen::MatrixXd Lq = rnd(nx, nx), Lr = rnd(nu, nu);
  p.Q = Lq * Lq.transpose() + Eigen::MatrixXd::Identity(nx, nx);
  p.R = Lr * Lr.transpose() + Eigen::MatrixXd::Identity(nu, nu);
  p.QN = 3.0 * p.Q;
  SqpSettings settings = test::controlDefaults().locomotion.sqp;
  settings.nodes = N;
  settings.dt = 0.05;
  SqpSolver sqp(p, settings);
  for (auto& r : sqp.references()) {
    r.x = rnd(nx, 1);
    r.u = rnd(nu, 1);
  }
  const Eigen::VectorXd x0 = rnd(nx, 1);
  ASSERT_TRUE(sqp.iterate(0.0, x0)) << sqp.statistics().message;
  EXPECT_DOUBLE_EQ(sqp.statistics().step, 1.0);

  // The same problem as one LQ in absolute variables, solved by a KKT system.
  std::vector<LqNode> nodes(N + 1, LqNode(nx, nu, 2));
  for (int k = 0; k <= N; ++k) {
    const NodeReference& r = sqp.references()[k];
    if (k == N) {
      nodes[k].Q = p.QN;
      nodes[k].q = -p.QN * r.x;
      break;
    }
    nodes[k].A = Eigen::MatrixXd::Identity(nx, nx) + settings.dt * p.Ac;
    nodes[k].B = settings.dt * p.Bc;
    nodes[k].b = settings.dt * p.c;
    nodes[k].neq = 2;
    nodes[k].C = p.C;
    nodes[k].D = p.D;
    nodes[k].e = p.e;
    nodes[k].Q = settings.dt * p.Q;
    nodes[k].R = settings.dt * p.R;
    nodes[k].q = -settings.dt * p.Q * r.x;
    nodes[k].r = -settings.dt * p.R * r.u;
  }
  std::vector<Eigen::VectorXd> x, u;
  testing::solveByKkt(nodes, x0, x, u);
  const MpcSolution& s = sqp.solution();
  for (int k = 0; k <= N; ++k) EXPECT_LT((s.x[k] - x[k]).norm(), 1e-8 * (1 + x[k].norm())) << k;
  for (int k = 0; k < N; ++k) EXPECT_LT((s.u[k] - u[k]).norm(), 1e-8 * (1 + u[k].norm())) << k;
  EXPECT_LT(sqp.statistics().violation, 1e-9);
}

TEST(Sqp, ARankDeficientEqualityFailsTheIterationAndNamesTheFirstNode) {
  // The backward sweep runs behind the projections, from the last node down: a node whose
  // equalities no input can meet stops it, and the iteration reports the first such node.
  LinearProblem p;
  const int nx = 3, nu = 2, N = 12;
  p.Ac = Eigen::MatrixXd::Identity(nx, nx);
  p.Bc = Eigen::MatrixXd::Ones(nx, nu);
  p.c = Eigen::VectorXd::Zero(nx);
  p.C = Eigen::MatrixXd::Ones(1, nx);
  p.D = Eigen::MatrixXd::Zero(1, nu);  // a row without inputs
  p.e = Eigen::VectorXd::Ones(1);
  p.Q = p.QN = Eigen::MatrixXd::Identity(nx, nx);
  p.R = Eigen::MatrixXd::Identity(nu, nu);
  SqpSettings settings = test::controlDefaults().locomotion.sqp;
  settings.nodes = N;
  settings.dt = 0.05;
  settings.threads = 2;
  SqpSolver sqp(p, settings);
  for (auto& r : sqp.references()) {
    r.x = Eigen::VectorXd::Zero(nx);
    r.u = Eigen::VectorXd::Zero(nu);
  }
  EXPECT_FALSE(sqp.iterate(0.0, Eigen::VectorXd::Ones(nx)));
  EXPECT_NE(sqp.statistics().message.find("at node 0 "), std::string::npos)
      << sqp.statistics().message;
}

class Kinodynamic : public ::testing::Test {
 protected:
  const model::Model& m = test::humanoid();
  const std::array<int, kNumContacts> frames{m.frameId("left_toe"), m.frameId("left_heel"),
                                             m.frameId("right_toe"), m.frameId("right_heel")};
  const CentroidalLayout L{m.nj(), kNumContacts};
  model::VecX<double> qStand = test::standingConfiguration(m);

  /// soleWidth > 0: soles with width, and their moments' input weights.
  ProblemSettings settings(double soleWidth = 0.0) const {
    ProblemSettings s = test::controlDefaults().locomotion.problem;
    s.soleWidth = soleWidth;
    const int nu = L.nu() + KinodynamicProblem::soleMoments(s);
    s.stateWeights = Eigen::VectorXd::Constant(L.nx(), 1.0);
    s.stateWeights.segment<6>(0).setConstant(10.0);
    s.stateWeights.segment<6>(L.kBasePosition).setConstant(500.0);
    s.stateWeights.segment(L.kJoints, m.nj()).setConstant(20.0);
    s.inputWeights = Eigen::VectorXd::Constant(nu, 1e-3);
    s.inputWeights.segment(L.jointVelocity(), m.nj()).setConstant(1.0);
    return s;
  }
  /// x for the standing configuration q with momentum h.
  Eigen::VectorXd stateOf(const model::VecX<double>& q, const model::Vec6<double>& h) const {
    Eigen::VectorXd x(L.nx());
    x << h, q.head<3>(), model::zyxFromRotation(model::quaternionToRotation<double>(q.segment<4>(3))),
        q.tail(m.nj());
    return x;
  }
  /// For a problem of `nu` inputs.
  NodeReference standingReference(int nu) const {
    NodeReference r;
    r.x = stateOf(qStand, model::Vec6<double>::Zero());
    r.u = Eigen::VectorXd::Zero(nu);
    for (int c = 0; c < 4; ++c) r.u[L.force(c) + 2] = m.totalMass() * 9.81 / 4;
    return r;
  }
  /// Standing on the right foot in the standing posture, the left one held where it is.
  NodeReference rightFootReference(int nu) const {
    model::Data<double> d(m);
    model::forwardKinematics(m, d, qStand);
    NodeReference r = standingReference(nu);
    r.stance = {false, false, true, true};
    r.u.setZero();
    for (int c : {2, 3}) r.u[L.force(c) + 2] = m.totalMass() * 9.81 / 2;
    for (int c : {0, 1}) {
      r.swingPosition[c] = model::framePlacement(m, d, frames[c]).p;
      r.swingVelocity[c].setZero();
    }
    return r;
  }
};

TEST_F(Kinodynamic, LinearizationMatchesFiniteDifferences) {
  // Soles with width: the standing right sole's moment in the dynamics and its barrier.
  KinodynamicProblem problem(m, frames, settings(0.1));
  const int nu = problem.nu();
  auto ws = problem.makeWorkspace();
  std::mt19937 rng(2);
  std::normal_distribution<double> n(0, 1);
  NodeReference ref = standingReference(problem.nu());
  ref.stance = {false, false, true, true};  // left foot swinging
  for (int c : {0, 1}) {
    ref.swingPosition[c] = Eigen::Vector3d(0.1 * n(rng), 0.1 + 0.05 * n(rng), 0.05);
    ref.swingVelocity[c] = Eigen::Vector3d(n(rng), 0.1 * n(rng), 0.3 * n(rng));
  }
  Eigen::VectorXd x = ref.x, u = ref.u;
  for (int i = 0; i < 6; ++i) x[i] += 5 * n(rng);
  for (int i = L.kBaseZyx; i < L.nx(); ++i) x[i] += 0.05 * n(rng);
  for (int i = 0; i < 12; ++i) u[i] += 20 * n(rng);
  for (int i = 12; i < nu; ++i) u[i] = 0.3 * n(rng);
  u[problem.soleMoment(1)] = 15.0;  // the right sole's, within its barrier's reach
  const double dt = 0.02;
  LqNode node(L.nx(), nu, problem.maxEqualities()), probe = node;
  NodeValue value, probeValue;
  problem.linearize(*ws, ref, x, u, dt, node, value);
  EXPECT_EQ(node.neq, 10 + 6 + 1);  // contact velocities, swing forces, the lifted sole's moment

  const double h = 1e-6;
  Eigen::MatrixXd Cfd(node.neq, L.nx()), Dfd(node.neq, nu), Afd(L.nx(), L.nx()), Bfd(L.nx(), nu);
  Eigen::VectorXd qfd(L.nx()), rfd(nu);
  auto column = [&](Eigen::VectorXd& xp, Eigen::VectorXd& up, Eigen::VectorXd& xm, Eigen::VectorXd& um,
                    auto&& A, auto&& C, double& g) {
    problem.linearize(*ws, ref, xp, up, dt, probe, probeValue);
    const Eigen::VectorXd ep = probe.e.head(node.neq), fp = probeValue.xdot;
    const double cp = probeValue.cost;
    problem.linearize(*ws, ref, xm, um, dt, probe, probeValue);
    C = (ep - probe.e.head(node.neq)) / (2 * h);
    A = dt * (fp - probeValue.xdot) / (2 * h);
    g = (cp - probeValue.cost) / (2 * h);
  };
  for (int i = 0; i < L.nx(); ++i) {
    Eigen::VectorXd xp = x, xm = x, uu = u;
    xp[i] += h;
    xm[i] -= h;
    column(xp, uu, xm, uu, Afd.col(i), Cfd.col(i), qfd[i]);
    Afd(i, i) += 1.0;
  }
  for (int i = 0; i < nu; ++i) {
    Eigen::VectorXd up = u, um = u, xx = x;
    up[i] += h;
    um[i] -= h;
    column(xx, up, xx, um, Bfd.col(i), Dfd.col(i), rfd[i]);
  }
  auto close = [](const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, double tol) {
    return (a - b).cwiseAbs().maxCoeff() <= tol * std::max(1.0, b.cwiseAbs().maxCoeff());
  };
  EXPECT_TRUE(close(node.A, Afd, 1e-6));
  EXPECT_TRUE(close(node.B, Bfd, 1e-6));
  EXPECT_TRUE(close(node.C.topRows(node.neq), Cfd, 1e-6)) << (node.C.topRows(node.neq) - Cfd).cwiseAbs().maxCoeff();
  EXPECT_TRUE(close(node.D.topRows(node.neq), Dfd, 1e-6)) << (node.D.topRows(node.neq) - Dfd).cwiseAbs().maxCoeff();
  EXPECT_TRUE(close(node.q, qfd, 1e-5)) << (node.q - qfd).cwiseAbs().maxCoeff();
  EXPECT_TRUE(close(node.r, rfd, 1e-5)) << (node.r - rfd).cwiseAbs().maxCoeff();
  // The value path gives the same cost and equality residual as the linearisation.
  NodeValue v;
  problem.evaluate(*ws, ref, x, u, dt, v);
  EXPECT_DOUBLE_EQ(v.cost, value.cost);
  EXPECT_NEAR(v.equalityNorm2, node.e.head(node.neq).squaredNorm(), 1e-12);
}

TEST_F(Kinodynamic, AlternatingJointVelocitiesDoNotSteerTheBase) {
  // Two nodes with opposite joint velocities return the joints where they were. Physically the
  // base turns back too (one joint at a time has no geometric phase); explicit Euler leaves it
  // turned by O(dt²·v²), a free actuator the optimiser once used by chattering at the velocity
  // limits. The midpoint discretisation removes that term; what is left is of third order in
  // dt·v (0.2 rad here), so at least 4 times smaller.
  KinodynamicProblem problem(m, frames, settings());
  auto ws = problem.makeWorkspace();
  const NodeReference ref = standingReference(problem.nu());
  const Eigen::VectorXd x0 = stateOf(qStand, model::Vec6<double>::Zero());
  const double dt = 0.02, w = 10.0;
  model::Data<double> d(m);
  const std::vector<int> contacts(frames.begin(), frames.end());
  for (const char* joint : {"left_shoulder_pitch", "right_shoulder_roll", "left_hip_roll"}) {
    Eigen::VectorXd up = Eigen::VectorXd::Zero(problem.nu()), down = up;
    up[L.jointVelocity() + m.jointId(joint)] = w;
    down[L.jointVelocity() + m.jointId(joint)] = -w;
    NodeValue v;
    Eigen::VectorXd mid = x0;
    problem.evaluate(*ws, ref, mid, up, dt, v);
    mid += dt * v.xdot;
    problem.evaluate(*ws, ref, mid, down, dt, v);
    mid += dt * v.xdot;
    Eigen::VectorXd euler = x0, xdot(L.nx());
    model::centroidalDynamics(m, d, contacts, euler, up, xdot);
    euler += dt * xdot;
    model::centroidalDynamics(m, d, contacts, euler, down, xdot);
    euler += dt * xdot;
    ASSERT_LT((mid.tail(m.nj()) - x0.tail(m.nj())).norm(), 1e-12) << joint;
    const double turnedMid = (mid.segment<3>(L.kBaseZyx) - x0.segment<3>(L.kBaseZyx)).norm();
    const double turnedEuler = (euler.segment<3>(L.kBaseZyx) - x0.segment<3>(L.kBaseZyx)).norm();
    std::printf("%s: base turned %.2e rad (Euler %.2e rad)\n", joint, turnedMid, turnedEuler);
    EXPECT_GT(turnedEuler, 1e-3) << joint << ": the test needs an exploit to remove";
    EXPECT_LT(turnedMid, 0.25 * turnedEuler) << joint;
  }
}

TEST_F(Kinodynamic, StandingConvergesToStaticEquilibrium) {
  KinodynamicProblem problem(m, frames, settings());
  SqpSettings settings = test::controlDefaults().locomotion.sqp;
  settings.nodes = 25;
  settings.dt = 0.04;
  SqpSolver sqp(problem, settings);
  for (auto& r : sqp.references()) r = standingReference(problem.nu());
  // Start off balance: base 2 cm aside, some momentum.
  model::VecX<double> q = qStand;
  q[1] += 0.02;
  model::Vec6<double> h;
  h << 3.0, -2.0, 1.0, 0.5, 0.2, 0.0;
  const Eigen::VectorXd x0 = stateOf(q, h);
  for (int it = 0; it < 15; ++it) {
    const bool ok = sqp.iterate(0.0, x0);
    ASSERT_TRUE(ok) << it << ": " << sqp.statistics().message;
  }
  const MpcSolution& s = sqp.solution();
  EXPECT_LT(sqp.statistics().violation, 1e-5);
  // At the end of the horizon the robot is at rest: forces carry the weight, no net torque,
  // momentum gone.
  const Eigen::VectorXd& u = s.u.back();
  double fz = 0;
  for (int c = 0; c < 4; ++c) {
    fz += u[L.force(c) + 2];
    EXPECT_GT(u[L.force(c) + 2], 0.0);  // every point pushes
  }
  EXPECT_NEAR(fz, m.totalMass() * 9.81, 0.01 * m.totalMass() * 9.81);
  EXPECT_LT(s.x.back().head<6>().norm(), 0.5);
  model::Data<double> d(m);
  Eigen::VectorXd xdot(L.nx());
  model::centroidalDynamics(m, d, std::vector<int>(frames.begin(), frames.end()), s.x.back(), u, xdot);
  EXPECT_LT(xdot.head<3>().norm(), 0.02 * m.totalMass() * 9.81);
  EXPECT_LT(xdot.segment<3>(3).norm(), 2.0);
  // The first node is the measured state, held.
  EXPECT_LT((s.x[0] - x0).norm(), 1e-12);
}

TEST_F(Kinodynamic, AFootStandingAloneHoldsTheBodyBesideItsToeHeelLineWithItsSole) {
  // Standing as on both feet, the left one lifted: the centre of mass is beside the right foot's
  // toe-heel line, and only a moment about that line holds the body still (toe and heel forces
  // lie on it): m = m g · (the centre of mass's distance from the line). A sole wide enough to
  // give it (0.3 m: half of it times m g is more than that).
  KinodynamicProblem problem(m, frames, settings(0.3));
  SqpSettings settings = test::controlDefaults().locomotion.sqp;
  settings.nodes = 25;
  settings.dt = 0.04;
  SqpSolver sqp(problem, settings);
  model::Data<double> d(m);
  model::forwardKinematics(m, d, qStand);
  model::compositeWorldInertias(m, d);
  const double line = 0.5 * (model::framePlacement(m, d, frames[2]).p.y() +
                             model::framePlacement(m, d, frames[3]).p.y());
  const double offset = d.com.y() - line;  // > 0: left of the right foot
  ASSERT_GT(offset, 0.05);
  const Eigen::VectorXd x0 = stateOf(qStand, model::Vec6<double>::Zero());
  for (auto& r : sqp.references()) r = rightFootReference(problem.nu());
  for (int it = 0; it < 15; ++it) ASSERT_TRUE(sqp.iterate(0.0, x0)) << it << ": " << sqp.statistics().message;
  const MpcSolution& s = sqp.solution();
  EXPECT_LT(sqp.statistics().violation, 1e-5);
  const double held = offset * m.totalMass() * 9.81;
  for (std::size_t k = 0; k < s.u.size(); ++k) {
    SCOPED_TRACE(k);
    EXPECT_LT((s.x[k].segment<2>(L.kBasePosition) - x0.segment<2>(L.kBasePosition)).norm(), 0.005);
    EXPECT_LT(s.x[k].head<6>().norm(), 1.0);  // at rest
    EXPECT_NEAR(s.u[k][problem.soleMoment(1)], held, 0.1 * held);
    EXPECT_EQ(s.u[k][problem.soleMoment(0)], 0.0);  // the lifted foot's
  }
}

TEST_F(Kinodynamic, ASolveIteratesWhileThePlanIsFarFromFeasible) {
  // Standing on one foot from a cold start, as above: the first iteration's plan is far from
  // feasible. solve() iterates again while the violation is over the tolerance, up to its
  // maximum, and its plan is the one as many iterate() calls give, to the bit.
  KinodynamicProblem problem(m, frames, settings(0.3));
  SqpSettings s = test::controlDefaults().locomotion.sqp;
  s.nodes = 25;
  s.dt = 0.04;
  s.maxIterations = 10;
  s.violationTolerance = 1e-3;
  const Eigen::VectorXd x0 = stateOf(qStand, model::Vec6<double>::Zero());
  const NodeReference ref = rightFootReference(problem.nu());
  SqpSolver solving(problem, s), iterating(problem, s);
  for (auto& r : solving.references()) r = ref;
  for (auto& r : iterating.references()) r = ref;
  ASSERT_TRUE(solving.solve(0.0, x0)) << solving.statistics().message;
  const int n = solving.statistics().iterations;
  EXPECT_GT(n, 1);
  EXPECT_LT(n, s.maxIterations);
  EXPECT_LE(solving.statistics().violation, s.violationTolerance);
  for (int it = 0; it < n; ++it) {
    if (it > 0) EXPECT_GT(iterating.statistics().violation, s.violationTolerance) << it;
    ASSERT_TRUE(iterating.iterate(0.0, x0)) << it << ": " << iterating.statistics().message;
  }
  EXPECT_EQ(solving.statistics().violation, iterating.statistics().violation);
  for (std::size_t k = 0; k < solving.solution().u.size(); ++k) {
    EXPECT_EQ((solving.solution().x[k] - iterating.solution().x[k]).norm(), 0.0) << k;
    EXPECT_EQ((solving.solution().u[k] - iterating.solution().u[k]).norm(), 0.0) << k;
  }
  // At most maxIterations; and none past the first once the plan is within the tolerance.
  for (const auto& [maxIterations, tolerance, expected] :
       {std::tuple{2, 1e-3, 2}, std::tuple{10, 1e9, 1}, std::tuple{1, 1e-3, 1}}) {
    s.maxIterations = maxIterations;
    s.violationTolerance = tolerance;
    SqpSolver once(problem, s);
    for (auto& r : once.references()) r = ref;
    ASSERT_TRUE(once.solve(0.0, x0)) << once.statistics().message;
    EXPECT_EQ(once.statistics().iterations, expected) << maxIterations << " " << tolerance;
  }
  // A wall-time budget spent by the first iteration: no other.
  s.maxIterations = 10;
  s.violationTolerance = 1e-3;
  SqpSolver hurried(problem, s);
  for (auto& r : hurried.references()) r = ref;
  ASSERT_TRUE(hurried.solve(0.0, x0, 1e-9)) << hurried.statistics().message;
  EXPECT_EQ(hurried.statistics().iterations, 1);
}

TEST_F(Kinodynamic, TheSolutionIsTheSameOnOneThreadAsOnSeveral) {
  // Nodes are projected on any thread and the backward sweep follows them on the caller's: the
  // arithmetic must not depend on who did what, so plans are bit-identical whatever the cores.
  KinodynamicProblem problem(m, frames, settings());
  std::vector<MpcSolution> solutions;
  for (int threads : {1, 2, 3}) {
    SqpSettings s = test::controlDefaults().locomotion.sqp;
    s.nodes = 30;
    s.dt = 0.02;
    s.threads = threads;
    SqpSolver sqp(problem, s);
    for (auto& r : sqp.references()) r = standingReference(problem.nu());
    model::VecX<double> q = qStand;
    q[1] += 0.03;
    model::Vec6<double> h;
    h << 5.0, -3.0, 1.0, 0.8, 0.3, -0.2;
    for (int it = 0; it < 4; ++it) ASSERT_TRUE(sqp.iterate(0.01 * it, stateOf(q, h))) << threads;
    solutions.push_back(sqp.solution());
  }
  for (size_t i = 1; i < solutions.size(); ++i)
    for (int k = 0; k <= 30; ++k) {
      ASSERT_EQ(solutions[i].x[k], solutions[0].x[k]) << "threads " << i + 1 << ", node " << k;
      if (k < 30) {
        ASSERT_EQ(solutions[i].u[k], solutions[0].u[k]) << "threads " << i + 1 << ", node " << k;
      }
    }
}

TEST_F(Kinodynamic, APreparedIterationGivesThePlanOfAnUnpreparedOneToTheBit) {
  // SqpSolver::prepare linearises, projects and sweeps, at the warm start of the next grid in
  // the contact modes expected there, all that does not depend on the rest of the references;
  // the iteration computes that rest, and whole the nodes whose point or mode is not the one
  // prepared. A walking horizon (soles with width) whose swings move with time; once, the
  // schedule is not the one expected (a step comes sooner, as the step timing does it).
  KinodynamicProblem problem(m, frames, settings(0.1));
  SqpSettings s = test::controlDefaults().locomotion.sqp;
  s.nodes = 30;
  s.dt = 0.02;
  s.threads = 2;
  SqpSolver plain(problem, s), prepared(problem, s);
  model::Data<double> d(m);
  model::forwardKinematics(m, d, qStand);
  auto walk = [&](SqpSolver& sqp, double t0, double sooner) {
    for (int k = 0; k <= s.nodes; ++k) {
      NodeReference& r = sqp.references()[k];
      r = standingReference(problem.nu());
      if (std::fmod(t0 + k * s.dt + sooner, 0.3) < 0.15) continue;  // both feet stand
      r.stance = {false, false, true, true};
      for (int c : {0, 1}) {
        r.u[L.force(c) + 2] = 0.0;
        r.swingPosition[c] =
            model::framePlacement(m, d, frames[c]).p + Eigen::Vector3d(0.0, 0.0, 0.03);
        r.swingVelocity[c] = Eigen::Vector3d(0.0, 0.0, 0.1);
      }
      for (int c : {2, 3}) r.u[L.force(c) + 2] = m.totalMass() * 9.81 / 2;
    }
  };
  model::Vec6<double> h;
  h << 4.0, -2.0, 1.0, 0.5, 0.3, -0.2;
  const int unexpected = 4;  // the iteration whose schedule moved
  double sooner = 0.0;
  for (int it = 0; it < 8; ++it) {
    SCOPED_TRACE(it);
    const double t0 = 0.01 * it;
    if (it > 0) {
      walk(prepared, t0, sooner);
      prepared.prepare(t0);
    }
    if (it == unexpected) sooner = 0.05;
    walk(plain, t0, sooner);
    walk(prepared, t0, sooner);
    const Eigen::VectorXd x0 = stateOf(qStand, (1.0 - 0.1 * it) * h);
    ASSERT_TRUE(plain.iterate(t0, x0)) << plain.statistics().message;
    ASSERT_TRUE(prepared.iterate(t0, x0)) << prepared.statistics().message;
    for (int k = 0; k <= s.nodes; ++k) {
      ASSERT_EQ(prepared.solution().x[k], plain.solution().x[k]) << "node " << k;
      if (k < s.nodes) {
        ASSERT_EQ(prepared.solution().u[k], plain.solution().u[k]) << "node " << k;
      }
    }
    // Used on every node but the measured one where the expectation held, on none before the
    // first that changed in the sweep where it did not.
    const SqpStatistics& st = prepared.statistics();
    if (it == 0) {
      EXPECT_EQ(st.preparedNodes, 0);
    } else if (it != unexpected) {
      EXPECT_EQ(st.preparedNodes, s.nodes - 1);
      EXPECT_EQ(st.preparedSweeps, s.nodes - 1);
    } else {
      EXPECT_GT(st.preparedNodes, s.nodes / 2);
      EXPECT_LT(st.preparedNodes, s.nodes - 1);
      EXPECT_LT(st.preparedSweeps, st.preparedNodes);
    }
  }
  // A start time off by less than SqpSolver::kSameTime (rounding: times are sums of periods)
  // is the one prepared for.
  const double t0 = 0.08;
  walk(prepared, t0, sooner);
  prepared.prepare(t0 + 1e-9);
  ASSERT_TRUE(prepared.iterate(t0, stateOf(qStand, model::Vec6<double>::Zero())));
  EXPECT_EQ(prepared.statistics().preparedNodes, s.nodes - 1);
}

TEST_F(Kinodynamic, AnIterationAllocatesNothingOnceItsNodesHaveTheirSizes) {
  // The planner runs on a real-time thread: once the first iterations have sized each node's
  // matrices for its contact mode, an SQP iteration (linearisation, projection, sweep, line
  // search) allocates nothing. A walking horizon: the left foot swings over the first nodes,
  // both feet stand over the rest, on soles with width (their moments' equalities too).
  KinodynamicProblem problem(m, frames, settings(0.1));
  SqpSettings s = test::controlDefaults().locomotion.sqp;
  s.nodes = 30;
  s.dt = 0.02;
  s.threads = 1;  // the counter watches this thread
  SqpSolver sqp(problem, s);
  model::Data<double> d(m);
  model::forwardKinematics(m, d, qStand);
  for (int k = 0; k <= s.nodes; ++k) {
    NodeReference& r = sqp.references()[k];
    r = standingReference(problem.nu());
    if (k >= s.nodes / 2) continue;
    r.stance = {false, false, true, true};
    for (int c : {0, 1}) {
      r.u[L.force(c) + 2] = 0.0;
      r.swingPosition[c] = model::framePlacement(m, d, frames[c]).p + Eigen::Vector3d(0.0, 0.0, 0.03);
      r.swingVelocity[c] = Eigen::Vector3d(0.0, 0.0, 0.1);
    }
  }
  model::VecX<double> q = qStand;
  q[1] += 0.02;
  model::Vec6<double> h;
  h << 3.0, -2.0, 1.0, 0.5, 0.2, 0.0;
  const Eigen::VectorXd x0 = stateOf(q, h);
  for (int it = 0; it < 3; ++it) ASSERT_TRUE(sqp.iterate(0.0, x0)) << sqp.statistics().message;
  bool ok = false;
  EXPECT_EQ(test::allocationsIn([&] { ok = sqp.iterate(0.0, x0); }), 0);
  EXPECT_TRUE(ok) << sqp.statistics().message;
  EXPECT_GT(sqp.statistics().step, 0.0);  // a step was taken: the line search ran its trials
}

}  // namespace
}  // namespace ballast::mpc
