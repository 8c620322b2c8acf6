// Gait: contact schedule invariants, swing trajectories, footholds (paper eq. desired_swing_traj).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "gait/swing_planner.hpp"
#include "test/unit/settings_support.hpp"

namespace ballast::gait {
namespace {

constexpr double kDt = 1e-3;

/// The swing planner's parameters a profile gets by default (the schema's).
SwingPlannerParameters defaults() { return test::controlDefaults().locomotion.swing; }

Gait walk(double period = 0.8, double ds = 0.2, double lead = 0.0) {
  return Gait{true, period, ds, lead};
}

bool footInSwing(const ContactFlags& f, bool left) {
  return left ? !(f[kLeftToe] && f[kLeftHeel]) : !(f[kRightToe] && f[kRightHeel]);
}

/// Durations of every complete swing of `contact` sampled on [t0, t1].
std::vector<double> swingDurations(const ContactSchedule& s, int contact, double t0, double t1) {
  std::vector<double> out;
  bool inSwing = false;
  double start = 0;
  for (double t = t0; t < t1; t += kDt) {
    const bool swing = !s.inStance(contact, t);
    if (swing && !inSwing) start = t;
    if (!swing && inSwing && start > t0) out.push_back(t - start);
    inSwing = swing;
  }
  return out;
}

TEST(ContactSchedule, StandingKeepsEveryContactClosed) {
  const ContactSchedule s(Gait{}, 0.0);
  for (double t = 0; t < 3; t += 0.01) EXPECT_EQ(s.flagsAt(t), kAllStance);
  SwingInterval swing;
  EXPECT_FALSE(s.swingAround(kLeftToe, 0.0, 10.0, swing));
  EXPECT_DOUBLE_EQ(s.nextSwitch(0.0, 5.0), 5.0);
}

TEST(ContactSchedule, WalkingAlternatesFeetWithTheRequestedDoubleSupport) {
  const Gait g = walk(0.8, 0.2);
  const ContactSchedule s(g, 0.0);
  double both = 0, left = 0, right = 0, total = 0;
  for (double t = 0; t < 8.0; t += kDt) {
    const ContactFlags f = s.flagsAt(t);
    const bool l = footInSwing(f, true), r = footInSwing(f, false);
    ASSERT_FALSE(l && r) << "both feet in the air at t = " << t;
    both += !l && !r;
    left += l;
    right += r;
    total += 1;
  }
  EXPECT_NEAR(both / total, 0.2, 0.005);
  EXPECT_NEAR(left / total, 0.4, 0.005);
  EXPECT_NEAR(right / total, 0.4, 0.005);
  for (double d : swingDurations(s, kLeftToe, 0, 8)) EXPECT_NEAR(d, g.swingDuration(), 2 * kDt);
  // Phase 0 is a double support, the left foot swings first.
  EXPECT_EQ(s.flagsAt(0.01), kAllStance);
  EXPECT_FALSE(s.inStance(kLeftToe, 0.1));
  EXPECT_TRUE(s.inStance(kRightToe, 0.1));
}

TEST(ContactSchedule, HeelLeavesAndLandsBeforeItsToe) {
  const ContactSchedule s(walk(0.8, 0.2, 0.05), 0.0);
  SwingInterval heel, toe;
  ASSERT_TRUE(s.swingAround(kLeftHeel, 0.0, 2.0, heel));
  ASSERT_TRUE(s.swingAround(kLeftToe, 0.0, 2.0, toe));
  EXPECT_NEAR(toe.liftOff - heel.liftOff, 0.05, 1e-12);
  EXPECT_NEAR(toe.touchDown - heel.touchDown, 0.05, 1e-12);
}

TEST(ContactSchedule, NextSwitchMatchesSampledFlagChanges) {
  const ContactSchedule s(walk(0.7, 0.3, 0.03), 0.2);
  for (double t = 0.0; t < 3.0; t += 0.037) {
    const double next = s.nextSwitch(t, t + 2.0);
    const ContactFlags now = s.flagsAt(t + 1e-7);
    // No change strictly before `next`, a change right after it.
    for (double u = t + kDt; u < next - 2e-6; u += kDt) ASSERT_EQ(s.flagsAt(u), now) << t << " " << u;
    EXPECT_NE(s.flagsAt(next + 1e-6), s.flagsAt(next - 1e-6)) << "t = " << t;
  }
}

TEST(ContactSchedule, StartingToWalkIsImmediateAndStoppingWaitsForTheSwingToEnd) {
  ContactSchedule s(Gait{}, 0.0);
  EXPECT_DOUBLE_EQ(s.setGait(walk(), 1.0), 1.0);
  EXPECT_FALSE(s.inStance(kLeftToe, 1.0 + 0.1 + 0.05));
  // Stop in the middle of the left swing (swing: [1.08, 1.40]): takes effect at the next
  // double-support start, 1.4.
  const double stop = s.setGait(Gait{}, 1.2);
  EXPECT_NEAR(stop, 1.4, 1e-9);
  for (double d : swingDurations(s, kLeftToe, 0.9, 3.0)) EXPECT_NEAR(d, 0.32, 2 * kDt);
  for (double t = 1.41; t < 4; t += 0.01) EXPECT_EQ(s.flagsAt(t), kAllStance);
  EXPECT_TRUE(s.gaitAt(1.39).walking);  // the request is recorded; walking runs until 1.4
  EXPECT_FALSE(s.gaitAt(1.41).walking);
  EXPECT_FALSE(s.latestGait().walking);
}

TEST(ContactSchedule, ChangingTheWalkKeepsFeetAlternating) {
  ContactSchedule s(walk(0.8, 0.2), 0.0);
  // Request at 0.5 (the right foot swinging, 0.48-0.8): takes effect at the next double support,
  // a cycle boundary.
  const double at = s.setGait(walk(0.6, 0.2), 0.5);
  EXPECT_NEAR(at, 0.8, 1e-9);
  // Sequence of swinging feet never repeats a foot.
  int last = -1;
  bool wasSwinging = false;
  for (double t = 0; t < 4; t += kDt) {
    const ContactFlags f = s.flagsAt(t);
    const bool l = footInSwing(f, true), r = footInSwing(f, false);
    if ((l || r) && !wasSwinging) {
      const int foot = l ? 0 : 1;
      EXPECT_NE(foot, last) << "same foot twice at t = " << t;
      last = foot;
    }
    wasSwinging = l || r;
  }
  for (double d : swingDurations(s, kRightToe, at + 0.01, 4)) EXPECT_NEAR(d, 0.24, 2 * kDt);
}

TEST(ContactSchedule, AStepTimingChangeTakesEffectAtTheNextDoubleSupport) {
  ContactSchedule s(walk(0.8, 0.2), 0.0);
  // Request at 0.3 (the left foot swinging, 0.08-0.4): takes effect at 0.4, half a cycle in,
  // where the right foot's turn comes: the new cycle starts with it (a 0.06 s double support,
  // then its 0.24 s swing, 0.46-0.7), then the left's (0.76-1.0).
  const double at = s.setGait(walk(0.6, 0.2), 0.3);
  EXPECT_NEAR(at, 0.4, 1e-9);
  EXPECT_TRUE(s.latestGait().rightFirst);
  EXPECT_EQ(s.setGait(walk(0.6, 0.2), 0.35), at);  // asked again: the same change
  const auto right = swingDurations(s, kRightToe, 0.41, 0.75);
  ASSERT_EQ(right.size(), 1u);
  EXPECT_NEAR(right[0], 0.24, 2 * kDt);
  EXPECT_FALSE(s.inStance(kRightToe, 0.6));
  EXPECT_TRUE(s.inStance(kLeftToe, 0.6));
  EXPECT_FALSE(s.inStance(kLeftToe, 0.9));
  EXPECT_TRUE(s.inStance(kRightToe, 0.9));
}

TEST(SwingTrajectory, EndsAtRestAndReachesTheApexAtMidSwing) {
  SwingTrajectory s;
  s.liftOff = 1.0;
  s.touchDown = 1.4;
  s.liftOffPosition = {0.1, 0.2, 0.0};
  s.touchDownPosition = {0.4, 0.25, 0.15};
  s.apexHeight = 0.25;
  const PointReference a = s.at(1.0), b = s.at(1.4), mid = s.at(1.2);
  EXPECT_LT((a.position - s.liftOffPosition).norm(), 1e-12);
  EXPECT_LT((b.position - s.touchDownPosition).norm(), 1e-12);
  EXPECT_LT(a.velocity.norm(), 1e-12);
  EXPECT_LT(b.velocity.norm(), 1e-12);
  EXPECT_NEAR(mid.position.z(), 0.25, 1e-12);
  EXPECT_NEAR(mid.velocity.z(), 0.0, 1e-12);
  for (double t = 1.01; t < 1.39; t += 0.013) {
    const double h = 1e-6;
    const PointReference p = s.at(t), pp = s.at(t + h), pm = s.at(t - h);
    EXPECT_LT(((pp.position - pm.position) / (2 * h) - p.velocity).norm(), 1e-6);
    if (std::abs(t - 1.2) > 1e-3) {  // the vertical acceleration jumps at the apex
      EXPECT_LT(((pp.velocity - pm.velocity) / (2 * h) - p.acceleration).norm(), 1e-4);
    }
  }
}

TEST(SwingTrajectory, OverAStepTheFootRisesBeforeItMovesAndMovesBeforeItLands) {
  SwingTrajectory s;
  s.liftOff = 0.0;
  s.touchDown = 0.4;
  s.liftOffPosition = {0.0, 0.1, 0.0};
  s.touchDownPosition = {0.3, 0.1, 0.15};
  s.apexHeight = 0.35;
  s.lift = 0.2;
  // The first and last 20 % of the swing: vertical only.
  for (double t : {0.0, 0.04, 0.079}) {
    EXPECT_NEAR(s.at(t).position.x(), 0.0, 1e-12) << t;
    EXPECT_NEAR(s.at(t).velocity.x(), 0.0, 1e-12) << t;
  }
  EXPECT_GT(s.at(0.079).position.z(), 0.1);  // up by then
  for (double t : {0.321, 0.36, 0.4}) EXPECT_NEAR(s.at(t).position.x(), 0.3, 1e-12) << t;
  // In between the horizontal cubic, sped up to fit, still continuous in velocity.
  EXPECT_NEAR(s.at(0.2).position.x(), 0.15, 1e-12);
  for (double t = 0.01; t < 0.4; t += 0.013) {
    const double h = 1e-6;
    const PointReference p = s.at(t), pp = s.at(t + h), pm = s.at(t - h);
    EXPECT_LT(((pp.position - pm.position) / (2 * h) - p.velocity).norm(), 1e-6) << t;
  }
  // The toe of a foot 10 cm from a 15 cm stage edge, when it gets there, is above the stage.
  for (double t = 0.0; t <= 0.4; t += 0.001) {
    const PointReference p = s.at(t);
    if (p.position.x() >= 0.1) {
      EXPECT_GT(p.position.z(), 0.15) << t;
      break;
    }
  }
}

TEST(Footholds, EachTermOfTheEquation) {
  const FlatTerrain ground(0.02);
  FootholdParameters params = defaults().foothold;
  params.comHeight = 0.81;
  PlanarPose base;
  base.position = {1.0, 2.0, 0.8};
  const Eigen::Vector3d offset(0.1, 0.1, 0.0), zero = Eigen::Vector3d::Zero();
  // At rest: under the hip, on the ground.
  EXPECT_LT((raibertFoothold(base, offset, zero, zero, 0, 0.5, params, ground) -
             Eigen::Vector3d(1.1, 2.1, 0.02))
                .norm(),
            1e-12);
  // Raibert: half the stance duration times the desired velocity.
  const Eigen::Vector3d vd(0.8, 0, 0);
  EXPECT_NEAR(raibertFoothold(base, offset, vd, vd, 0, 0.5, params, ground).x(), 1.1 + 0.2, 1e-12);
  // Capture-point feedback: k (v − v_des).
  const Eigen::Vector3d v(1.0, 0, 0);
  EXPECT_NEAR(raibertFoothold(base, offset, v, vd, 0, 0.5, params, ground).x(),
              1.1 + 0.2 + 0.15 * 0.2, 1e-12);
  // Centrifugal: walking forward and turning left puts the foot further right, by the centre of
  // pressure's offset that gives the pendulum the turn's inward acceleration v·ω = 0.5 m/s²:
  // (h/g)·v·ω = 0.81 / 9.81 · 0.5 = 4.13 cm.
  const Eigen::Vector3d p = raibertFoothold(base, offset, v, v, 0.5, 0.5, params, ground);
  EXPECT_NEAR(p.y(), 2.1 - 0.81 / 9.81 * 1.0 * 0.5, 1e-12);
  // Heading: the offset turns with the base.
  base.yaw = M_PI / 2;
  EXPECT_LT((raibertFoothold(base, offset, zero, zero, 0, 0.5, params, ground).head<2>() -
             Eigen::Vector2d(0.9, 2.1))
                .norm(),
            1e-12);
}

TEST(Footholds, PredictedPoseFollowsTheCommandedArc) {
  PlanarPose start;
  start.position = {0.3, -0.2, 0.8};
  start.yaw = 0.4;
  const VelocityCommand cmd{0.7, 0.2, 0.6};
  PlanarPose numeric = start;
  const double dt = 1e-5;
  for (int i = 0; i < 100000; ++i) {  // 1 s of Euler steps
    const double c = std::cos(numeric.yaw), s = std::sin(numeric.yaw);
    numeric.position += dt * Eigen::Vector3d(c * cmd.vx - s * cmd.vy, s * cmd.vx + c * cmd.vy, 0);
    numeric.yaw += dt * cmd.yawRate;
  }
  const PlanarPose exact = start.predicted(cmd, 1.0);
  EXPECT_LT((exact.position - numeric.position).norm(), 1e-4);
  EXPECT_NEAR(exact.yaw, numeric.yaw, 1e-9);
}

/// A 10 cm stage for x > 0.5.
class Stage final : public TerrainQuery {
 public:
  double height(double x, double) const override { return x > 0.5 ? 0.10 : 0.0; }
};

class SwingPlannerTest : public ::testing::Test {
 protected:
  std::array<Eigen::Vector3d, kNumContacts> offsets{
      Eigen::Vector3d(0.13, 0.1, 0), Eigen::Vector3d(-0.07, 0.1, 0),
      Eigen::Vector3d(0.13, -0.1, 0), Eigen::Vector3d(-0.07, -0.1, 0)};
  GaitState state() const {
    GaitState s;
    s.base.position = {0, 0, 0.85};
    for (int c = 0; c < kNumContacts; ++c) s.contactPositions[c] = offsets[c];
    return s;
  }
  /// A planner updated at time t walking the 0.8 s gait at 0.5 m/s, as commanded, from state().
  SwingPlanner walkingAtHalfAMetreASecond(double t) const {
    SwingPlanner planner(defaults(), offsets);
    GaitState s = state();
    s.t = t;
    s.baseVelocity = s.comVelocity = Eigen::Vector3d{0.5, 0, 0};
    planner.update(ContactSchedule(walk(0.8, 0.2), 0.0), s, VelocityCommand{0.5, 0, 0}, 1.0,
                   FlatTerrain());
    return planner;
  }
};

TEST_F(SwingPlannerTest, WalkingForwardChainsSwingsAndStepsAhead) {
  const SwingPlanner planner = walkingAtHalfAMetreASecond(0.0);
  const SwingTrajectory* first = planner.swingAt(kLeftToe, 0.2);
  ASSERT_NE(first, nullptr);
  EXPECT_LT((first->liftOffPosition - offsets[kLeftToe]).norm(), 1e-12);
  // Lands where the hip will be at touch-down plus half a stance of travel.
  const double expectedX = 0.13 + 0.5 * first->touchDown + 0.5 * 0.48 * 0.5;
  EXPECT_NEAR(first->touchDownPosition.x(), expectedX, 1e-9);
  EXPECT_NEAR(planner.reference(kLeftToe, 0.5).position.x(), expectedX, 1e-9);  // landed
  EXPECT_NEAR(first->apexHeight, 0.08, 1e-12);
  // The right foot's swing within the horizon starts where it stands.
  const SwingTrajectory* right = planner.swingAt(kRightToe, 0.6);
  ASSERT_NE(right, nullptr);
  EXPECT_LT((right->liftOffPosition - offsets[kRightToe]).norm(), 1e-12);
}

TEST_F(SwingPlannerTest, ApexClearsTheTerrainAndFootholdsSitOnIt) {
  const ContactSchedule schedule(walk(0.8, 0.2), 0.0);
  SwingPlanner planner(defaults(), offsets);
  GaitState s = state();
  s.base.position.x() = 0.3;
  s.baseVelocity = s.comVelocity = Eigen::Vector3d{0.6, 0, 0};
  planner.update(schedule, s, VelocityCommand{0.6, 0, 0}, 1.0, Stage());
  const SwingTrajectory* sw = planner.swingAt(kLeftToe, 0.2);
  ASSERT_NE(sw, nullptr);
  ASSERT_GT(sw->touchDownPosition.x(), 0.5);
  EXPECT_DOUBLE_EQ(sw->touchDownPosition.z(), 0.10);
  EXPECT_NEAR(sw->apexHeight, 0.18, 1e-12);
  EXPECT_DOUBLE_EQ(sw->lift, defaults().stepLift);  // a step up: lift first
  // A swing on the flat floor is no step.
  planner.update(schedule, state(), VelocityCommand{0.1, 0, 0}, 1.0, Stage());
  const SwingTrajectory* flat = planner.swingAt(kLeftToe, 0.2);
  ASSERT_NE(flat, nullptr);
  ASSERT_LT(flat->touchDownPosition.x(), 0.5);
  EXPECT_DOUBLE_EQ(flat->lift, 0.0);
}

/// A 4 cm block just ahead of the left foot's toe, beside its line (2 to 8 cm to its left).
class BlockBesideTheToe final : public TerrainQuery {
 public:
  double height(double x, double y) const override {
    return x > 0.135 && x < 0.18 && y > 0.12 && y < 0.18 ? 0.04 : 0.0;
  }
};

TEST_F(SwingPlannerTest, TheSolesSidesClearTheGroundBesideThePointsPath) {
  // The toe's own line stays on the floor; the side of its sole passes over the block: a step,
  // so the foot rises before it moves, and its apex clears the block.
  const ContactSchedule schedule(walk(0.8, 0.2), 0.0);
  SwingPlanner planner(defaults(), offsets);
  planner.update(schedule, state(), VelocityCommand{0.3, 0, 0}, 1.0, BlockBesideTheToe());
  const SwingTrajectory* sw = planner.swingAt(kLeftToe, 0.2);
  ASSERT_NE(sw, nullptr);
  ASSERT_GT(sw->touchDownPosition.x(), 0.18 + defaults().search.patch);  // past the block
  EXPECT_DOUBLE_EQ(sw->touchDownPosition.z(), 0.0);
  EXPECT_NEAR(sw->apexHeight, 0.04 + defaults().apexClearance, 1e-12);
  EXPECT_DOUBLE_EQ(sw->lift, defaults().stepLift);
}

TEST_F(SwingPlannerTest, FeetNeverCrossEvenWhenCommandedSideways) {
  const ContactSchedule schedule(walk(0.8, 0.2), 0.0);
  SwingPlannerParameters params = defaults();
  params.minFeetDistance = 0.15;
  SwingPlanner planner(params, offsets);
  GaitState s = state();
  s.baseVelocity = s.comVelocity = Eigen::Vector3d{0, -0.6, 0};  // moving right fast: the left foot's foothold would cross
  planner.update(schedule, s, VelocityCommand{0, -0.6, 0}, 1.0, FlatTerrain());
  const SwingTrajectory* sw = planner.swingAt(kLeftToe, 0.2);
  ASSERT_NE(sw, nullptr);
  EXPECT_GE(sw->touchDownPosition.y() - s.contactPositions[kRightToe].y(), 0.15 - 1e-12);
}

TEST_F(SwingPlannerTest, TheCapturePointSaysWhenItsStepIsHeldToTheLimits) {
  // Walking in place, pushed sideways: 300 N on 50 kg is a force offset of 0.49 m at a pendulum
  // of 0.8 m, so the capture point asks the left foot to land beyond the widest step (0.45 m
  // from the stance foot): the step is held to the limits, which the planner's step timing
  // reads (LocomotionPlanner: the gait walks gait.recovery_min_period then). The paper's rule
  // has no such steps.
  const ContactSchedule schedule(walk(0.8, 0.2), 0.0);
  SwingPlannerParameters params = defaults();
  params.rule = FootholdRule::kCapturePoint;
  params.foothold.comHeight = 0.8;
  GaitState s = state();
  s.mass = 50.0;
  s.com = Eigen::Vector3d(0.03, 0.0, 0.8);
  auto limited = [&](const SwingPlannerParameters& p, double push) {
    SwingPlanner planner(p, offsets);
    s.externalForce = Eigen::Vector3d(0.0, push, 0.0);
    planner.update(schedule, s, VelocityCommand{}, 1.0, FlatTerrain());
    return planner.stepsLimited();
  };
  EXPECT_TRUE(limited(params, 300.0));
  EXPECT_FALSE(limited(defaults(), 300.0));
}

TEST_F(SwingPlannerTest, TheLongestNextSwingIsOfTheFeetStillToLift) {
  // Walking at 0.5 m/s as commanded, the paper's rule: a foot lands 0.13 + 0.5·(t_td − t) +
  // 0.5·0.48·0.5 = 0.25 + 0.5·(t_td − t) ahead (the base at x 0 now).
  // At 0 neither foot has lifted: the left swings 0.08-0.4 from 0.13 to 0.45 (0.32 m), the right
  // 0.48-0.8 from 0.13 to 0.65 (0.52 m).
  EXPECT_NEAR(walkingAtHalfAMetreASecond(0.0).longestNextSwing(0.0), 0.52, 1e-9);
  // At 0.1 the left foot is in the air: its swing now is not counted, its next one is (0.88-1.2,
  // from 0.40 to 0.80: 0.40 m); the right swings from 0.13 to 0.60 (0.47 m).
  SwingPlanner planner = walkingAtHalfAMetreASecond(0.1);
  EXPECT_NEAR(planner.longestNextSwing(0.1), 0.47, 1e-9);
  // Standing: no swing.
  GaitState s = state();
  s.t = 0.1;
  planner.update(ContactSchedule(), s, VelocityCommand{}, 1.0, FlatTerrain());
  EXPECT_EQ(planner.longestNextSwing(0.1), 0.0);
}

TEST_F(SwingPlannerTest, ASwingInProgressKeepsItsLiftOffAndHoldsItsTargetLate) {
  const ContactSchedule schedule(walk(0.8, 0.2), 0.0);
  SwingPlanner planner(defaults(), offsets);
  GaitState s = state();
  planner.update(schedule, s, VelocityCommand{0.5, 0, 0}, 1.0, FlatTerrain());
  const SwingTrajectory first = *planner.swingAt(kLeftToe, 0.1);
  // Later, mid-swing, the robot has moved and the measured foot is elsewhere: lift-off stays.
  s.t = 0.15;
  s.contactPositions[kLeftToe] += Eigen::Vector3d(0.05, 0, 0.03);
  planner.update(schedule, s, VelocityCommand{0.5, 0, 0}, 1.0, FlatTerrain());
  EXPECT_LT((planner.swingAt(kLeftToe, 0.16)->liftOffPosition - first.liftOffPosition).norm(), 1e-12);
  // After 70 % of the swing a new command no longer moves the touch-down.
  s.t = 0.08 + 0.8 * 0.32;
  const Eigen::Vector3d held = planner.swingAt(kLeftToe, s.t)->touchDownPosition;
  planner.update(schedule, s, VelocityCommand{-0.5, 0.3, 0}, 1.0, FlatTerrain());
  EXPECT_LT((planner.swingAt(kLeftToe, s.t)->touchDownPosition - held).norm(), 1e-12);
}

TEST_F(SwingPlannerTest, AHeldSwingHandedToTheCapturePointIsSteppedOnFromWhereItLands) {
  // Walking forward on the paper's footholds, 3.6 m from the origin; late in the left foot's
  // swing (its touch-down held) a push hands the footholds to the capture point (the walking
  // push switch). The held swing keeps its target and the capture point steps on from it: the
  // right foot's next step lands within a step of it, as the paper's would. With the paper's
  // swings not saying where their foot lands, it stepped about the origin (a fall).
  const ContactSchedule schedule(walk(0.8, 0.2), 0.0);
  SwingPlanner planner(defaults(), offsets);
  GaitState s = state();
  const Eigen::Vector3d away(3.0, 2.0, 0.0);
  s.base.position += away;
  s.com = s.base.position;
  for (Eigen::Vector3d& p : s.contactPositions) p += away;
  s.baseVelocity = s.comVelocity = Eigen::Vector3d{0.5, 0, 0};
  s.mass = 50.0;
  const VelocityCommand cmd{0.5, 0, 0};
  planner.update(schedule, s, cmd, 1.0, FlatTerrain());
  s.t = 0.08 + 0.8 * 0.32;
  planner.update(schedule, s, cmd, 1.0, FlatTerrain());
  const SwingTrajectory held = *planner.swingAt(kLeftToe, s.t);
  SwingPlannerParameters capture = defaults();
  capture.rule = FootholdRule::kCapturePoint;
  planner.setParameters(capture);
  planner.update(schedule, s, cmd, 1.0, FlatTerrain());
  EXPECT_LT((planner.swingAt(kLeftToe, s.t)->touchDownPosition - held.touchDownPosition).norm(),
            1e-12);
  const SwingTrajectory* right = planner.swingAt(kRightToe, 0.6);
  ASSERT_NE(right, nullptr);
  EXPECT_LT((right->touchDownPosition - held.touchDownPosition).head<2>().norm(),
            capture.limits.maxForward + capture.limits.maxWidth);
}

TEST_F(SwingPlannerTest, AcrossAPushAxisTheFootholdsMoveTowardsThePapers) {
  // Walking at 0.5 m/s, pushed along the walk on a 50 kg robot (gait::walkingPushAxis): with
  // the capture axis along x each touch-down is the capture point's along x, and along y the
  // capture point's moved paperAcross of the way to the paper's. The push is diagonal so that
  // the two rules differ both ways.
  const ContactSchedule schedule(walk(0.8, 0.2), 0.0);
  GaitState s = state();
  s.mass = 50.0;
  s.com = Eigen::Vector3d(0.03, 0.0, 0.8);
  s.baseVelocity = s.comVelocity = Eigen::Vector3d{0.7, 0.2, 0};
  s.externalForce = Eigen::Vector3d(80.0, 60.0, 0.0);
  const VelocityCommand cmd{0.5, 0, 0};
  auto touchDowns = [&](FootholdRule rule, double paperAcross) {
    SwingPlannerParameters p = defaults();
    p.rule = rule;
    p.foothold.comHeight = 0.8;
    p.walkingPush.axis = Eigen::Vector2d::UnitX();
    p.walkingPush.paperAcross = paperAcross;
    SwingPlanner planner(p, offsets);
    planner.update(schedule, s, cmd, 1.0, FlatTerrain());
    return std::array<Eigen::Vector3d, 2>{planner.swingAt(kLeftToe, 0.2)->touchDownPosition,
                                          planner.swingAt(kRightToe, 0.6)->touchDownPosition};
  };
  const auto paper = touchDowns(FootholdRule::kPaper, 0.0);
  const auto capture = touchDowns(FootholdRule::kCapturePoint, 0.0);
  for (const double share : {1.0, 0.25}) {
    const auto blended = touchDowns(FootholdRule::kCapturePoint, share);
    for (int foot = 0; foot < 2; ++foot) {
      ASSERT_GT(std::abs(paper[foot].x() - capture[foot].x()), 0.01) << foot;
      ASSERT_GT(std::abs(paper[foot].y() - capture[foot].y()), 0.01) << foot;
      EXPECT_NEAR(blended[foot].x(), capture[foot].x(), 1e-9) << foot << " " << share;
      EXPECT_NEAR(blended[foot].y(),
                  capture[foot].y() + share * (paper[foot].y() - capture[foot].y()), 1e-9)
          << foot << " " << share;
    }
  }
}

/// Nothing observed anywhere: every placement the foothold search tries fails at its first
/// known(), so the calls count the placements tried.
class UnknownTerrain final : public TerrainQuery {
 public:
  double height(double, double) const override { return 0.0; }
  bool known(double, double) const override {
    ++calls;
    return false;
  }
  mutable int calls = 0;
};

TEST_F(SwingPlannerTest, TheFootholdSearchRunsOncePerFootAndTouchDown) {
  const ContactSchedule schedule(walk(0.8, 0.2), 0.0);
  SwingPlannerParameters params = defaults();
  params.rule = FootholdRule::kPaper;
  ASSERT_TRUE(params.search.enabled);
  SwingPlanner planner(params, offsets);
  GaitState s = state();
  s.baseVelocity = s.comVelocity = Eigen::Vector3d{0.5, 0, 0};
  UnknownTerrain terrain;
  planner.update(schedule, s, VelocityCommand{0.5, 0, 0}, 1.0, terrain);
  // One search: the paper's placement, then every grid offset within the foot's window.
  const FootholdSearchParameters& f = params.search;
  const double radius = searchRadius(offsets[kLeftToe], offsets[kLeftHeel], f);
  ASSERT_EQ(radius, searchRadius(offsets[kRightToe], offsets[kRightHeel], f));
  const int n = static_cast<int>(std::floor(radius / f.step + 1e-9));
  int placements = 1;
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      placements += (i * i + j * j) * f.step * f.step <= radius * radius + 1e-12;
  // Toe and heel land together (no toe-off lead): one search per swing of each foot.
  const int swings = planner.swingCount(kLeftToe) + planner.swingCount(kRightToe);
  ASSERT_EQ(planner.swingCount(kLeftHeel) + planner.swingCount(kRightHeel), swings);
  ASSERT_GT(swings, 0);
  EXPECT_EQ(terrain.calls, swings * placements);
}

}  // namespace
}  // namespace ballast::gait
