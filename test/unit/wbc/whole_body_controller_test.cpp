// The whole-body controller on the humanoid: every level met under consistent references, strict
// priority when limbs and base conflict, limits, friction, swing forces, torques against RNEA.
#include <gtest/gtest.h>

#include "test/unit/settings_support.hpp"
#include "test/unit/test_support.hpp"
#include "test/unit/wbc/wbc_test_support.hpp"

namespace ballast::test {
namespace {

using namespace wbc;

std::vector<int> contactFrameIds(const model::Model& m, const WbcSettings& s) {
  std::vector<int> ids;
  for (const auto& name : s.contactFrames) ids.push_back(m.frameId(name));
  return ids;
}

WbcState stateOf(const ConsistentMotion& c) { return WbcState{c.q, c.v}; }

/// Checks that hold for every answer: the torques reproduce the full dynamics (RNEA, all rows),
/// stance points are inside the friction pyramid, swing points carry no force, limits hold.
void expectPhysicallyConsistent(const model::Model& m, const WholeBodyController& wbc,
                                const WbcState& state, const WbcReference& ref,
                                const WbcOutput& out) {
  model::Data<double> d(m);
  const Eigen::VectorXd tau = model::rnea(m, d, state.q, state.v, out.acceleration);
  Eigen::MatrixXd J;
  Eigen::VectorXd Jdv;
  contactKinematics(m, state.q, state.v, contactFrameIds(m, wbc.settings()), J, Jdv);
  const Eigen::VectorXd generalised = tau - J.transpose() * out.contactForce;
  const double scale = tau.cwiseAbs().maxCoeff();
  EXPECT_LT(generalised.head(6).cwiseAbs().maxCoeff(), 1e-8 * scale) << "base rows of M v̇ + n − JᵀF";
  EXPECT_LT((generalised.tail(m.nj()) - out.jointTorque).cwiseAbs().maxCoeff(), 1e-8 * scale)
      << "τ differs from the actuated rows of the dynamics";
  const double mu = wbc.settings().frictionCoefficient;
  for (int i = 0; i < wbc.contactCount(); ++i) {
    const Eigen::Vector3d f = out.contactForce.segment<3>(3 * i);
    if (ref.stance[i]) {
      EXPECT_GE(f.z(), -1e-8) << "contact " << i;
      EXPECT_LE(std::abs(f.x()), mu * f.z() + 1e-8) << "contact " << i;
      EXPECT_LE(std::abs(f.y()), mu * f.z() + 1e-8) << "contact " << i;
      EXPECT_LT((J.middleRows(3 * i, 3) * out.acceleration + Jdv.segment<3>(3 * i)).norm(), 1e-8)
          << "stance contact " << i << " accelerates";
    } else {
      EXPECT_LT(f.norm(), 1e-9) << "swing contact " << i << " carries force";
    }
  }
  for (int j = 0; j < m.nj(); ++j)
    EXPECT_LE(std::abs(out.jointTorque[j]), wbc.torqueLimit()[j] + 1e-9) << m.jointName[j + 1];
}

TEST(WbcSettings, ValidationNamesTheField) {
  const model::Model& m = humanoid();
  WbcSettings s = wbcSettings();
  EXPECT_FALSE(validateSettings(s, m));
  s.frictionCoefficient = -0.5;
  EXPECT_EQ(validateSettings(s, m).field, &s.frictionCoefficient);
  s = wbcSettings();
  s.contactFrames = {"left_toe", "left_knuckle"};
  EXPECT_EQ(validateSettings(s, m).field, &s.contactFrames);
  EXPECT_NE(validateSettings(s, m).message.find("left_knuckle"), std::string::npos);
  s = wbcSettings();
  s.torqueLimit = {1.0, 2.0};
  EXPECT_EQ(validateSettings(s, m).field, &s.torqueLimit);
  EXPECT_NE(validateSettings(s, m).message.find("needs 24"), std::string::npos);
  s = wbcSettings();
  s.baseKp[4] = std::nan("");
  EXPECT_EQ(validateSettings(s, m).field, &s.baseKp[4]);
  s = wbcSettings();
  s.jointSpaceJoints.push_back("left_elbow");
  EXPECT_EQ(validateSettings(s, m).field, &s.jointSpaceJoints);
  EXPECT_NE(validateSettings(s, m).message.find("listed twice"), std::string::npos);
  EXPECT_THROW(WholeBodyController(m, s), std::invalid_argument);
}

class WbcVariants : public ::testing::TestWithParam<WbcVariant> {};

TEST_P(WbcVariants, ConsistentReferencesAreMetAtEveryLevel) {
  const model::Model& m = humanoid();
  WbcSettings settings = wbcSettings();
  settings.variant = GetParam();
  // Random motions roll their swinging feet; the task that levels them asks for its own roll
  // acceleration (ASwingingFootIsHeldLevel), which no reference here carries.
  settings.levelSwingFeet = false;
  WholeBodyController wbc(m, settings);
  WbcReference ref = wbc.makeReference();
  WbcOutput out = wbc.makeOutput();
  std::mt19937 rng(17);
  const std::vector<std::vector<bool>> schedules{
      {true, true, true, true}, {true, true, false, false}, {false, false, true, true},
      {true, false, true, true}};
  for (int trial = 0; trial < 24; ++trial) {
    ref.stance = schedules[trial % schedules.size()];
    // Motions whose forces leave the pyramid are not consistent with priority 1: draw again.
    ConsistentMotion c;
    int draws = 0;
    do {
      c = consistentMotion(m, contactFrameIds(m, settings), ref.stance, rng);
      ASSERT_LT(++draws, 100) << "no motion inside the friction pyramids";
    } while (!insidePyramid(c.F, ref.stance, settings.frictionCoefficient));
    consistentReferences(m, wbc, c, ref);
    const WbcState state = stateOf(c);
    ASSERT_EQ(wbc.update(state, ref, out), WbcStatus::kOk) << "trial " << trial;
    EXPECT_LT(out.taskError[kPhysics], 1e-8) << "trial " << trial;
    EXPECT_LT(out.taskError[kLimbs], 1e-7) << "trial " << trial;
    EXPECT_LT(out.taskError[kBase], 1e-7) << "trial " << trial;
    EXPECT_LT(out.taskError[kContactForces], 1e-6) << "trial " << trial;
    expectPhysicallyConsistent(m, wbc, state, ref, out);
  }
}

TEST_P(WbcVariants, StandingStillHoldsTheRobotWithTorquesWithinLimits) {
  const model::Model& m = humanoid();
  WbcSettings settings = wbcSettings();
  settings.variant = GetParam();
  WholeBodyController wbc(m, settings);
  WbcReference ref = wbc.makeReference();
  std::mt19937 rng(1);
  // Still, with the force reference the static equilibrium closest to an equal share.
  const ConsistentMotion c =
      consistentMotion(m, contactFrameIds(m, settings), ref.stance, rng, 0.0, 0.0, 0.0);
  ASSERT_LT(c.vdot.norm(), 1e-9);
  consistentReferences(m, wbc, c, ref);
  const WbcState state = stateOf(c);
  WbcOutput out = wbc.makeOutput();
  ASSERT_EQ(wbc.update(state, ref, out), WbcStatus::kOk);
  // Nothing moves: the controller holds the robot against gravity.
  EXPECT_LT(out.acceleration.cwiseAbs().maxCoeff(), 1e-7);
  EXPECT_NEAR(out.contactForce(Eigen::seq(2, Eigen::last, 3)).sum(), m.totalMass() * 9.81, 1e-6);
  EXPECT_LT((out.contactForce - c.F).norm(), 1e-6);
  EXPECT_GT(out.jointTorque.cwiseAbs().maxCoeff(), 10.0);  // the knees work
  expectPhysicallyConsistent(m, wbc, state, ref, out);
  // Targets one period ahead of a still robot are where it is.
  EXPECT_LT((out.jointPositionTarget - state.q.tail(m.nj())).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT(out.jointVelocityTarget.cwiseAbs().maxCoeff(), 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Both, WbcVariants,
                         ::testing::Values(WbcVariant::kHierarchical, WbcVariant::kWeighted),
                         [](const auto& info) { return std::string(toString(info.param)); });

/// Minimum of ‖A₃ξ − b₃‖ over {A₀ξ = b₀, A₂ξ = b₂} by a complete orthogonal decomposition
/// (independent of the controller's QR): what level 3 can achieve after levels 1 and 2.
double bestResidualBelow(const TaskStack& t, int level, const std::vector<int>& above) {
  const int n = t.variables();
  int rows = 0;
  for (int k : above) rows += t.equalityRows(k);
  Eigen::MatrixXd A(rows, n);
  Eigen::VectorXd b(rows);
  int r = 0;
  for (int k : above) {
    A.middleRows(r, t.equalityRows(k)) = t.A().middleRows(t.equalityBegin(k), t.equalityRows(k));
    b.segment(r, t.equalityRows(k)) = t.b().segment(t.equalityBegin(k), t.equalityRows(k));
    r += t.equalityRows(k);
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
  svd.setThreshold(1e-10);
  const int rank = static_cast<int>(svd.rank());
  const Eigen::MatrixXd N = svd.matrixV().rightCols(n - rank);
  const Eigen::VectorXd x0 = svd.solve(b);
  const Eigen::MatrixXd A3 = t.A().middleRows(t.equalityBegin(level), t.equalityRows(level));
  const Eigen::VectorXd b3 = t.b().segment(t.equalityBegin(level), t.equalityRows(level));
  const Eigen::MatrixXd AN = A3 * N;
  const Eigen::VectorXd z = AN.jacobiSvd(Eigen::ComputeThinU | Eigen::ComputeThinV).solve(b3 - A3 * x0);
  return (A3 * (x0 + N * z) - b3).norm();
}

// In flight (no contact point in stance) the base moves only through the reaction of the limbs:
// settings with limits large enough to keep the inequalities inactive, and, per trial, limb
// references consistent with one motion and base references asking for another. The conflict
// both priority orders are tested on.
WbcSettings inFlightSettings(const model::Model& m) {
  WbcSettings settings = wbcSettings();
  settings.torqueLimit.assign(m.nj(), 5000.0);
  settings.levelSwingFeet = false;  // as in ConsistentReferencesAreMetAtEveryLevel
  return settings;
}

WbcState inFlightConflict(const model::Model& m, const WbcSettings& settings,
                          const WholeBodyController& wbc, std::mt19937& rng, WbcReference& ref) {
  ref.stance = {false, false, false, false};
  const ConsistentMotion c = consistentMotion(m, contactFrameIds(m, settings), ref.stance, rng);
  consistentReferences(m, wbc, c, ref);
  ref.baseAngularAcceleration += Eigen::Vector3d(3.0, -1.0, 0.5);  // the conflicting demand
  ref.basePosition += Eigen::Vector3d(0.0, 0.02, -0.01);
  return stateOf(c);
}

TEST(Wbc, LimbsOverBaseWhenTheyConflict) {
  // The in-flight conflict (inFlightConflict): level 2 (limbs) must be met, level 3 (base) only
  // as far as the remaining freedom allows. Equality algebra, by an independent SVD, gives the
  // best achievable base residual.
  const model::Model& m = humanoid();
  const WbcSettings settings = inFlightSettings(m);
  WholeBodyController wbc(m, settings);
  WbcReference ref = wbc.makeReference();
  std::mt19937 rng(3);
  WbcOutput out = wbc.makeOutput();
  for (int trial = 0; trial < 10; ++trial) {
    const WbcState state = inFlightConflict(m, settings, wbc, rng, ref);
    ASSERT_EQ(wbc.update(state, ref, out), WbcStatus::kOk) << "trial " << trial;
    const TaskStack& t = wbc.tasks();
    EXPECT_LT(out.taskError[kLimbs], 1e-7) << "trial " << trial;
    const double best = bestResidualBelow(t, kLevelBase, {kLevelPhysics, kLevelLimbs});
    EXPECT_GT(best, 0.5) << "the test needs a real conflict";
    EXPECT_NEAR(out.taskError[kBase], best, 1e-6 * best) << "trial " << trial;
    // Without the limbs above it, the base could do better: the conflict is real.
    EXPECT_LT(bestResidualBelow(t, kLevelBase, {kLevelPhysics}), 0.5 * best);
    expectPhysicallyConsistent(m, wbc, state, ref, out);
  }
}

TEST(Wbc, APushStepPutsTheBaseAboveTheLimbs) {
  // LimbsOverBaseWhenTheyConflict's conflict, the plan stepping out a push (issue 13): the base
  // task goes above the limbs (WbcSettings::pushBaseFirst), so the base is met as far as the
  // physics allows and the limbs only in what is left; with pushBaseFirst off, the paper's order.
  // A push's quick swing at its hip's torque limit took the rest of its acceleration from the
  // base through the stance leg: 2100 N under a plan of 960 N, and the robot left the ground.
  const model::Model& m = humanoid();
  WbcSettings settings = inFlightSettings(m);
  WholeBodyController wbc(m, settings);
  settings.pushBaseFirst = false;
  WholeBodyController paper(m, settings);
  WbcReference ref = wbc.makeReference();
  ref.pushStep = true;
  std::mt19937 rng(3);
  WbcOutput out = wbc.makeOutput(), outPaper = paper.makeOutput();
  for (int trial = 0; trial < 10; ++trial) {
    const WbcState state = inFlightConflict(m, settings, wbc, rng, ref);
    ASSERT_EQ(wbc.update(state, ref, out), WbcStatus::kOk) << "trial " << trial;
    const TaskStack& t = wbc.tasks();
    ASSERT_EQ(wbc.baseLevel(), kLevelLimbs);
    ASSERT_EQ(wbc.limbsLevel(), kLevelBase);
    const double base = bestResidualBelow(t, wbc.baseLevel(), {kLevelPhysics});
    const double limbs = bestResidualBelow(t, wbc.limbsLevel(), {kLevelPhysics, wbc.baseLevel()});
    EXPECT_NEAR(out.taskError[kBase], base, 1e-6 * std::max(base, 1.0)) << "trial " << trial;
    EXPECT_NEAR(out.taskError[kLimbs], limbs, 1e-6 * std::max(limbs, 1.0)) << "trial " << trial;
    expectPhysicallyConsistent(m, wbc, state, ref, out);

    ASSERT_EQ(paper.update(state, ref, outPaper), WbcStatus::kOk) << "trial " << trial;
    EXPECT_EQ(paper.baseLevel(), kLevelBase);
    EXPECT_LT(outPaper.taskError[kLimbs], 1e-7) << "trial " << trial;
    EXPECT_GT(outPaper.taskError[kBase], 2.0 * out.taskError[kBase] + 0.25) << "trial " << trial;
    EXPECT_GT(out.taskError[kLimbs], 0.1) << "the limbs give way to the base";
  }
  // Undisturbed walking keeps the paper's order.
  ASSERT_NE(wbc.update(wbc.makeState(), wbc.makeReference(), out), WbcStatus::kInvalidInput);
  EXPECT_EQ(wbc.baseLevel(), kLevelBase);
  EXPECT_EQ(wbc.limbsLevel(), kLevelLimbs);
}

TEST(Wbc, InverseDynamicsIsTheWeightedQpWithTheArmsHeld) {
  // cI's tracking: the weighted QP, its joint-space joints asked back to their reference
  // positions with no reference velocity or acceleration (its plan's limbs do not move).
  const model::Model& m = humanoid();
  WbcSettings settings = wbcSettings();
  settings.variant = WbcVariant::kInverseDynamics;
  WholeBodyController inverseDynamics(m, settings);
  settings.variant = WbcVariant::kWeighted;
  WholeBodyController weighted(m, settings);
  WbcReference ref = inverseDynamics.makeReference();
  std::mt19937 rng(23);
  for (const std::vector<bool>& stance :
       {std::vector<bool>{true, true, true, true}, std::vector<bool>{true, true, false, false}}) {
    ref.stance = stance;
    const ConsistentMotion c = consistentMotion(m, contactFrameIds(m, settings), ref.stance, rng);
    consistentReferences(m, inverseDynamics, c, ref);
    ASSERT_GT(ref.jointVelocity.norm() + ref.jointAcceleration.norm(), 0.1);
    const WbcState state = stateOf(c);
    WbcOutput held = inverseDynamics.makeOutput(), plain = weighted.makeOutput();
    ASSERT_NE(inverseDynamics.update(state, ref, held), WbcStatus::kInvalidInput);
    WbcReference still = ref;
    still.jointVelocity.setZero();
    still.jointAcceleration.setZero();
    ASSERT_NE(weighted.update(state, still, plain), WbcStatus::kInvalidInput);
    EXPECT_LT((held.acceleration - plain.acceleration).norm(), 1e-9);
    EXPECT_LT((held.contactForce - plain.contactForce).norm(), 1e-6);
    EXPECT_LT((held.jointTorque - plain.jointTorque).norm(), 1e-6);
    expectPhysicallyConsistent(m, inverseDynamics, state, ref, held);
  }
}

TEST(Wbc, WeightedVariantTradesLimbErrorForBase) {
  // The same conflict under cNH: limb tracking is no longer exact (the paper's point).
  const model::Model& m = humanoid();
  WbcSettings settings = wbcSettings();
  settings.torqueLimit.assign(m.nj(), 5000.0);
  settings.variant = WbcVariant::kWeighted;
  WholeBodyController weighted(m, settings);
  settings.variant = WbcVariant::kHierarchical;
  WholeBodyController hierarchical(m, settings);
  WbcReference ref = weighted.makeReference();
  ref.stance = {false, false, false, false};
  std::mt19937 rng(5);
  const ConsistentMotion c = consistentMotion(m, contactFrameIds(m, settings), ref.stance, rng);
  consistentReferences(m, weighted, c, ref);
  ref.baseAngularAcceleration += Eigen::Vector3d(3.0, -1.0, 0.5);
  WbcOutput a = weighted.makeOutput(), b = hierarchical.makeOutput();
  ASSERT_EQ(weighted.update(stateOf(c), ref, a), WbcStatus::kOk);
  ASSERT_EQ(hierarchical.update(stateOf(c), ref, b), WbcStatus::kOk);
  EXPECT_GT(a.taskError[kLimbs], 1e-3);
  EXPECT_LT(b.taskError[kLimbs], 1e-7);
  EXPECT_LT(a.taskError[kBase], b.taskError[kBase]);
  expectPhysicallyConsistent(m, weighted, stateOf(c), ref, a);
}

/// Best ‖A_k ξ − b_k‖ over ξ that achieves what the controller achieved on the levels above
/// (A_j ξ = A_j ξ_wbc, j < k) and meets every inequality row: one QP in the full space, a
/// formulation independent of the controller's null-space sequence.
double bestResidualWithLimits(const TaskStack& t, int level, const Eigen::VectorXd& xi) {
  const int n = t.variables(), p = t.totalInequalityRows();
  int me = 0;
  for (int j = 0; j < level; ++j) me += t.equalityRows(j);
  QpSolver qp(QpCapacity{n, me, p});
  qp.resize(n, me, p);
  const Eigen::MatrixXd Ak = t.A().middleRows(t.equalityBegin(level), t.equalityRows(level));
  const Eigen::VectorXd bk = t.b().segment(t.equalityBegin(level), t.equalityRows(level));
  qp.H() = Ak.transpose() * Ak + 1e-10 * Eigen::MatrixXd::Identity(n, n);
  qp.g() = -Ak.transpose() * bk;
  qp.A() = t.A().topRows(me);
  qp.b() = qp.A() * xi;
  qp.C() = t.D().topRows(p);
  qp.lower() = t.lower().head(p);
  qp.upper() = t.upper().head(p);
  EXPECT_EQ(qp.solve(), QpStatus::kOptimal) << qp.result().reason;
  return (Ak * qp.x() - bk).norm();
}

WbcReference standingReference(const model::Model& m, const WholeBodyController& wbc,
                               const WbcState& state) {
  WbcReference ref = wbc.makeReference();
  ref.basePosition = state.q.head<3>();
  ref.jointPosition = state.q.tail(m.nj());
  for (int i = 0; i < wbc.contactCount(); ++i)
    ref.contactForce[3 * i + 2] = m.totalMass() * 9.81 / wbc.contactCount();
  return ref;
}

TEST(Wbc, TorqueLimitsRedistributeTheLoad) {
  // Standing, with a left knee limit below what an even stance needs: the controller must shift
  // the load (and move) so the left knee stays within its limit, the physics still exact.
  const model::Model& m = humanoid();
  WbcSettings settings = wbcSettings();
  WholeBodyController free(m, settings);
  WbcState state = free.makeState();
  state.q = standingConfiguration(m, -0.45, 0.9, -0.45);
  const WbcReference ref = standingReference(m, free, state);
  WbcOutput out = free.makeOutput();
  ASSERT_EQ(free.update(state, ref, out), WbcStatus::kOk);
  const int knee = m.jointId("left_knee");
  const double needed = std::abs(out.jointTorque[knee]);
  ASSERT_GT(needed, 20.0);
  EXPECT_EQ(out.qpSolves, 0);  // nothing binds: least squares all the way

  settings.torqueLimit.assign(m.effortLimit.data(), m.effortLimit.data() + m.nj());
  settings.torqueLimit[knee] = 0.6 * needed;
  WholeBodyController limited(m, settings);
  ASSERT_EQ(limited.update(state, ref, out), WbcStatus::kOk);
  EXPECT_NEAR(std::abs(out.jointTorque[knee]), 0.6 * needed, 1e-6 * needed) << "the limit binds";
  EXPECT_LT(out.taskError[kPhysics], 1e-8);
  EXPECT_GT(out.qpSolves, 0);
  expectPhysicallyConsistent(m, limited, state, ref, out);
  for (int k : {kLevelBase, kLevelContactForces})
    EXPECT_NEAR(limited.tasks().residual(k, limited.decision()),
                bestResidualWithLimits(limited.tasks(), k, limited.decision()), 1e-5)
        << "level " << k;

  // Limits far below what standing needs: the limits (priority 1) win over the base (3); the
  // robot is allowed to sag, the physics rows stay exact.
  settings.torqueLimit.assign(m.nj(), 5.0);
  WholeBodyController starved(m, settings);
  EXPECT_NE(starved.update(state, ref, out), WbcStatus::kInvalidInput);
  EXPECT_NE(out.status, WbcStatus::kDegraded);
  EXPECT_LT(out.taskError[kPhysics], 1e-8);
  EXPECT_GT(out.taskError[kBase], 1.0);
  expectPhysicallyConsistent(m, starved, state, ref, out);
}

TEST(Wbc, FrictionPyramidLimitsTheBase) {
  // A sideways base acceleration (1 m/s², below the ≈1.1 m/s² at which a foot would lift) on a
  // slippery floor: forces stay inside the pyramid, the base does the best the pyramid permits,
  // and with more friction it follows exactly.
  const model::Model& m = humanoid();
  WbcSettings settings = wbcSettings();
  settings.frictionCoefficient = 0.05;
  WholeBodyController wbc(m, settings);
  WbcState state = wbc.makeState();
  state.q = standingConfiguration(m);
  WbcReference ref = standingReference(m, wbc, state);
  ref.baseLinearAcceleration = Eigen::Vector3d(0.0, 1.0, 0.0);
  WbcOutput out = wbc.makeOutput();
  ASSERT_EQ(wbc.update(state, ref, out), WbcStatus::kOk);
  expectPhysicallyConsistent(m, wbc, state, ref, out);
  const double best = bestResidualWithLimits(wbc.tasks(), kLevelBase, wbc.decision());
  EXPECT_NEAR(out.taskError[kBase], best, 1e-5 * std::max(1.0, best));
  EXPECT_GT(out.taskError[kBase], 0.2);
  double lateral = 0.0, normal = 0.0;
  for (int i = 0; i < 4; ++i) lateral += out.contactForce[3 * i + 1], normal += out.contactForce[3 * i + 2];
  EXPECT_NEAR(lateral, 0.05 * normal, 1e-6 * normal) << "every pyramid's side binds";

  settings.frictionCoefficient = 2.0;
  WholeBodyController grippy(m, settings);
  WbcOutput out2 = grippy.makeOutput();
  ASSERT_EQ(grippy.update(state, ref, out2), WbcStatus::kOk);
  EXPECT_LT(out2.taskError[kBase], 1e-6);
  expectPhysicallyConsistent(m, grippy, state, ref, out2);
}

TEST(Wbc, ASwingingFootIsHeldLevel) {
  // The right foot in swing, rolled about its toe-heel line by its ankle (0.3 rad) and rolling
  // on (1 rad/s), its points' references where they are: the foot's roll acceleration about that
  // line is the feedback −kp·tilt − kd·rate that levels it, and the points stay on their paths.
  // Without wbc.level_swing_feet nothing asks for that roll.
  const model::Model& m = humanoid();
  WbcSettings settings = wbcSettings();
  ASSERT_TRUE(settings.levelSwingFeet);  // the schema's default
  ConsistentMotion c;
  c.q = standingConfiguration(m);
  const int ankleRoll = m.jointId("right_ankle_roll");
  c.q[model::Model::qIndexOfJoint(ankleRoll)] = 0.3;
  c.v = Eigen::VectorXd::Zero(m.nv);
  c.v[model::Model::vIndexOfJoint(ankleRoll)] = 1.0;
  c.vdot = Eigen::VectorXd::Zero(m.nv);
  c.F = Eigen::VectorXd::Zero(12);
  c.F[2] = c.F[5] = 0.5 * m.totalMass() * 9.81;
  const int toe = m.frameId("right_toe"), heel = m.frameId("right_heel");
  model::Data<double> d(m);
  model::forwardKinematicsBias(m, d, c.q, c.v);
  const Eigen::Vector3d line = model::framePlacement(m, d, toe).p - model::framePlacement(m, d, heel).p;
  const Eigen::Vector3d axis = line.normalized();
  const double rate = axis.dot(model::frameVelocity(m, d, toe).angular);
  const Eigen::Vector3d sideways = model::framePlacement(m, d, toe).R.col(1);
  const double tilt = std::asin(sideways.z() / std::sqrt(1.0 - std::pow(sideways.dot(axis), 2)));
  ASSERT_NEAR(tilt, 0.3, 0.02);  // feet flat in the standing configuration: the ankle's roll
  ASSERT_NEAR(rate, 1.0, 0.02);

  // The toe's roll acceleration about the line the WBC asks for, on `robot` (m, or m with the
  // right foot's contact frames turned).
  auto rollAsked = [&](const model::Model& robot) {
    WholeBodyController wbc(robot, settings);
    WbcReference ref = wbc.makeReference();
    ref.stance = {true, true, false, false};
    consistentReferences(robot, wbc, c, ref);
    WbcOutput out = wbc.makeOutput();
    EXPECT_EQ(wbc.update(stateOf(c), ref, out), WbcStatus::kOk);
    EXPECT_LT(out.taskError[kLimbs], 1e-7);
    Eigen::MatrixXd J(6, m.nv);
    model::frameJacobian(m, d, toe, J);
    return axis.dot(J.bottomRows<3>() * out.acceleration +
                    model::frameClassicalAcceleration(m, d, toe).angular);
  };
  const double levelling = -settings.swingKp * tilt - settings.swingKd * rate;
  settings.levelSwingFeet = true;
  EXPECT_NEAR(rollAsked(m), levelling, 1e-6);
  settings.levelSwingFeet = false;
  EXPECT_GT(std::abs(rollAsked(m) - levelling), 10.0);

  // The same foot with contact frames oriented as a vendor's links may be (the frames' points
  // unchanged): mirrored (y pointing out of the right foot, x backwards), and with y along the
  // leg. The sole's tilt, and so the levelling, does not depend on which axis is sideways.
  settings.levelSwingFeet = true;
  const Eigen::Matrix3d mirrored = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d yUp = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  for (const Eigen::Matrix3d& turn : {mirrored, yUp}) {
    model::Model turned = m;
    for (const int f : {toe, heel}) turned.frames[f].placement.R = turned.frames[f].placement.R * turn;
    EXPECT_NEAR(rollAsked(turned), levelling, 1e-6) << turn;
  }
}

TEST(Wbc, JointLimitsBrakeAJointBeforeItsStop) {
  // The left elbow (a joint-space joint) 0.01 rad below its upper limit, moving towards it at
  // 1 rad/s, its reference asking to go on (the limit 0.1 rad beyond it). Without wbc.joint_limits
  // the controller accelerates it into the stop; with them its acceleration is at most
  // kp·0.01 − kd·1 (400·0.01 − 40 = −36 rad/s²): it brakes.
  const model::Model& m = humanoid();
  WbcSettings settings = wbcSettings();
  ASSERT_FALSE(settings.jointLimits);  // the schema's default
  const int elbow = m.jointId("left_elbow");
  WbcState state{standingConfiguration(m), Eigen::VectorXd::Zero(m.nv)};
  const double hi = m.upperPositionLimit[elbow];
  state.q[model::Model::qIndexOfJoint(elbow)] = hi - 0.01;
  state.v[model::Model::vIndexOfJoint(elbow)] = 1.0;
  auto elbowAcceleration = [&](bool limits) {
    settings.jointLimits = limits;
    WholeBodyController wbc(m, settings);
    WbcReference ref = standingReference(m, wbc, state);
    ref.jointPosition[elbow] = hi + 0.1;
    ref.jointVelocity[elbow] = 1.0;
    WbcOutput out = wbc.makeOutput();
    EXPECT_NE(wbc.update(state, ref, out), WbcStatus::kInvalidInput);
    return out.acceleration[model::Model::vIndexOfJoint(elbow)];
  };
  const double bound = settings.jointKp * 0.01 - settings.jointKd * 1.0;
  ASSERT_NEAR(bound, -36.0, 1e-9);
  EXPECT_GT(elbowAcceleration(false), 0.0);
  EXPECT_LE(elbowAcceleration(true), bound + 1e-6);
}

TEST(Wbc, BadInputGivesZeroTorquesAndAFlag) {
  const model::Model& m = humanoid();
  WholeBodyController wbc(m, wbcSettings());
  WbcState state = wbc.makeState();
  state.q = standingConfiguration(m);
  WbcReference ref = wbc.makeReference();
  WbcOutput out = wbc.makeOutput();
  state.v[9] = std::nan("");
  EXPECT_EQ(wbc.update(state, ref, out), WbcStatus::kInvalidInput);
  EXPECT_TRUE(out.jointTorque.isZero());
  EXPECT_EQ(out.jointPositionTarget, state.q.tail(m.nj()));
  state.v.setZero();
  ref.contactForce[4] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(wbc.update(state, ref, out), WbcStatus::kInvalidInput);
  ref.contactForce.setZero();
  ref.stance.pop_back();
  EXPECT_EQ(wbc.update(state, ref, out), WbcStatus::kInvalidInput);
  ref.stance.push_back(true);
  state.q.segment<4>(3).setZero();  // not a rotation
  EXPECT_EQ(wbc.update(state, ref, out), WbcStatus::kInvalidInput);
  state.q = standingConfiguration(m);
  EXPECT_NE(wbc.update(state, ref, out), WbcStatus::kInvalidInput);
}

}  // namespace
}  // namespace ballast::test
