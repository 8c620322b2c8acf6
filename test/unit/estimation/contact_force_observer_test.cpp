// The contact force observer against the dynamics it inverts: joint torques made by inverse
// dynamics (RNEA) with known contact forces, τ = (M v̇ + n − Jᵀ F) on the joint rows.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "estimation/contact_force_observer.hpp"
#include "test/unit/test_support.hpp"

namespace ballast::test {
namespace {

using estimation::ContactForceObserver;
using estimation::kContactPoints;
using Eigen::Vector3d;
using Eigen::VectorXd;

std::array<int, kContactPoints> contactFrames(const model::Model& m) {
  return {m.frameId("left_toe"), m.frameId("left_heel"), m.frameId("right_toe"),
          m.frameId("right_heel")};
}

/// Joint torques that produce the contact forces F at (q, v, a): τ = rnea(q, v, a) − Jᵀ F.
VectorXd torques(const model::Model& m, const VectorXd& q, const VectorXd& v, const VectorXd& a,
                 const std::array<Vector3d, kContactPoints>& F) {
  model::Data<double> d(m);
  VectorXd tau = model::rnea(m, d, q, v, a);
  Eigen::Matrix<double, 3, Eigen::Dynamic> J(3, m.nv);
  for (int c = 0; c < kContactPoints; ++c) {
    model::frameJacobian(m, d, contactFrames(m)[c], J);
    tau -= J.transpose() * F[c];
  }
  return tau.tail(m.nj());
}

void prepare(const model::Model& m, model::Data<double>& d, const VectorXd& q, const VectorXd& v) {
  model::crba(m, d, q);
  model::nonLinearEffects(m, d, q, v);
}

TEST(ContactForceObserver, StaticForcesRecovered) {
  const model::Model& m = humanoid();
  const VectorXd v = VectorXd::Zero(m.nv), a = VectorXd::Zero(m.nv);
  const std::array<Vector3d, kContactPoints> F{Vector3d(10, 5, 200), Vector3d(-4, 3, 120),
                                               Vector3d(0, -8, 90), Vector3d(6, 0, 210)};
  const char* toe[] = {"left_toe", "right_toe"};
  const char* heel[] = {"left_heel", "right_heel"};
  for (const Vector3d& zyx : {Vector3d(0.4, 0.0, 0.0), Vector3d(0.4, 0.05, -0.03)}) {
    VectorXd q = standingConfiguration(m);
    q.segment<4>(3) = model::quaternionXyzwFromZyx(zyx);  // yawed; then also tilted
    const VectorXd tau = torques(m, q, v, a, F);
    model::Data<double> d(m);
    prepare(m, d, q, v);
    ContactForceObserver obs(m, contactFrames(m));
    obs.update(d, v, q.tail(m.nj()), tau, 0.001, 50.0);
    for (int foot = 0; foot < 2; ++foot) {
      // Per foot, the total force is observable, and the error on each point lies along the
      // toe–heel line (equal and opposite: the internal force the joints cannot feel).
      const int t = 2 * foot, h = 2 * foot + 1;
      EXPECT_LT((obs.force(t) + obs.force(h) - F[t] - F[h]).norm(), 0.05) << "foot " << foot;
      EXPECT_LT((obs.footForce(t) - F[t] - F[h]).norm(), 0.05) << "foot " << foot;
      EXPECT_EQ(obs.footForce(t), obs.footForce(h));
      const Vector3d line = (model::framePlacement(m, d, m.frameId(toe[foot])).p -
                             model::framePlacement(m, d, m.frameId(heel[foot])).p).normalized();
      const Vector3d e = obs.force(t) - F[t];
      EXPECT_LT((e - e.dot(line) * line).norm(), 0.05) << "foot " << foot;
      // With the foot flat the line is horizontal and the normal forces come out exactly.
      if (zyx.tail<2>().isZero()) {
        EXPECT_NEAR(obs.force(t).z(), F[t].z(), 0.05);
        EXPECT_NEAR(obs.force(h).z(), F[h].z(), 0.05);
      }
    }
  }
}

TEST(ContactForceObserver, SwingLegInertiaIsNotAContactForce) {
  // The right foot stands (300 N on each point); the left leg swings fast (hip and knee ±0.5 rad
  // at 2 Hz: foot accelerations around 40 m/s²) with no contact force. The observer must see
  // ~0 on the left foot; the static estimate J_cᵀF = n − τ, without M v̇, sees a large force.
  // Sensor noise: 0.02 rad/s on joint velocities, 0.5 N·m on torques.
  const model::Model& m = humanoid();
  const VectorXd q0 = standingConfiguration(m);
  const int hip = model::Model::vIndexOfJoint(m.jointId("left_hip_pitch"));
  const int knee = model::Model::vIndexOfJoint(m.jointId("left_knee"));
  const std::array<Vector3d, kContactPoints> F{Vector3d::Zero(), Vector3d::Zero(),
                                               Vector3d(0, 0, 300), Vector3d(0, 0, 300)};
  const double dt = 0.001, w = 2 * M_PI * 2.0, A = 0.5;
  model::Data<double> d(m);
  ContactForceObserver obs(m, contactFrames(m));
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 1.0);
  double worstLeft = 0, worstRight = 0, worstStatic = 0, sumLeft2 = 0;
  int samples = 0;
  for (int k = 0; k <= 2000; ++k) {
    const double t = k * dt;
    VectorXd q = q0, v = VectorXd::Zero(m.nv), a = VectorXd::Zero(m.nv);
    for (auto [i, sign] : {std::pair{hip, -1.0}, std::pair{knee, 1.0}}) {
      q[i + 1] += sign * A * std::sin(w * t);
      v[i] = sign * A * w * std::cos(w * t);
      a[i] = -sign * A * w * w * std::sin(w * t);
    }
    VectorXd tau = torques(m, q, v, a, F);
    VectorXd vMeasured = v;
    for (int j = 0; j < m.nj(); ++j) {
      vMeasured[6 + j] += 0.02 * noise(rng);
      tau[j] += 0.5 * noise(rng);
    }
    prepare(m, d, q, vMeasured);
    obs.update(d, vMeasured, q.tail(m.nj()), tau, dt, 50.0);
    if (t < 0.5) continue;  // 25 observer time constants
    worstLeft = std::max(worstLeft, std::max(obs.force(0).norm(), obs.force(1).norm()));
    sumLeft2 += (obs.force(0) + obs.force(1)).squaredNorm();
    ++samples;
    worstRight = std::max({worstRight, std::abs(obs.force(2).z() - 300), std::abs(obs.force(3).z() - 300)});
    // The static estimate at this instant, from a fresh observer (r = n − τ).
    ContactForceObserver fresh(m, contactFrames(m));
    fresh.update(d, vMeasured, q.tail(m.nj()), tau, dt, 50.0);
    worstStatic = std::max(worstStatic, std::max(fresh.force(0).norm(), fresh.force(1).norm()));
  }
  std::printf("swing foot: observer RMS %.1f N, max %.1f N, static estimate max %.1f N; stance "
              "foot normal force error max %.1f N\n",
              std::sqrt(sumLeft2 / samples), worstLeft, worstStatic, worstRight);
  // Noise-free, the observer's error is 1 N (the Δv/dt discretisation); the rest is sensor noise
  // through K·M·Δv. The stance threshold (30 N by default) must stay above it.
  EXPECT_GT(worstStatic, 100.0);  // the case really needs the inertia term
  EXPECT_LT(std::sqrt(sumLeft2 / samples), 8.0);
  EXPECT_LT(worstLeft, 25.0);
  EXPECT_LT(worstRight, 25.0);
}

TEST(ContactForceObserver, ATurningStanceLegDoesNotTiltItsForce) {
  // Both feet carry 300 N straight up on each point; the left leg turns steadily about the hip
  // (hip pitch at -1 rad/s, the ankle at +1 rad/s keeping the sole flat), as a stance leg turns
  // under a walking base. The forces are constant in world axes, so their estimate must stay
  // vertical. Low-passed in joint space and solved through the current Jacobian, the estimate is
  // the force of 1/K ago's leg pose read through this pose's: the weight turned by ω/K, 600 N ·
  // 1/50 = 12 N horizontal on the left foot (walking at 1.5 m/s, the stance leg turns at about
  // v/L = 1.8 rad/s: 23-25 N, read by the external force observer as a push against the walk).
  const model::Model& m = humanoid();
  const VectorXd q0 = standingConfiguration(m);
  const int hip = model::Model::vIndexOfJoint(m.jointId("left_hip_pitch"));
  const int ankle = model::Model::vIndexOfJoint(m.jointId("left_ankle_pitch"));
  const std::array<Vector3d, kContactPoints> F{Vector3d(0, 0, 300), Vector3d(0, 0, 300),
                                               Vector3d(0, 0, 300), Vector3d(0, 0, 300)};
  const double dt = 0.001, omega = 1.0;
  model::Data<double> d(m);
  ContactForceObserver obs(m, contactFrames(m));
  double worstHorizontal = 0, worstVertical = 0;
  for (int k = 0; k <= 300; ++k) {
    const double t = k * dt;
    VectorXd q = q0, v = VectorXd::Zero(m.nv), a = VectorXd::Zero(m.nv);
    for (auto [i, sign] : {std::pair{hip, -1.0}, std::pair{ankle, 1.0}}) {
      q[i + 1] += sign * omega * t;
      v[i] = sign * omega;
    }
    const VectorXd tau = torques(m, q, v, a, F);
    prepare(m, d, q, v);
    obs.update(d, v, q.tail(m.nj()), tau, dt, 50.0);
    if (t < 0.1) continue;  // 5 observer time constants
    const Vector3d left = obs.footForce(0);
    worstHorizontal = std::max(worstHorizontal, left.head<2>().norm());
    worstVertical = std::max(worstVertical, std::abs(left.z() - 600));
  }
  std::printf("turning stance leg: horizontal force read %.2f N, vertical error %.2f N\n",
              worstHorizontal, worstVertical);
  EXPECT_LT(worstHorizontal, 1.0);
  EXPECT_LT(worstVertical, 1.0);
}

TEST(ContactForceObserver, AJointOnItsStopIsNotAContactForce) {
  // The right foot stands (300 N on each point); the left foot swings free with its ankle pitch
  // 0.1 rad past its lower limit, where the stop holds it with 100 N·m that the motor's torque
  // does not include. The swing foot must read ~0, not the stop's torque over the ankle's lever;
  // the stance foot, whose joints are within their limits, its 600 N. With the ankle back inside
  // its limit the same torque error is read as a force again (the row is only left out on the
  // stop).
  const model::Model& m = humanoid();
  const int ankle = m.jointId("left_ankle_pitch");
  const int j = model::Model::vIndexOfJoint(ankle) - 6;
  const std::array<Vector3d, kContactPoints> F{Vector3d::Zero(), Vector3d::Zero(),
                                               Vector3d(0, 0, 300), Vector3d(0, 0, 300)};
  const VectorXd v = VectorXd::Zero(m.nv), a = VectorXd::Zero(m.nv);
  auto leftFootForce = [&](double ankleAngle, Vector3d& right) {
    VectorXd q = standingConfiguration(m);
    q[7 + j] = ankleAngle;
    VectorXd tau = torques(m, q, v, a, F);
    tau[j] -= 100.0;  // the stop's 100 N·m pushes the ankle back up; the motor supplies the rest
    model::Data<double> d(m);
    prepare(m, d, q, v);
    ContactForceObserver obs(m, contactFrames(m));
    obs.update(d, v, q.tail(m.nj()), tau, 0.001, 50.0);
    right = obs.footForce(2);
    return obs.footForce(0).norm();
  };
  Vector3d right;
  const double onStop = leftFootForce(m.lowerPositionLimit[j] - 0.1, right);
  std::printf("swing foot with its ankle on the stop: %.2f N\n", onStop);
  EXPECT_LT(onStop, 1.0);
  EXPECT_LT((right - Vector3d(0, 0, 600)).norm(), 0.05);
  EXPECT_GT(leftFootForce(m.lowerPositionLimit[j] + 0.1, right), 100.0);
}

}  // namespace
}  // namespace ballast::test
