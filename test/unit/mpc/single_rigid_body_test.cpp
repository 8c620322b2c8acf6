// The paper's cI planner (mpc/single_rigid_body_problem.hpp): its dynamics are the kino-dynamic
// problem's for a robot whose limbs stay at the nominal posture and do not move, at the rotation
// it is linearised about; its linearisation is the dynamics' and the cost's derivatives; its LQ
// subproblem over a walking horizon is solved to the KKT conditions by the Riccati sweep; the
// SQP's real-time iterations converge onto its dynamics with no force on a swing and the stance
// forces inside the cone.
#include <gtest/gtest.h>

#include <random>

#include "locomotion/locomotion_planner.hpp"
#include "model/algorithms.hpp"
#include "mpc/riccati_solver.hpp"
#include "mpc/single_rigid_body_problem.hpp"
#include "mpc/sqp_solver.hpp"
#define BALLAST_ALLOCATION_COUNTER_ELSEWHERE  // sqp_test.cpp defines the counting malloc
#include "test/unit/allocation_counter.hpp"
#include "test/unit/mpc/lq_test_problems.hpp"
#include "test/unit/settings_support.hpp"
#include "test/unit/test_support.hpp"

namespace ballast::mpc {
namespace {

using model::CentroidalLayout;

class SingleRigidBody : public ::testing::Test {
 protected:
  const model::Model& m = test::humanoid();
  const std::vector<int> frames{m.frameId("left_toe"), m.frameId("left_heel"),
                                m.frameId("right_toe"), m.frameId("right_heel")};
  const CentroidalLayout L{m.nj(), kNumContacts};
  const model::VecX<double> qStand = test::standingConfiguration(m);
  const Eigen::VectorXd posture = qStand.tail(m.nj());
  const RigidBody body = locomotion::LocomotionPlanner::nominalBody(m, posture);

  ProblemSettings settings() const {
    ProblemSettings s = test::controlDefaults().locomotion.problem;
    s.stateWeights = Eigen::VectorXd::Constant(12, 1.0);
    s.stateWeights.segment<6>(0).setConstant(10.0 / (body.mass * body.mass));
    s.stateWeights.segment<6>(CentroidalLayout::kBasePosition).setConstant(500.0);
    s.inputWeights = Eigen::VectorXd::Constant(12, 1e-3);
    return s;
  }
};

TEST_F(SingleRigidBody, IsTheCentroidalDynamicsOfARobotWhoseLimbsDoNotMove) {
  SingleRigidBodyProblem problem(body, settings());
  EXPECT_NEAR(body.mass, m.totalMass(), 1e-12);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  model::Data<double> data(m);
  for (int trial = 0; trial < 20; ++trial) {
    // Any base pose and momentum, the limbs at the posture, any forces.
    Eigen::VectorXd x(L.nx()), uFull = Eigen::VectorXd::Zero(L.nu());
    x.head<6>() = 30.0 * Eigen::Matrix<double, 6, 1>::NullaryExpr([&] { return u(rng); });
    x.segment<3>(L.kBasePosition) = Eigen::Vector3d(u(rng), u(rng), 0.8 + 0.1 * u(rng));
    x.segment<3>(L.kBaseZyx) = Eigen::Vector3d(3.0 * u(rng), 0.3 * u(rng), 0.3 * u(rng));
    x.tail(m.nj()) = posture;
    uFull.head(12) = 200.0 * Eigen::VectorXd::NullaryExpr(12, [&] { return u(rng); });
    Eigen::VectorXd kino(L.nx());
    model::centroidalDynamics(m, data, frames, x, uFull, kino);  // leaves the kinematics in data

    // Linearised about this very state, with the points where the robot has them.
    NodeReference ref;
    ref.x = x.head(12);
    ref.u = Eigen::VectorXd::Zero(12);
    for (int c = 0; c < kNumContacts; ++c)
      ref.contactPosition[c] = model::framePlacement(m, data, frames[c]).p;
    const auto workspace = problem.makeWorkspace();
    ProblemWorkspace& ws = *workspace;
    NodeValue value;
    problem.evaluate(ws, ref, x.head(12), uFull.head(12), 0.02, value);
    EXPECT_LT((value.xdot - kino.head(12)).cwiseAbs().maxCoeff(),
              1e-9 * (1.0 + kino.head(12).cwiseAbs().maxCoeff()))
        << "trial " << trial << "\nsrbd " << value.xdot.transpose() << "\nkino "
        << kino.head(12).transpose();
    EXPECT_LT(kino.tail(m.nj()).norm(), 1e-12);  // the limbs indeed stay

    // At another reference rotation it is the model linearised there, no longer the robot: the
    // rotation enters only through R*.
    NodeReference turned = ref;
    turned.x[L.kBaseZyx] += 0.5;
    problem.evaluate(ws, turned, x.head(12), uFull.head(12), 0.02, value);
    EXPECT_GT((value.xdot - kino.head(12)).norm(), 1e-3) << "trial " << trial;
  }
}

TEST_F(SingleRigidBody, LinearizationIsTheDynamicsAndItsCostDerivatives) {
  SingleRigidBodyProblem problem(body, settings());
  NodeReference ref;
  ref.x = Eigen::VectorXd::Zero(12);
  ref.x.segment<3>(L.kBasePosition) = qStand.head<3>();
  ref.x[L.kBaseZyx] = 0.3;
  ref.u = Eigen::VectorXd::Zero(12);
  ref.stance = {true, true, false, false};
  for (int c = 0; c < kNumContacts; ++c) ref.contactPosition[c] = Eigen::Vector3d(0.1 * (c % 2), 0.1 - 0.2 * (c / 2), 0.0);
  for (int c : {0, 1}) ref.u[3 * c + 2] = body.mass * 9.81 / 2;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  Eigen::VectorXd x = ref.x + 0.1 * Eigen::VectorXd::NullaryExpr(12, [&] { return d(rng); });
  Eigen::VectorXd u = ref.u + 20.0 * Eigen::VectorXd::NullaryExpr(12, [&] { return d(rng); });
  const double dt = 0.02;
  const auto workspace = problem.makeWorkspace();
  ProblemWorkspace& ws = *workspace;
  LqNode node(12, 12, problem.maxEqualities());
  NodeValue value, probe;
  problem.linearize(ws, ref, x, u, dt, node, value);
  ASSERT_EQ(node.neq, 6);  // the right foot's two points carry no force
  EXPECT_LT((node.D.topRows(6) * u - node.e.head(6)).norm(), 1e-12);  // e = f of the swing points
  const double h = 1e-6;
  for (int i = 0; i < 24; ++i) {
    Eigen::VectorXd xp = x, xm = x, up = u, um = u;
    (i < 12 ? xp[i] : up[i - 12]) += h;
    (i < 12 ? xm[i] : um[i - 12]) -= h;
    problem.evaluate(ws, ref, xp, up, dt, probe);
    const Eigen::VectorXd fp = probe.xdot;
    const double cp = probe.cost;
    problem.evaluate(ws, ref, xm, um, dt, probe);
    const Eigen::VectorXd column = dt * (fp - probe.xdot) / (2 * h);
    const Eigen::VectorXd expected = i < 12 ? Eigen::VectorXd(node.A.col(i) - Eigen::VectorXd::Unit(12, i))
                                            : Eigen::VectorXd(node.B.col(i - 12));
    EXPECT_LT((column - expected).cwiseAbs().maxCoeff(), 1e-8) << "column " << i;
    const double gradient = (cp - probe.cost) / (2 * h);
    EXPECT_NEAR(gradient, i < 12 ? node.q[i] : node.r[i - 12], 1e-5 * (1.0 + std::abs(gradient))) << i;
  }
}

/// A walking horizon: the left foot swings over nodes 5..14, the right over 18..27.
std::vector<NodeReference> walkingReferences(const RigidBody& body, const Eigen::Vector3d& base,
                                             int N, double dt) {
  std::vector<NodeReference> refs(N + 1);
  for (int k = 0; k <= N; ++k) {
    NodeReference& r = refs[k];
    const double t = k * dt;
    r.x = Eigen::VectorXd::Zero(12);
    r.x.head<3>() = body.mass * Eigen::Vector3d(0.8, 0.0, 0.0);
    r.x.segment<3>(CentroidalLayout::kBasePosition) = base + Eigen::Vector3d(0.8 * t, 0.0, 0.0);
    r.x[CentroidalLayout::kBaseZyx] = 0.1 * t;  // turning: the linearisation changes node to node
    const bool leftSwing = k >= 5 && k < 15, rightSwing = k >= 18 && k < 28;
    r.stance = {!leftSwing, !leftSwing, !rightSwing, !rightSwing};
    int stance = 0;
    for (bool s : r.stance) stance += s;
    r.u = Eigen::VectorXd::Zero(12);
    for (int c = 0; c < kNumContacts; ++c) {
      const double x = 0.8 * t + (c % 2 ? -0.05 : 0.12), y = c < 2 ? 0.1 : -0.1;
      r.contactPosition[c] = Eigen::Vector3d(x, y, 0.0);
      if (r.stance[c]) r.u[3 * c + 2] = body.mass * 9.81 / stance;
    }
  }
  return refs;
}

TEST_F(SingleRigidBody, ItsQpIsSolvedToTheKktConditions) {
  // The LQ subproblem at an iterate off the references (barriers active: Gauss-Newton terms in
  // R), by the Riccati sweep and by one direct KKT solve over the whole horizon.
  SingleRigidBodyProblem problem(body, settings());
  const int N = 30;
  const double dt = 0.02;
  const auto refs = walkingReferences(body, qStand.head<3>(), N, dt);
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  std::vector<LqNode> nodes(N + 1, LqNode(12, 12, problem.maxEqualities()));
  const auto workspace = problem.makeWorkspace();
  ProblemWorkspace& ws = *workspace;
  NodeValue value;
  for (int k = 0; k < N; ++k) {
    const Eigen::VectorXd x = refs[k].x + 0.05 * Eigen::VectorXd::NullaryExpr(12, [&] { return d(rng); });
    const Eigen::VectorXd u = refs[k].u + 30.0 * Eigen::VectorXd::NullaryExpr(12, [&] { return d(rng); });
    problem.linearize(ws, refs[k], x, u, dt, nodes[k], value);
    nodes[k].b = 0.01 * Eigen::VectorXd::NullaryExpr(12, [&] { return d(rng); });  // defects
  }
  problem.terminalCost(ws, refs[N], refs[N].x, &nodes[N]);
  const Eigen::VectorXd dx0 = 0.02 * Eigen::VectorXd::NullaryExpr(12, [&] { return d(rng); });
  std::vector<Eigen::VectorXd> dx, du, dxKkt, duKkt;
  RiccatiSolver riccati(N, 12, 12);
  ASSERT_TRUE(riccati.solve(nodes, dx0, dx, du));
  testing::solveByKkt(nodes, dx0, dxKkt, duKkt);
  testing::expectKktSolution(dx, du, dxKkt, duKkt);
  for (int k = 0; k < N; ++k) {
    const LqNode& n = nodes[k];
    EXPECT_LT((n.C.topRows(n.neq) * dx[k] + n.D.topRows(n.neq) * du[k] + n.e.head(n.neq)).norm(), 1e-9);
    EXPECT_LT((dx[k + 1] - n.A * dx[k] - n.B * du[k] - n.b).norm(), 1e-9) << "node " << k;
  }
}

TEST_F(SingleRigidBody, SqpIterationsMeetTheDynamicsAndConvergeInsideTheCone) {
  // Real-time iterations from a state off to the side: no force on a swing at any of them; they
  // converge onto the dynamics, the stance forces inside the cone's barrier.
  SingleRigidBodyProblem problem(body, settings());
  SqpSettings s = test::controlDefaults().locomotion.sqp;
  s.nodes = 30;
  s.dt = 0.02;
  SqpSolver sqp(problem, s);
  const auto refs = walkingReferences(body, qStand.head<3>(), s.nodes, s.dt);
  for (int k = 0; k <= s.nodes; ++k) sqp.references()[k] = refs[k];
  Eigen::VectorXd x0 = refs[0].x;
  x0[CentroidalLayout::kBasePosition + 1] += 0.03;  // off to the side: it has to come back
  const auto workspace = problem.makeWorkspace();
  ProblemWorkspace& ws = *workspace;
  NodeValue value;
  std::vector<Eigen::VectorXd> before;
  for (int iteration = 0; iteration < 30; ++iteration) {
    before = sqp.solution().u;
    ASSERT_TRUE(sqp.iterate(0.0, x0)) << sqp.statistics().message;
    const MpcSolution& sol = sqp.solution();
    for (int k = 0; k < s.nodes; ++k) {
      problem.evaluate(ws, refs[k], sol.x[k], sol.u[k], s.dt, value);
      if (iteration == 29) {  // the lever arms make it bilinear: met once converged
        EXPECT_LT((sol.x[k + 1] - sol.x[k] - s.dt * value.xdot).norm(), 1e-6) << " node " << k;
      }
      for (int c = 0; c < kNumContacts; ++c) {
        if (!refs[k].stance[c]) {
          EXPECT_LT(sol.u[k].segment<3>(3 * c).norm(), 1e-9) << k;
        }
      }
    }
  }
  const MpcSolution& sol = sqp.solution();
  for (int k = 0; k < s.nodes; ++k)  // converged: the last iteration moved the forces by < 0.1 N
    EXPECT_LT((sol.u[k] - before[k]).cwiseAbs().maxCoeff(), 0.1) << "node " << k;
  const ProblemSettings p = settings();
  for (int k = 0; k < s.nodes; ++k)
    for (int c = 0; c < kNumContacts; ++c) {
      if (!refs[k].stance[c]) continue;
      const Eigen::Vector3d f = sol.u[k].segment<3>(3 * c);
      EXPECT_GT(p.frictionCoefficient * f.z() - f.head<2>().norm(), -p.frictionBarrier.delta)
          << "node " << k << " point " << c << ": " << f.transpose();
    }
}

TEST_F(SingleRigidBody, AnIterationAllocatesNothingOnceItsNodesHaveTheirSizes) {
  // As the kino-dynamic problem's (sqp_test.cpp): the cI planner runs on the same real-time
  // thread, so once the first iterations have sized the nodes an SQP iteration allocates nothing.
  SingleRigidBodyProblem problem(body, settings());
  SqpSettings s = test::controlDefaults().locomotion.sqp;
  s.nodes = 30;
  s.dt = 0.02;
  s.threads = 1;  // the counter watches this thread
  SqpSolver sqp(problem, s);
  const auto refs = walkingReferences(body, qStand.head<3>(), s.nodes, s.dt);
  for (int k = 0; k <= s.nodes; ++k) sqp.references()[k] = refs[k];
  Eigen::VectorXd x0 = refs[0].x;
  x0[CentroidalLayout::kBasePosition + 1] += 0.03;
  for (int it = 0; it < 3; ++it) ASSERT_TRUE(sqp.iterate(0.0, x0)) << sqp.statistics().message;
  bool ok = false;
  EXPECT_EQ(test::allocationsIn([&] { ok = sqp.iterate(0.0, x0); }), 0);
  EXPECT_TRUE(ok) << sqp.statistics().message;
}

// The cost terms the two problems share are computed twice (tracking_cost.hpp says why): on a
// state whose limbs are at their reference, with the kino-dynamic problem's own barriers (joint
// limits, feet distance) switched off, both give the same cost, the same Q, R, q and r on the 12
// shared entries, the same terminal cost and the same warm-start forces across a mode change.
TEST_F(SingleRigidBody, CostTermsAreTheKinodynamicProblems) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  ProblemSettings kinoSettings = test::controlDefaults().locomotion.problem;
  kinoSettings.stateWeights = Eigen::VectorXd::NullaryExpr(L.nx(), [&] { return 2.0 + d(rng); });
  kinoSettings.inputWeights = Eigen::VectorXd::NullaryExpr(L.nu(), [&] { return 0.02 + 0.01 * d(rng); });
  kinoSettings.limitBarrier.weight = 0.0;
  kinoSettings.jointStop.weight = 0.0;
  kinoSettings.collisionBarrier.weight = 0.0;
  ProblemSettings srbdSettings = kinoSettings;
  srbdSettings.stateWeights = kinoSettings.stateWeights.head(12);
  srbdSettings.inputWeights = kinoSettings.inputWeights.head(12);
  const KinodynamicProblem kino(m, {frames[0], frames[1], frames[2], frames[3]}, kinoSettings);
  const SingleRigidBodyProblem srbd(body, srbdSettings);

  NodeReference kinoRef;
  kinoRef.x = Eigen::VectorXd::Zero(L.nx());
  kinoRef.x.segment<3>(L.kBasePosition) = qStand.head<3>();
  kinoRef.x[L.kBaseZyx] = 3.0;  // near +pi: the state's yaw below -pi checks the wrap
  kinoRef.x.tail(m.nj()) = posture;
  kinoRef.u = Eigen::VectorXd::Zero(L.nu());
  kinoRef.stance = {true, true, false, true};
  for (int c : {0, 1, 3}) kinoRef.u[L.force(c) + 2] = body.mass * 9.81 / 3;
  Eigen::VectorXd x = kinoRef.x, u = kinoRef.u;
  x.head(12) += 0.2 * Eigen::VectorXd::NullaryExpr(12, [&] { return d(rng); });
  x[L.kBaseZyx] -= 2.0 * M_PI;
  u.head(12) += 30.0 * Eigen::VectorXd::NullaryExpr(12, [&] { return d(rng); });
  NodeReference srbdRef = kinoRef;
  srbdRef.x = kinoRef.x.head(12);
  srbdRef.u = kinoRef.u.head(12);

  const double dt = 0.02;
  auto kinoWs = kino.makeWorkspace();
  const auto srbdWorkspace = srbd.makeWorkspace();
  ProblemWorkspace& srbdWs = *srbdWorkspace;
  LqNode kinoNode(L.nx(), L.nu(), kino.maxEqualities()), srbdNode(12, 12, srbd.maxEqualities());
  NodeValue kinoValue, srbdValue;
  kino.linearize(*kinoWs, kinoRef, x, u, dt, kinoNode, kinoValue);
  srbd.linearize(srbdWs, srbdRef, x.head(12), u.head(12), dt, srbdNode, srbdValue);
  ASSERT_GT(srbdValue.cost, 0.1);  // the terms matter here (dt = 0.02)
  auto same = [](const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
    return (a - b).cwiseAbs().maxCoeff() <= 1e-12 * (1.0 + b.cwiseAbs().maxCoeff());
  };
  EXPECT_NEAR(srbdValue.cost, kinoValue.cost, 1e-12 * kinoValue.cost);
  EXPECT_TRUE(same(srbdNode.Q, kinoNode.Q.topLeftCorner(12, 12)));
  EXPECT_TRUE(same(srbdNode.R, kinoNode.R.topLeftCorner(12, 12)));
  EXPECT_TRUE(same(srbdNode.q, kinoNode.q.head(12)));
  EXPECT_TRUE(same(srbdNode.r, kinoNode.r.head(12))) << srbdNode.r.transpose() << "\n"
                                                     << kinoNode.r.head(12).transpose();
  EXPECT_TRUE(same(srbdNode.S, kinoNode.S.topLeftCorner(12, 12)));

  LqNode kinoTerminal(L.nx(), L.nu(), 0), srbdTerminal(12, 12, 0);
  const double kinoCost = kino.terminalCost(*kinoWs, kinoRef, x, &kinoTerminal);
  EXPECT_NEAR(srbd.terminalCost(srbdWs, srbdRef, x.head(12), &srbdTerminal), kinoCost,
              1e-12 * kinoCost);
  EXPECT_TRUE(same(srbdTerminal.Q, kinoTerminal.Q.topLeftCorner(12, 12)));
  EXPECT_TRUE(same(srbdTerminal.q, kinoTerminal.q.head(12)));

  // The right heel lands and the left toe lifts: the warm start's forces follow alike.
  const StanceFlags before = {true, true, true, false};
  Eigen::VectorXd kinoU = u, srbdU = u.head(12);
  kino.adaptInputToMode(kinoRef, before, kinoU);
  srbd.adaptInputToMode(srbdRef, before, srbdU);
  EXPECT_EQ(srbdU, kinoU.head(12));
  EXPECT_NE(srbdU, u.head(12));
}

}  // namespace
}  // namespace ballast::mpc
