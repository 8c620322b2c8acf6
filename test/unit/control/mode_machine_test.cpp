// The mode machine: every transition of DESIGN.md's mode diagram, the refusals and what they
// tell the operator, TTL expiry in controller time.
#include <gtest/gtest.h>

#include <cmath>

#include "control/mode_machine.hpp"
#include "test/unit/settings_support.hpp"

namespace ballast::control {
namespace {

class Modes : public ::testing::Test {
 protected:
  void SetUp() override {
    settings_.stand_up_duration = 2.0;
    settings_.command_ttl = 3.0;
    settings_.max_command_ttl = 10.0;
    m_.configure(settings_, 0.89);
    m_.start(Mode::kPassive, 0.0);
  }
  Refusal send(CommandKind kind, double t, OperatorCommand c = {}) {
    c.kind = kind;
    return m_.handle(c, t, situation_, message_);
  }
  ControlSettings settings_ = test::controlDefaults();
  ModeMachine m_;
  Situation situation_;
  char message_[kMessageLength];
};

TEST_F(Modes, PassiveStandUpStand) {
  EXPECT_EQ(send(CommandKind::kStand, 1.0), Refusal::kNone);
  EXPECT_EQ(m_.mode(), Mode::kStandUp);
  m_.update(2.0);
  EXPECT_EQ(m_.mode(), Mode::kStandUp);
  EXPECT_DOUBLE_EQ(m_.standUpProgress(2.0), 0.5);
  m_.update(3.0);
  EXPECT_EQ(m_.mode(), Mode::kStand);
  EXPECT_DOUBLE_EQ(m_.standUpProgress(3.0), 1.0);
}

TEST_F(Modes, WalkNeedsThePlanner) {
  send(CommandKind::kStand, 0.0);
  m_.update(5.0);
  OperatorCommand w;
  w.vx = 0.5;
  EXPECT_EQ(send(CommandKind::kWalk, 5.0, w), Refusal::kUnavailable);
  EXPECT_NE(std::string(message_).find("walking needs the planner and this ballastd runs without one"),
            std::string::npos);
  EXPECT_EQ(m_.mode(), Mode::kStand);
}

TEST_F(Modes, WalkExpiresToStandAfterItsTtl) {
  situation_.planner_available = true;
  send(CommandKind::kStand, 0.0);
  m_.update(5.0);
  OperatorCommand w;
  w.vx = 0.5;
  w.ttl = 1.5;
  ASSERT_EQ(send(CommandKind::kWalk, 5.0, w), Refusal::kNone);
  EXPECT_EQ(m_.mode(), Mode::kWalk);
  EXPECT_TRUE(m_.command().velocity_active);
  m_.update(6.49);
  EXPECT_EQ(m_.mode(), Mode::kWalk);
  m_.update(6.5);
  EXPECT_EQ(m_.mode(), Mode::kStand);
  EXPECT_FALSE(m_.command().velocity_active);
  EXPECT_EQ(m_.command().vx, 0.0);
  // Without a ttl: the profile's safety.command_ttl.
  w.ttl = 0.0;
  send(CommandKind::kWalk, 10.0, w);
  EXPECT_DOUBLE_EQ(m_.command().expires_at, 13.0);
  // Stop: zero velocity, standing.
  EXPECT_EQ(send(CommandKind::kStop, 11.0), Refusal::kNone);
  EXPECT_EQ(m_.mode(), Mode::kStand);
  // Limits from the profile.
  w.vx = 2.0;
  EXPECT_EQ(send(CommandKind::kWalk, 12.0, w), Refusal::kOutOfRange);
  EXPECT_NE(std::string(message_).find("safety.max_vx"), std::string::npos);
  w.vx = 0.1;
  w.ttl = 11.0;
  EXPECT_EQ(send(CommandKind::kWalk, 12.0, w), Refusal::kOutOfRange);
  EXPECT_NE(std::string(message_).find("safety.max_command_ttl"), std::string::npos);
  EXPECT_EQ(m_.mode(), Mode::kStand);
}

// A robot whose feet cannot yaw relative to its pelvis (profile::settingsFor says why) cannot
// turn: a walk or a pose with a yaw is refused with the reason, and the same without one goes.
TEST_F(Modes, ARobotThatCannotTurnRefusesAYawAndSaysWhy) {
  situation_.planner_available = true;
  settings_.feet_cannot_yaw = "no joint of either leg turns its foot about the vertical";
  send(CommandKind::kStand, 0.0);
  m_.update(5.0);
  ASSERT_EQ(m_.mode(), Mode::kStand);
  OperatorCommand w;
  w.vx = 0.4;
  w.yaw_rate = 0.2;
  EXPECT_EQ(send(CommandKind::kWalk, 5.0, w), Refusal::kOutOfRange);
  EXPECT_NE(std::string(message_).find("cannot turn: no joint of either leg"), std::string::npos)
      << message_;
  EXPECT_EQ(m_.mode(), Mode::kStand);
  w.yaw_rate = 0.0;
  EXPECT_EQ(send(CommandKind::kWalk, 5.1, w), Refusal::kNone);
  EXPECT_EQ(m_.mode(), Mode::kWalk);
  OperatorCommand p;
  p.height = std::nan("");
  p.yaw = 0.1;
  EXPECT_EQ(send(CommandKind::kPose, 5.2, p), Refusal::kOutOfRange);
  EXPECT_NE(std::string(message_).find("cannot turn its base over its feet"), std::string::npos)
      << message_;
  p.yaw = 0.0;
  p.pitch = 0.05;
  EXPECT_EQ(send(CommandKind::kPose, 5.3, p), Refusal::kNone);
}

TEST_F(Modes, RecoveryStepsLeaveStandAndComeBack) {
  situation_.planner_available = true;
  send(CommandKind::kStand, 0.0);
  m_.update(5.0);
  ASSERT_EQ(m_.mode(), Mode::kStand);
  // The planner steps after a push: recover, and stand again when it stops.
  m_.recovering(true, 5.1);
  EXPECT_EQ(m_.mode(), Mode::kRecover);
  EXPECT_STREQ(modeName(m_.mode()), "recover");
  m_.update(9.0);  // nothing in recover expires
  EXPECT_EQ(m_.mode(), Mode::kRecover);
  EXPECT_EQ(send(CommandKind::kStand, 9.0), Refusal::kNone);  // it stands by itself afterwards
  EXPECT_EQ(m_.mode(), Mode::kRecover);
  m_.recovering(false, 9.5);
  EXPECT_EQ(m_.mode(), Mode::kStand);
  // A walk takes over from the steps, and the planner's flag leaves walk alone.
  m_.recovering(true, 10.0);
  OperatorCommand w;
  w.vx = 0.3;
  EXPECT_EQ(send(CommandKind::kWalk, 10.1, w), Refusal::kNone);
  EXPECT_EQ(m_.mode(), Mode::kWalk);
  m_.recovering(false, 10.2);
  EXPECT_EQ(m_.mode(), Mode::kWalk);
  m_.recovering(true, 10.3);
  EXPECT_EQ(m_.mode(), Mode::kWalk);
}

TEST_F(Modes, OnlyAStandingRobotRecovers) {
  m_.recovering(true, 0.1);  // passive
  EXPECT_EQ(m_.mode(), Mode::kPassive);
  send(CommandKind::kStand, 0.2);
  m_.recovering(true, 0.3);  // standing up
  EXPECT_EQ(m_.mode(), Mode::kStandUp);
  m_.update(5.0);
  m_.recovering(true, 5.1);
  send(CommandKind::kEstop, 5.2);
  m_.recovering(false, 5.3);  // damped stays damped
  EXPECT_EQ(m_.mode(), Mode::kDamp);
}

TEST_F(Modes, WalkFromPassiveIsRefused) {
  situation_.planner_available = true;
  EXPECT_EQ(send(CommandKind::kWalk, 0.0), Refusal::kRefused);
  EXPECT_NE(std::string(message_).find("run `ballast stand` first"), std::string::npos);
}

TEST_F(Modes, EstopLatchesDampUntilReset) {
  send(CommandKind::kStand, 0.0);
  EXPECT_EQ(send(CommandKind::kEstop, 0.5), Refusal::kNone);
  EXPECT_EQ(m_.mode(), Mode::kDamp);
  EXPECT_TRUE(m_.estopLatched());
  for (CommandKind k : {CommandKind::kStand, CommandKind::kPassive, CommandKind::kPose}) {
    EXPECT_EQ(send(k, 1.0), Refusal::kRefused);
    EXPECT_NE(std::string(message_).find("estop is latched"), std::string::npos) << message_;
    EXPECT_EQ(m_.mode(), Mode::kDamp);
  }
  m_.update(100.0);
  EXPECT_EQ(m_.mode(), Mode::kDamp);
  EXPECT_EQ(send(CommandKind::kReset, 2.0), Refusal::kNone);
  EXPECT_EQ(m_.mode(), Mode::kPassive);
  EXPECT_FALSE(m_.estopLatched());
  EXPECT_EQ(m_.faults().size, 0);
}

TEST_F(Modes, FaultDampsAndIsCountedOnce) {
  send(CommandKind::kStand, 0.0);
  EXPECT_TRUE(m_.fault(FaultKind::kBackendStale, 0.2, "stale"));
  EXPECT_FALSE(m_.fault(FaultKind::kBackendStale, 0.3, "stale again"));
  EXPECT_EQ(m_.mode(), Mode::kDamp);
  ASSERT_EQ(m_.faults().size, 1);
  EXPECT_EQ(m_.faults().fault[0].count, 2u);
  EXPECT_DOUBLE_EQ(m_.faults().fault[0].t, 0.2);
  EXPECT_EQ(send(CommandKind::kStand, 1.0), Refusal::kRefused);
  EXPECT_NE(std::string(message_).find("damped after a fault"), std::string::npos);
  send(CommandKind::kReset, 1.0);
  EXPECT_EQ(send(CommandKind::kStand, 1.0), Refusal::kNone);
}

TEST_F(Modes, FallenRobotIsNotStoodUp) {
  situation_.fallen = true;
  EXPECT_EQ(send(CommandKind::kStand, 0.0), Refusal::kRefused);
  EXPECT_NE(std::string(message_).find("has fallen"), std::string::npos);
  EXPECT_EQ(m_.mode(), Mode::kPassive);
}

TEST_F(Modes, PoseWithinLimitsOnlyWhileStanding) {
  OperatorCommand p;
  p.height = 0.8;
  EXPECT_EQ(send(CommandKind::kPose, 0.0, p), Refusal::kRefused);
  send(CommandKind::kStand, 0.0);
  EXPECT_EQ(send(CommandKind::kPose, 0.1, p), Refusal::kNone);
  EXPECT_DOUBLE_EQ(m_.command().height, 0.8);
  p.height = 0.5;
  EXPECT_EQ(send(CommandKind::kPose, 0.1, p), Refusal::kOutOfRange);
  p.height = std::nan("");
  p.pitch = 1.0;
  EXPECT_EQ(send(CommandKind::kPose, 0.1, p), Refusal::kOutOfRange);
  EXPECT_NE(std::string(message_).find("safety.max_pose_tilt"), std::string::npos);
  p.pitch = 0.1;
  EXPECT_EQ(send(CommandKind::kPose, 0.1, p), Refusal::kNone);
  EXPECT_DOUBLE_EQ(m_.command().height, 0.89);  // unset height: nominal
  EXPECT_DOUBLE_EQ(m_.command().pitch, 0.1);
}

}  // namespace
}  // namespace ballast::control
