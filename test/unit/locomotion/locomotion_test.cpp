// The planner pipeline closed on its own model: each update the state advances along eq. (1)
// with the planned inputs for one planner period and is fed back. A plan that cannot walk its
// own model cannot walk the robot.
#include <gtest/gtest.h>

#include "control/map_terrain.hpp"
#include "locomotion/locomotion_planner.hpp"
#include "model/algorithms.hpp"
#include "test/unit/plan_support.hpp"
#include "test/unit/settings_support.hpp"
#include "test/unit/test_support.hpp"

namespace ballast::locomotion {
namespace {

using model::CentroidalLayout;

LocomotionSettings defaultSettings(const model::Model& m) {
  LocomotionSettings s = test::controlDefaults().locomotion;
  const Eigen::VectorXd q = test::standingConfiguration(m);
  s.nominalJoints = q.tail(m.nj());
  s.nominalHeight = q[2];
  s.armJoint.assign(m.nj(), false);
  for (int j = 0; j < m.nj(); ++j) s.armJoint[j] = m.jointName[j + 1].find("shoulder") != std::string::npos ||
                                                   m.jointName[j + 1].find("elbow") != std::string::npos ||
                                                   m.jointName[j + 1].find("wrist") != std::string::npos;
  return s;
}

/// The robot as the planner's model sees it. Two ways to move it over one planner period:
///  kFollowPlan   — it is where the plan said it would be (a perfect whole-body controller),
///  kOpenLoop     — eq. (1) integrated in 1 ms steps under the plan's inputs, with no state
///                  feedback at all: what the plan's forward-Euler discretisation misses
///                  accumulates until the next plan corrects it.
enum class Tracking { kFollowPlan, kOpenLoop };

class OwnModelWorld {
 public:
  OwnModelWorld(const model::Model& m, const std::array<int, 4>& frames)
      : m_(m), frames_(frames.begin(), frames.end()), data_(m), L_{m.nj(), 4} {}

  void advance(Eigen::VectorXd& x, const Plan& plan, double t, double duration, Tracking how) {
    Eigen::VectorXd u(L_.nu()), xdot(L_.nx());
    const double k = std::clamp((t + duration - plan.t0) / plan.dt, 0.0, plan.nodes - 1e-9);
    const int i = static_cast<int>(k);
    u = Eigen::Map<const Eigen::VectorXd>(plan.u[std::min(i, plan.nodes - 1)], plan.nu);
    if (how == Tracking::kFollowPlan) {
      x = (i + 1 - k) * Eigen::Map<const Eigen::VectorXd>(plan.x[i], plan.nx) +
          (k - i) * Eigen::Map<const Eigen::VectorXd>(plan.x[i + 1], plan.nx);
    } else {
      for (double s = 0; s < duration - 1e-9; s += 1e-3) {
        const double n = std::clamp((t + s - plan.t0) / plan.dt, 0.0, plan.nodes - 1.0);
        u = Eigen::Map<const Eigen::VectorXd>(plan.u[static_cast<int>(n)], plan.nu);
        model::centroidalDynamics(m_, data_, frames_, x, u, xdot);
        x += 1e-3 * xdot;
      }
    }
    lastU_ = u;
  }
  /// Model (q, v) for the planner's x (joint velocities from the last input).
  void toModel(const Eigen::VectorXd& x, Eigen::VectorXd& q, Eigen::VectorXd& v) {
    Eigen::VectorXd xdot(L_.nx());
    model::centroidalDynamics(m_, data_, frames_, x, lastU_, xdot);
    const Eigen::Vector3d zyx = x.segment<3>(L_.kBaseZyx);
    q = model::configurationFromZyx(m_, x.segment<3>(L_.kBasePosition), zyx, x.tail(m_.nj()));
    v.resize(m_.nv);
    v << model::baseVelocityFromZyxRates<double>(zyx, xdot.segment<3>(L_.kBasePosition),
                                                 xdot.segment<3>(L_.kBaseZyx)),
        lastU_.tail(m_.nj());
  }
  Eigen::VectorXd lastU_;

 private:
  const model::Model& m_;
  std::vector<int> frames_;
  model::Data<double> data_;
  CentroidalLayout L_;
};

class Locomotion : public ::testing::Test {
 public:
  const model::Model& m = test::humanoid();
  LocomotionSettings settings = defaultSettings(m);
  gait::FlatTerrain ground;

  /// Runs the planner closed on its own model for `duration`; returns the base x positions.
  std::vector<double> run(LocomotionPlanner& planner, const LocomotionCommand& cmd, double duration,
                          Eigen::VectorXd& q, Eigen::VectorXd& v, Plan& plan, double& t,
                          Tracking how = Tracking::kFollowPlan) {
    OwnModelWorld world(m, contactFrameIds(m, settings));
    world.lastU_ = Eigen::VectorXd::Zero(CentroidalLayout{m.nj(), 4}.nu());
    std::vector<double> xs;
    const double period = 0.01;
    for (; duration > 1e-9; duration -= period, t += period) {
      const bool ok = planner.update(t, q, v, cmd, plan);
      EXPECT_TRUE(ok) << "t = " << t << ": " << planner.statistics().message;
      if (!ok) break;
      Eigen::VectorXd x = planner.measuredState(q, v);
      world.advance(x, plan, t, period, how);
      world.toModel(x, q, v);
      xs.push_back(q[0]);
    }
    return xs;
  }

  /// A robot standing on the planner's own model at t = 0, commanded to walk at `vx`; run()
  /// closes the planner on that model as the fixture's run() does.
  struct Walk {
    Walk(Locomotion& fixture, double vx)
        : f(fixture),
          planner(f.m, f.settings, f.ground),
          q(test::standingConfiguration(f.m)),
          v(Eigen::VectorXd::Zero(f.m.nv)) {
      cmd.walk = true;
      cmd.vx = vx;
    }
    std::vector<double> run(double duration, Tracking how = Tracking::kFollowPlan) {
      return f.run(planner, cmd, duration, q, v, plan, t, how);
    }
    Locomotion& f;
    LocomotionPlanner planner;
    Eigen::VectorXd q, v;
    Plan plan;
    double t = 0;
    LocomotionCommand cmd;
  };
};

TEST_F(Locomotion, StandsOnItsOwnModel) {
  LocomotionPlanner planner(m, settings, ground);
  Eigen::VectorXd q = test::standingConfiguration(m), v = Eigen::VectorXd::Zero(m.nv);
  q[0] += 0.02;  // off centre
  Plan plan;
  double t = 0;
  run(planner, LocomotionCommand{}, 2.0, q, v, plan, t);
  PlanSampler sampler(m, contactFrameIds(m, settings));
  PlanSample s;
  sampler.sample(plan, t, s);
  double fz = 0;
  for (int c = 0; c < 4; ++c) fz += s.contactForce[c].z();
  EXPECT_NEAR(fz, m.totalMass() * 9.81, 0.02 * m.totalMass() * 9.81);
  EXPECT_LT(s.baseLinearVelocity.norm(), 0.05);
  EXPECT_NEAR(q[2], settings.nominalHeight, 0.02);
}

/// Walks at `vx` for 4 s; returns the mean speed over the last 2 s.
double walkSpeed(Locomotion& f, double vx, Tracking how, Eigen::VectorXd& q) {
  Locomotion::Walk walk(f, vx);
  const std::vector<double> xs = walk.run(4.0, how);
  q = walk.q;
  EXPECT_EQ(xs.size(), 400u);
  if (xs.size() != 400u) return 0.0;
  return (xs[399] - xs[199]) / 2.0;
}

TEST_F(Locomotion, StepsOntoTheLabStageAtItsHeight) {
  // maps/lab-stage.bt (a 15 cm stage from x = 1.5 m, 2 cm cells) through the planner's terrain
  // binding; the robot walks at 0.5 m/s from x = 1.0 m along its own plan.
  const control::MapTerrain stage(std::make_shared<const terrain::HeightMap>(
      terrain::HeightMap::fromFile(std::string(BALLAST_SOURCE_DIR) + "/maps/lab-stage.bt", 0.0)));
  constexpr double kEdge = 1.5, kHeight = 0.15, kHalfCell = 0.0101;
  LocomotionPlanner planner(m, settings, stage);
  Eigen::VectorXd q = test::standingConfiguration(m), v = Eigen::VectorXd::Zero(m.nv);
  q[0] = 1.0;
  LocomotionCommand cmd;
  cmd.walk = true;
  cmd.vx = 0.5;
  Plan plan;
  double t = 0;
  int onStage = 0, onFloor = 0;
  for (int chunk = 0; chunk < 30 && !HasFailure(); ++chunk) {  // 3 s, 0.1 s at a time
    run(planner, cmd, 0.1, q, v, plan, t);
    for (const test::TouchDown& s : test::plannedTouchDowns(plan)) {
      const double x = s.position.x(), z = s.position.z();
      if (x > kEdge + 0.02) {
        EXPECT_NEAR(z, kHeight, kHalfCell)
            << "t = " << t << ", contact " << s.contact << " at x " << x;
        ++onStage;
      } else if (x < kEdge - 0.02) {
        EXPECT_NEAR(z, 0.0, 1e-9) << "t = " << t << ", contact " << s.contact << " at x " << x;
        ++onFloor;
      }
    }
  }
  EXPECT_GT(onFloor, 0);
  EXPECT_GT(onStage, 0);
  // By now the feet are on the stage in the plan's own model, the stance ones on its top.
  EXPECT_GT(q[0], kEdge + 0.5);
  model::Data<double> d(m);
  model::forwardKinematics(m, d, q);
  const std::array<int, kNumContacts> frames = contactFrameIds(m, settings);
  for (int c = 0; c < kNumContacts; ++c) {
    const Eigen::Vector3d p = model::framePlacement(m, d, frames[c]).p;
    EXPECT_GT(p.x(), kEdge + 0.02) << settings.contactFrames[c];
    if (plan.schedule.inStance(c, t)) {
      EXPECT_NEAR(p.z(), kHeight, 2 * kHalfCell) << settings.contactFrames[c];
    }
  }
}

TEST_F(Locomotion, PlansWalkingAtTheCommandedSpeed) {
  Eigen::VectorXd q;
  for (double vx : {0.5, 1.0}) {
    const double speed = walkSpeed(*this, vx, Tracking::kFollowPlan, q);
    std::printf("commanded %.2f m/s, planned and followed %.3f m/s\n", vx, speed);
    EXPECT_NEAR(speed, vx, 0.03 * vx) << vx;
    EXPECT_NEAR(q[2], settings.nominalHeight, 0.03);
    const Eigen::Vector3d zyx = model::zyxFromRotation(model::quaternionToRotation<double>(q.segment<4>(3)));
    EXPECT_LT(zyx.cwiseAbs().maxCoeff(), 0.1) << vx;
  }
}

TEST_F(Locomotion, TurningTheBodyLeansIntoTheTurnAsThePendulumDoes) {
  // Walking at 1.0 m/s and turning at +-0.4 rad/s the centre of mass accelerates inwards by
  // 0.4 m/s^2, and the reference leans the body in by atan(0.4 / 9.81) = 0.041 rad (a left
  // turn: roll < 0, the body's top to the left). Walked on its own model, the last of 4 s leans
  // in by 0.027-0.030 rad; upright in the reference it leaned out, by 0.011-0.014 rad.
  for (double yawRate : {0.4, -0.4}) {
    Walk walk(*this, 1.0);
    walk.cmd.yawRate = yawRate;
    walk.run(3.0);
    double roll = 0.0;
    int n = 0;
    for (; n < 100; ++n) {
      walk.run(0.01);
      roll += model::zyxFromRotation(model::quaternionToRotation<double>(walk.q.segment<4>(3)))[2];
    }
    roll /= n;
    const double lean = -std::atan(1.0 * yawRate / 9.81);
    std::printf("turning at %+.1f rad/s: mean roll %+.4f rad (the pendulum's lean %+.4f)\n",
                yawRate, roll, lean);
    EXPECT_NEAR(roll, lean, 0.5 * std::abs(lean)) << yawRate;
  }
}

TEST_F(Locomotion, WalksEvenWithoutStateFeedbackBetweenPlans) {
  // Open loop between plans, so the 20 ms forward-Euler model error accumulates each period.
  Eigen::VectorXd q;
  const double speed = walkSpeed(*this, 0.8, Tracking::kOpenLoop, q);
  std::printf("commanded 0.80 m/s, open loop between plans %.3f m/s\n", speed);
  EXPECT_NEAR(speed, 0.8, 0.1 * 0.8);
  EXPECT_NEAR(q[2], settings.nominalHeight, 0.05);
}

}  // namespace
}  // namespace ballast::locomotion

namespace ballast::locomotion {
namespace {

TEST_F(Locomotion, FirstStepWaitsForTheWeightShift) {
  // Asked to walk from standing, the plan keeps all four points down for walkStartDelay (plus
  // the gait's first half double support), and the base is not asked to move before.
  LocomotionPlanner planner(m, settings, ground);
  const Eigen::VectorXd q = test::standingConfiguration(m), v = Eigen::VectorXd::Zero(m.nv);
  Plan plan;
  LocomotionCommand cmd;
  cmd.walk = true;
  cmd.vx = 1.0;
  for (double t = 0.0; t < 0.2 + 1e-9; t += 0.01) ASSERT_TRUE(planner.update(t, q, v, cmd, plan));
  EXPECT_EQ(planner.commandedVelocity().vx, 0.0);
  const double firstLift =
      settings.walkStartDelay + 0.5 * settings.walkGait.doubleSupport * settings.walkGait.period;
  for (double t = 0.2; t < firstLift - 1e-3; t += 0.01)
    EXPECT_EQ(gait::numStance(plan.schedule.flagsAt(t)), 4) << t;
  EXPECT_EQ(gait::numStance(plan.schedule.flagsAt(firstLift + 0.01)), 2);
  ASSERT_TRUE(planner.update(settings.walkStartDelay + 0.1, q, v, cmd, plan));
  EXPECT_GT(planner.commandedVelocity().vx, 0.0);
}

TEST_F(Locomotion, SamplerInterpolatesInputsWithinAContactMode) {
  // Joint velocities and forces change linearly between nodes of one contact mode (so the
  // acceleration references the controller differentiates from them have no spikes), and hold
  // over a node where the mode changes (touch-down, lift-off jump by design).
  const CentroidalLayout L{m.nj(), 4};
  Plan plan;
  plan.nodes = 2;
  plan.dt = 0.02;
  plan.nx = L.nx();
  plan.nu = L.nu();
  const Eigen::VectorXd q = test::standingConfiguration(m);
  Eigen::VectorXd x(L.nx());
  x << Eigen::VectorXd::Zero(6), q.head<3>(), Eigen::Vector3d::Zero(), q.tail(m.nj());
  for (int k = 0; k <= 2; ++k) Eigen::Map<Eigen::VectorXd>(plan.x[k], L.nx()) = x;
  const int j = m.jointId("left_shoulder_pitch");
  plan.u[0][L.jointVelocity() + j] = 1.0;
  plan.u[1][L.jointVelocity() + j] = 3.0;
  plan.u[0][L.force(2) + 2] = 100.0;
  plan.u[1][L.force(2) + 2] = 300.0;
  PlanSampler sampler(m, contactFrameIds(m, settings));
  PlanSample s;

  plan.t0 = 1.0;  // standing: one mode throughout
  sampler.sample(plan, 1.005, s);
  EXPECT_NEAR(s.jointVelocities[j], 1.5, 1e-12);
  EXPECT_NEAR(s.contactForce[2].z(), 150.0, 1e-9);

  // Walking from 0: the left foot lifts at doubleSupport/2 · period = 0.08 s. Node 0 at 0.07
  // is double support, node 1 at 0.09 left swing.
  plan.schedule = gait::ContactSchedule(settings.walkGait, 0.0);
  plan.t0 = 0.07;
  sampler.sample(plan, 0.075, s);
  EXPECT_EQ(s.jointVelocities[j], 1.0);
  EXPECT_EQ(s.contactForce[2].z(), 100.0);
  sampler.sample(plan, 0.085, s);  // in the swing: the left points carry nothing
  EXPECT_EQ(s.contactForce[0].norm() + s.contactForce[1].norm(), 0.0);
}

}  // namespace
}  // namespace ballast::locomotion

namespace ballast::locomotion {
namespace {

TEST_F(Locomotion, APushWalkingHandsTheFootholdsToTheCapturePointUntilItHasPassed) {
  // gait.footholds paper: an estimated push over gait.recovery_walking_force switches the
  // footholds to the capture point's; once it has been under half that force for a gait cycle
  // they go back, at a double support. A push under it changes nothing.
  ASSERT_EQ(settings.swing.rule, gait::FootholdRule::kPaper);
  const double limit = settings.recovery.walkingPushForce(m.totalMass());  // N
  ASSERT_GT(limit, 0.0);
  Walk walk(*this, 0.5);
  const auto rule = [&] { return walk.plan.swings.parameters().rule; };
  walk.run(1.5);
  EXPECT_EQ(rule(), gait::FootholdRule::kPaper);
  walk.planner.setExternalForce(Eigen::Vector3d(0.0, 0.9 * limit, 0.0));
  walk.run(0.3);
  EXPECT_EQ(rule(), gait::FootholdRule::kPaper) << "a push under the limit";
  walk.planner.setExternalForce(Eigen::Vector3d(1.1 * limit, 0.0, 0.0));
  walk.run(0.02);
  EXPECT_EQ(rule(), gait::FootholdRule::kCapturePoint) << "the push";
  walk.planner.setExternalForce(Eigen::Vector3d(0.4 * limit, 0.0, 0.0));
  const double pushEnd = walk.t;
  const double period = settings.walkGait.period;
  double handedBack = -1.0;
  while (walk.t < pushEnd + 3.0 * period && handedBack < 0.0 && !HasFailure()) {
    walk.run(0.01);
    if (rule() == gait::FootholdRule::kPaper) handedBack = walk.t - 0.01;  // the update's time
  }
  ASSERT_GT(handedBack, 0.0) << "still on the capture point's footholds";
  EXPECT_GE(handedBack, pushEnd + period);
  EXPECT_LE(handedBack, pushEnd + 1.5 * period + 0.011);
  EXPECT_EQ(gait::numStance(walk.plan.schedule.flagsAt(handedBack)), kNumContacts)
      << "handed back in a swing";
}

TEST_F(Locomotion, APushWalkingTakesTheBaseReferenceWhereThePushTookTheBody) {
  // On the capture point's footholds for a push (gait.recovery_walking_force), the base
  // reference starts where the body is: the steps stop it, the plan does not pull it back to the
  // path it was pushed off. Off its path without a push, the plan goes back by
  // planner.max_position_lead.
  const double limit = settings.recovery.walkingPushForce(m.totalMass());  // N
  ASSERT_GT(limit, 0.0);
  const double lead = settings.maxPositionLead;
  ASSERT_GT(lead, 0.05);
  const CentroidalLayout L{m.nj(), kNumContacts};
  const int y = L.kBasePosition + 1;
  // The plan's base y at its last node relative to its first, the whole robot moved `off`
  // along +y after 1.5 s of walking, with a push along -x (the footholds' switch; against the
  // walk, the capture point's both ways: gait::walkingPushAxis) or none.
  const auto drift = [&](double push, double off) {
    Walk walk(*this, 0.5);
    walk.run(1.5);
    walk.planner.setExternalForce(Eigen::Vector3d(-push, 0.0, 0.0));
    walk.run(0.02);
    walk.q[1] += off;
    walk.run(0.01);
    return walk.plan.x[walk.plan.nodes][y] - walk.plan.x[0][y];
  };
  const double pushed = drift(1.1 * limit, 2.0 * lead);
  const double unpushed = drift(0.0, 2.0 * lead);
  EXPECT_NEAR(pushed, 0.0, 0.02) << "pulled back towards the path";
  EXPECT_LT(unpushed, -0.5 * lead) << "off its path unpushed, the plan went back";
}

}  // namespace
}  // namespace ballast::locomotion
