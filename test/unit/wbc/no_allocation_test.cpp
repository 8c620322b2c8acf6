// The 1 kHz path allocates nothing: the QP solver, the hierarchical solver and a whole controller
// tick, run on prepared objects, are watched by a counting malloc (as in test/unit/model).
#include <gtest/gtest.h>

#include "test/unit/allocation_counter.hpp"
#include "test/unit/settings_support.hpp"
#include "test/unit/wbc/qp_test_support.hpp"
#include "test/unit/wbc/wbc_test_support.hpp"

namespace ballast::test {
namespace {

using namespace wbc;

TEST(WbcNoAllocation, CounterSeesAnAllocation) {
  EXPECT_GT(allocationsIn([] { Eigen::VectorXd x(100); x.setZero(); }), 0);
}

TEST(WbcNoAllocation, QpSolver) {
  QpSolver qp(QpCapacity{42, 30, 40});
  std::mt19937 rng(1);
  randomFeasibleQp(qp, 42, 30, 40, rng);
  EXPECT_EQ(allocationsIn([&] { qp.solve(); }), 0);  // cold
  EXPECT_EQ(allocationsIn([&] { qp.solve(); }), 0);  // warm
  randomFeasibleQp(qp, 17, 5, 33, rng);
  EXPECT_EQ(allocationsIn([&] { qp.resize(17, 5, 33); }), 0);
  randomFeasibleQp(qp, 17, 5, 33, rng);
  EXPECT_EQ(allocationsIn([&] { qp.solve(); }), 0);
  ASSERT_EQ(qp.result().status, QpStatus::kOptimal);
}

TEST(WbcNoAllocation, ControllerTicks) {
  const model::Model& m = humanoid();
  for (const bool limits : {false, true}) {  // the joint limits' rows too
    for (WbcVariant variant : {WbcVariant::kHierarchical, WbcVariant::kWeighted}) {
      WbcSettings settings = wbcSettings();
      settings.variant = variant;
      settings.jointLimits = limits;
      WholeBodyController wbc(m, settings);
      settings.torqueLimit.assign(m.nj(), 5.0);  // slack and clamping paths
      WholeBodyController starved(m, settings);
      WbcReference ref = wbc.makeReference();
      WbcOutput out = wbc.makeOutput();
      std::vector<int> frames;
      for (const auto& f : settings.contactFrames) frames.push_back(m.frameId(f));
      std::mt19937 rng(2);
      const std::vector<std::vector<bool>> schedules{
          {true, true, true, true}, {true, true, false, false}, {false, false, false, false}};
      int qpSolves = 0;
      for (const auto& schedule : schedules) {
        ref.stance = schedule;
        const ConsistentMotion c = consistentMotion(m, frames, schedule, rng, 0.5, 3.0);
        consistentReferences(m, wbc, c, ref);
        ref.baseLinearAcceleration.y() += 8.0;  // beyond friction: QPs run
        const WbcState state{c.q, c.v};
        wbc.update(state, ref, out);  // first tick (warm starts begin)
        EXPECT_EQ(allocationsIn([&] { wbc.update(state, ref, out); }), 0) << toString(variant);
        qpSolves += out.qpSolves;
        EXPECT_EQ(allocationsIn([&] { starved.update(state, ref, out); }), 0) << toString(variant);
        // A push stepped out puts the base above the limbs (levels 2 and 3 of other sizes) and
        // back: neither change allocates.
        ref.pushStep = true;
        EXPECT_EQ(allocationsIn([&] { wbc.update(state, ref, out); }), 0) << toString(variant);
        ref.pushStep = false;
        EXPECT_EQ(allocationsIn([&] { wbc.update(state, ref, out); }), 0) << toString(variant);
        WbcState bad = state;
        bad.v[3] = std::nan("");
        EXPECT_EQ(allocationsIn([&] { wbc.update(bad, ref, out); }), 0);
        EXPECT_EQ(out.status, WbcStatus::kInvalidInput);
      }
      EXPECT_GT(qpSolves, 0);
    }
  }
}

// A profile switch reconfigures the loop's controller in place: other gains, variant, base frame,
// joint-space joints and torque limits, without allocating; then it ticks without allocating.
TEST(WbcNoAllocation, SettingsSwitch) {
  const model::Model& m = humanoid();
  const WbcSettings first = wbcSettings();
  WholeBodyController wbc(m, first);
  WbcSettings next = first;
  next.variant = WbcVariant::kWeighted;
  next.swingKp = 300;
  next.baseKd = {30, 30, 30, 30, 30, 30};
  next.jointSpaceJoints.clear();  // arms and legs both in joint space
  for (int j = 0; j < m.nj(); ++j) next.jointSpaceJoints.push_back(m.jointName[j + 1]);
  next.torqueLimit.assign(m.nj(), 50.0);
  next.jointLimits = true;
  ASSERT_FALSE(validateSettings(next, m));
  bool taken = false;
  EXPECT_EQ(allocationsIn([&] { taken = wbc.setSettings(next); }), 0);
  EXPECT_TRUE(taken);
  EXPECT_EQ(wbc.settings().variant, WbcVariant::kWeighted);
  EXPECT_DOUBLE_EQ(wbc.torqueLimit()[3], 50.0);
  WbcReference ref = wbc.makeReference();
  WbcOutput out = wbc.makeOutput();
  const WbcState state = wbc.makeState();
  wbc.update(state, ref, out);
  EXPECT_EQ(allocationsIn([&] { wbc.update(state, ref, out); }), 0);
  EXPECT_EQ(allocationsIn([&] { taken = wbc.setSettings(first); }), 0);
  EXPECT_TRUE(taken);
  WbcSettings moved = first;
  moved.contactFrames[0] = "left_heel";
  moved.contactFrames[1] = "left_toe";
  EXPECT_FALSE(wbc.setSettings(moved));  // contact frames are the controller's for good
}

}  // namespace
}  // namespace ballast::test
