// The standing controller's parts against independent references: the posture solver against
// forward kinematics of the full robot, the gravity feed-forward against the principle of
// virtual work, leg odometry against a known base motion.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <memory>

#include "control/stand_controller.hpp"
#include "control/stand_posture.hpp"
#include "model/algorithms.hpp"
#include "profile/settings.hpp"
#include "test/unit/settings_support.hpp"
#include "test/unit/test_support.hpp"

namespace ballast::control {
namespace {

using namespace model;

/// The contact points, in the profile's order.
const char* const kContactFrames[] = {"left_toe", "left_heel", "right_toe", "right_heel"};

/// World placement of a frame for the base at (height, roll, pitch, yaw) and joints qj.
SE3<double> frameAt(const Model& m, Data<double>& d, const std::string& frame, double h,
                    double roll, double pitch, double yaw, const double* qj) {
  VecX<double> q(m.nq);
  q.head<3>() << 0, 0, h;
  q.segment<4>(3) = quaternionXyzwFromZyx(Vec3<double>(yaw, pitch, roll));
  for (int j = 0; j < m.nj(); ++j) q[7 + j] = qj[j];
  forwardKinematics(m, d, q);
  return framePlacement(m, d, m.frameId(frame));
}

TEST(StandPosture, FeetStayWhereTheNominalStancePutsThem) {
  const Model& m = test::humanoid();
  const ControlSettings s = test::simFlat().control;
  StandPosture posture(m, s);
  Data<double> d(m);
  const double h0 = posture.nominalHeight();
  EXPECT_NEAR(h0, 0.890, 0.001);  // 0.19 m of fixed offsets + 2 x 0.38 m x cos(0.4)
  std::vector<SE3<double>> stance;
  for (const char* f : kContactFrames)
    stance.push_back(frameAt(m, d, f, h0, 0, 0, 0, s.nominal_q.data()));
  for (const SE3<double>& f : stance) EXPECT_NEAR(f.p.z(), 0.0, 1e-12);  // soles on the ground

  const double poses[][4] = {{0.80, 0, 0, 0}, {0.85, 0.1, -0.05, 0.2}, {0.88, -0.08, 0.1, -0.3}};
  double qj[kMaxJoints];
  for (const auto& p : poses) {
    const double err = posture.solve(p[0], p[1], p[2], p[3], 30, qj);
    EXPECT_LT(err, 1e-9);
    for (int k = 0; k < 4; ++k) {
      const SE3<double> f = frameAt(m, d, kContactFrames[k], p[0], p[1], p[2], p[3], qj);
      EXPECT_LT((f.p - stance[k].p).norm(), 1e-8) << kContactFrames[k];
      EXPECT_LT((f.R - stance[k].R).norm(), 1e-8) << kContactFrames[k];
    }
    for (int j = 0; j < m.nj(); ++j) {
      EXPECT_GE(qj[j], m.lowerPositionLimit[j]);
      EXPECT_LE(qj[j], m.upperPositionLimit[j]);
    }
    // Arms keep the nominal posture.
    EXPECT_DOUBLE_EQ(qj[m.jointId("left_elbow")], s.nominal_q[m.jointId("left_elbow")]);
  }
}

/// Feet on uneven ground: the nominal legs bent unevenly under a base rolled, pitched and turned
/// (soles tilted about 0.1 rad, 3-5 cm apart in height), as a robot dropped onto rough ground
/// lands. Joints in `qj`, the base's orientation returned.
Mat3<double> unevenFeet(const Model& m, const ControlSettings& s, double* qj) {
  for (int j = 0; j < m.nj(); ++j) qj[j] = s.nominal_q[j];
  qj[m.jointId("left_hip_pitch")] -= 0.12;
  qj[m.jointId("left_knee")] += 0.2;
  qj[m.jointId("left_hip_roll")] += 0.04;
  qj[m.jointId("right_ankle_pitch")] += 0.1;
  qj[m.jointId("right_ankle_roll")] -= 0.07;
  return rotationFromZyx(Vec3<double>(0.3, -0.05, 0.06));
}

/// Whether, with the base level at the feet's mean heading, joints qj put the four contact
/// frames where `feet` has them (one translation for all: the base's place is free), and the
/// base at `height` above the two soles' mean, horizontally where the nominal stance has it.
void expectLevelBaseOnTheFeet(const Model& m, const ControlSettings& s, double height,
                              const std::vector<SE3<double>>& feet, const double* qj) {
  Data<double> d(m);
  const double yaw = std::atan2(std::sin(std::atan2(feet[0].R(1, 0), feet[0].R(0, 0))) +
                                    std::sin(std::atan2(feet[2].R(1, 0), feet[2].R(0, 0))),
                                std::cos(std::atan2(feet[0].R(1, 0), feet[0].R(0, 0))) +
                                    std::cos(std::atan2(feet[2].R(1, 0), feet[2].R(0, 0))));
  std::vector<SE3<double>> level;  // base at the origin, level, at the feet's heading
  Vec3<double> shift = Vec3<double>::Zero();
  for (int k = 0; k < 4; ++k) {
    level.push_back(frameAt(m, d, kContactFrames[k], 0.0, 0.0, 0.0, yaw, qj));
    shift += 0.25 * (feet[k].p - level[k].p);
  }
  for (int k = 0; k < 4; ++k) {
    EXPECT_LT((level[k].p + shift - feet[k].p).norm(), 1e-6) << kContactFrames[k];
    EXPECT_LT((level[k].R - feet[k].R).norm(), 1e-6) << kContactFrames[k];
  }
  // `shift` is the base's place under the feet: height above the soles' mean (the first frame
  // of each foot), and the nominal stance's horizontal offset from the feet, turned by yaw.
  const Vec3<double> soles = 0.5 * (feet[0].p + feet[2].p);
  EXPECT_NEAR(shift.z() - soles.z(), height, 1e-6);
  const SE3<double> l0 = frameAt(m, d, "left_toe", 0, 0, 0, 0, s.nominal_q.data());
  const SE3<double> r0 = frameAt(m, d, "right_toe", 0, 0, 0, 0, s.nominal_q.data());
  const Vec3<double> offset = rotationFromZyx(Vec3<double>(yaw, 0, 0)) * (0.5 * (l0.p + r0.p));
  EXPECT_NEAR(soles.x() - shift.x(), offset.x(), 1e-6);
  EXPECT_NEAR(soles.y() - shift.y(), offset.y(), 1e-6);
}

TEST(StandPosture, AnchoredALevelBaseStandsOnTheFeetWhereTheyAre) {
  const Model& m = test::humanoid();
  const ControlSettings s = test::simFlat().control;
  StandPosture posture(m, s);
  Data<double> d(m);
  double q0[kMaxJoints];
  const Mat3<double> R0 = unevenFeet(m, s, q0);
  const Vec3<double> zyx0 = zyxFromRotation(R0);
  std::vector<SE3<double>> feet;
  for (const char* f : kContactFrames)
    feet.push_back(frameAt(m, d, f, 1.0, zyx0[2], zyx0[1], zyx0[0], q0));
  // The feet are uneven: tilted soles at different heights.
  ASSERT_GT(std::abs(feet[0].p.z() - feet[2].p.z()), 0.02);
  ASSERT_GT(std::acos(std::clamp(feet[0].R(2, 2), -1.0, 1.0)), 0.08);

  posture.anchor(R0, q0);
  EXPECT_TRUE(posture.anchored());
  double qj[kMaxJoints];
  EXPECT_LT(posture.solve(posture.nominalHeight(), 0, 0, 0, 50, qj), 1e-9);
  expectLevelBaseOnTheFeet(m, s, posture.nominalHeight(), feet, qj);

  // On a flat floor with the feet where the nominal stance has them (here turned by 0.4 rad),
  // the anchored stance is the nominal one: the same postures for every pose.
  StandPosture nominal(m, s);
  posture.anchor(rotationFromZyx(Vec3<double>(0.4, 0, 0)), s.nominal_q.data());
  const double poses[][4] = {{0.80, 0, 0, 0}, {0.85, 0.1, -0.05, 0.2}};
  for (const auto& p : poses) {
    double qa[kMaxJoints], qn[kMaxJoints];
    posture.solve(p[0], p[1], p[2], p[3], 30, qa);
    nominal.solve(p[0], p[1], p[2], p[3], 30, qn);
    for (int j = 0; j < m.nj(); ++j) EXPECT_NEAR(qa[j], qn[j], 1e-9) << "joint " << j;
  }
  posture.unanchor();
  EXPECT_FALSE(posture.anchored());
}

TEST(StandController, StandsUpToALevelBaseOverUnevenFeet) {
  const Model& m = test::humanoid();
  const ControlSettings s = test::simFlat().control;
  StandController controller(m, s);
  Data<double> d(m);
  ControllerInput in;
  in.mode = Mode::kStandUp;
  in.state.num_joints = m.nj();
  const Mat3<double> R0 = unevenFeet(m, s, in.state.q);
  const Eigen::Vector4d quat = quaternionXyzwFromRotation(R0);
  for (int i = 0; i < 4; ++i) in.state.base.orientation[i] = quat[i];
  for (bool& c : in.state.contact) c = true;
  const Vec3<double> zyx0 = zyxFromRotation(R0);
  std::vector<SE3<double>> feet;
  for (const char* f : kContactFrames)
    feet.push_back(frameAt(m, d, f, 1.0, zyx0[2], zyx0[1], zyx0[0], in.state.q));
  in.command.height = controller.nominalHeight();

  std::vector<double> kp(m.nj(), 300.0), kd(m.nj(), 8.0);
  auto out = std::make_unique<ControllerOutput>();
  controller.beginStandUp(in.state);
  const int ticks = 1000;  // stand-up over 1 s at 1 kHz
  for (int i = 1; i <= ticks; ++i) {
    in.stand_up_progress = double(i) / ticks;
    controller.compute(in, kp.data(), kd.data(), 1e-3, *out);
  }
  expectLevelBaseOnTheFeet(m, s, controller.nominalHeight(), feet, out->q_ref);

  // With a foot off the ground the stance is the nominal one: the soles level.
  StandController lifted(m, s);
  in.state.contact[2] = in.state.contact[3] = false;  // the right foot's points
  lifted.beginStandUp(in.state);
  for (int i = 1; i <= ticks; ++i) {
    in.stand_up_progress = double(i) / ticks;
    lifted.compute(in, kp.data(), kd.data(), 1e-3, *out);
  }
  for (const char* f : kContactFrames) {
    const SE3<double> p = frameAt(m, d, f, 1.0, 0, 0, 0, out->q_ref);
    EXPECT_NEAR(p.R(2, 2), 1.0, 1e-9) << f;
  }
}

TEST(GravityFeedForward, DoesNoWorkAlongMotionsThatKeepTheFeetDown) {
  // Virtual work: with contact forces f, n(q) = Jcᵀ f + [0; τ]. For any velocity v that keeps
  // the contact points still (Jc v = 0) this gives vᵀ n = v_jᵀ τ, whatever f is.
  const Model& m = test::humanoid();
  const ControlSettings s = test::simFlat().control;
  StandController controller(m, s);
  StandPosture posture(m, s);
  EstimatedState state;
  state.num_joints = m.nj();
  posture.solve(0.84, 0.05, -0.08, 0.1, 30, state.q);
  for (bool& c : state.contact) c = true;
  const Vec3<double> zyx(0.0, -0.08, 0.05);  // the base orientation of that pose (yaw 0)
  const Eigen::Vector4d quat = quaternionXyzwFromZyx(zyx);
  for (int i = 0; i < 4; ++i) state.base.orientation[i] = quat[i];
  state.base.position[2] = 0.84;
  double tau[kMaxJoints];
  controller.gravityFeedForward(state, tau);

  Data<double> d(m);
  VecX<double> q(m.nq);
  q << 0, 0, 0.84, quat, Eigen::Map<const VecX<double>>(state.q, m.nj());
  const VecX<double> n = nonLinearEffects(m, d, q, VecX<double>::Zero(m.nv));
  MatX<double> Jc(12, m.nv);
  forwardKinematics(m, d, q);
  int row = 0;
  for (const std::string& f : s.contact_frames) {
    Mat3X<double> J(3, m.nv);
    frameJacobian(m, d, m.frameId(f), J);
    Jc.middleRows<3>(row) = J;
    row += 3;
  }
  const MatX<double> N = Eigen::FullPivLU<MatX<double>>(Jc).kernel();
  ASSERT_GE(N.cols(), 12);  // the two arms, free of the contacts
  for (int k = 0; k < N.cols(); ++k) {
    const VecX<double> v = N.col(k);
    const double work = n.dot(v) - Eigen::Map<const VecX<double>>(tau, m.nj()).dot(v.tail(m.nj()));
    EXPECT_NEAR(work, 0.0, 1e-8 * (1.0 + n.norm())) << "null-space direction " << k;
  }
  // The arms touch nothing: their feed-forward is their gravity torque.
  const int elbow = m.jointId("left_elbow");
  EXPECT_NEAR(tau[elbow], n[6 + elbow], 1e-9);
  // And the legs carry the robot: the knees hold a substantial torque.
  EXPECT_GT(std::abs(tau[m.jointId("left_knee")]), 10.0);
}

}  // namespace
}  // namespace ballast::control
