// The standing controller's parts against independent references: the posture solver against
// forward kinematics of the full robot, the gravity feed-forward against the principle of
// virtual work, leg odometry against a known base motion.
#include <gtest/gtest.h>

#include <Eigen/LU>

#include "control/stand_controller.hpp"
#include "control/stand_posture.hpp"
#include "model/algorithms.hpp"
#include "profile/settings.hpp"
#include "test/unit/test_support.hpp"

namespace ballast::control {
namespace {

using namespace model;

ControlSettings simFlat() {
  const profile::Profile p =
      profile::Profile::load(std::string(BALLAST_SOURCE_DIR) + "/profiles/sim-flat.yaml");
  return profile::buildSettings(p, test::humanoid());
}

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
  const ControlSettings s = simFlat();
  StandPosture posture(m, s);
  Data<double> d(m);
  const double h0 = posture.nominalHeight();
  EXPECT_NEAR(h0, 0.890, 0.001);  // 0.19 m of fixed offsets + 2 x 0.38 m x cos(0.4)
  const char* feet[] = {"left_toe", "left_heel", "right_toe", "right_heel"};
  std::vector<SE3<double>> stance;
  for (const char* f : feet) stance.push_back(frameAt(m, d, f, h0, 0, 0, 0, s.nominal_q.data()));
  for (const SE3<double>& f : stance) EXPECT_NEAR(f.p.z(), 0.0, 1e-12);  // soles on the ground

  const double poses[][4] = {{0.80, 0, 0, 0}, {0.85, 0.1, -0.05, 0.2}, {0.88, -0.08, 0.1, -0.3}};
  double qj[kMaxJoints];
  for (const auto& p : poses) {
    const double err = posture.solve(p[0], p[1], p[2], p[3], 30, qj);
    EXPECT_LT(err, 1e-9);
    for (int k = 0; k < 4; ++k) {
      const SE3<double> f = frameAt(m, d, feet[k], p[0], p[1], p[2], p[3], qj);
      EXPECT_LT((f.p - stance[k].p).norm(), 1e-8) << feet[k];
      EXPECT_LT((f.R - stance[k].R).norm(), 1e-8) << feet[k];
    }
    for (int j = 0; j < m.nj(); ++j) {
      EXPECT_GE(qj[j], m.lowerPositionLimit[j]);
      EXPECT_LE(qj[j], m.upperPositionLimit[j]);
    }
    // Arms keep the nominal posture.
    EXPECT_DOUBLE_EQ(qj[m.jointId("left_elbow")], s.nominal_q[m.jointId("left_elbow")]);
  }
}

TEST(GravityFeedForward, DoesNoWorkAlongMotionsThatKeepTheFeetDown) {
  // Virtual work: with contact forces f, n(q) = Jcᵀ f + [0; τ]. For any velocity v that keeps
  // the contact points still (Jc v = 0) this gives vᵀ n = v_jᵀ τ, whatever f is.
  const Model& m = test::humanoid();
  const ControlSettings s = simFlat();
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
