// The contact force observer against the dynamics it inverts: joint torques made by inverse
// dynamics (RNEA) with known contact forces, τ = (M v̇ + n − Jᵀ F) on the joint rows.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <utility>

#include <Eigen/Eigenvalues>

#include "estimation/contact_force_observer.hpp"
#include "test/unit/settings_support.hpp"
#include "test/unit/test_support.hpp"

namespace ballast::test {
namespace {

using estimation::ContactForceObserver;
using estimation::kContactPoints;
using Eigen::Vector3d;
using Eigen::VectorXd;

/// A λ small enough that a bent leg's forces come out exact (the profile's default is larger:
/// WhatAStretchedLegCannotSenseIsMeasured).
constexpr double kExact = 1e-6;

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
    obs.update(d, v, q.tail(m.nj()), tau, 0.001, 50.0, kExact);
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
    obs.update(d, vMeasured, q.tail(m.nj()), tau, dt, 50.0, kExact);
    if (t < 0.5) continue;  // 25 observer time constants
    worstLeft = std::max(worstLeft, std::max(obs.force(0).norm(), obs.force(1).norm()));
    sumLeft2 += (obs.force(0) + obs.force(1)).squaredNorm();
    ++samples;
    worstRight = std::max({worstRight, std::abs(obs.force(2).z() - 300), std::abs(obs.force(3).z() - 300)});
    // The static estimate at this instant, from a fresh observer (r = n − τ).
    ContactForceObserver fresh(m, contactFrames(m));
    fresh.update(d, vMeasured, q.tail(m.nj()), tau, dt, 50.0, kExact);
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
    obs.update(d, v, q.tail(m.nj()), tau, dt, 50.0, kExact);
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
    obs.update(d, v, q.tail(m.nj()), tau, 0.001, 50.0, kExact);
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

TEST(ContactForceObserver, WhatAStretchedLegCannotSenseIsMeasured) {
  // The right foot carries 600 N along its leg (split evenly between toe and heel), the left
  // foot nothing. Whatever the posture, the least squares keeps exactly (I − W)·F of an evenly
  // split foot force F (W: unsensedLoad). With the knee bent W is small; with the knee on its
  // stop (its row left out) the force along the line from hip to ankle reaches no joint, and W
  // says so: a large eigenvalue along that line.
  const model::Model& m = humanoid();
  const int knee = m.jointId("right_knee");
  const int j = model::Model::vIndexOfJoint(knee) - 6;
  const VectorXd v = VectorXd::Zero(m.nv), a = VectorXd::Zero(m.nv);
  const double lambda = estimatorSettings().contactForceRegularization;  // the profile's
  auto check = [&](double kneeAngle, double stopTorque) {
    VectorXd q = standingConfiguration(m);
    q[7 + j] = kneeAngle;
    model::Data<double> d(m);
    prepare(m, d, q, v);
    const Vector3d hip = d.oMi[m.jointId("right_hip_pitch")].p;
    const Vector3d ankle = d.oMi[m.jointId("right_ankle_pitch")].p;
    const Vector3d leg = (hip - ankle).normalized();
    const Vector3d load = 600.0 * leg;
    const std::array<Vector3d, kContactPoints> F{Vector3d::Zero(), Vector3d::Zero(), 0.5 * load,
                                                 0.5 * load};
    VectorXd tau = torques(m, q, v, a, F);
    tau[j] -= stopTorque;
    ContactForceObserver obs(m, contactFrames(m));
    obs.update(d, v, q.tail(m.nj()), tau, 0.001, 50.0, lambda);
    const Eigen::Matrix3d& W = obs.unsensedLoad(2);
    EXPECT_LT((obs.footForce(2) - (Eigen::Matrix3d::Identity() - W) * load).norm(), 1e-6 * 600.0);
    EXPECT_EQ(W, obs.unsensedLoad(3));
    // The stance feet's sum counts each foot once.
    EXPECT_EQ(obs.unsensedLoad(std::array<bool, kContactPoints>{false, false, true, true}), W);
    EXPECT_EQ(obs.unsensedLoad(std::array<bool, kContactPoints>{false, false, false, true}), W);
    EXPECT_EQ(obs.unsensedLoad(std::array<bool, kContactPoints>{true, true, true, false}),
              obs.unsensedLoad(0) + W);
    EXPECT_EQ(obs.unsensedLoad(std::array<bool, kContactPoints>{}), Eigen::Matrix3d::Zero());
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(W);
    std::printf("knee %.2f rad: W's eigenvalues %.4f %.4f %.4f, |cos| to the leg %.4f\n",
                kneeAngle, eig.eigenvalues()[0], eig.eigenvalues()[1], eig.eigenvalues()[2],
                std::abs(eig.eigenvectors().col(2).dot(leg)));
    return std::make_pair(eig.eigenvalues()[2], std::abs(eig.eigenvectors().col(2).dot(leg)));
  };
  const auto bent = check(0.8, 0.0);
  EXPECT_LT(bent.first, 0.1);
  // Not 1: the unsensed force runs through the ankle, and an even split between toe and heel
  // also has a moment about it, which the ankle senses.
  const auto onStop = check(m.lowerPositionLimit[j] - 0.05, 200.0);
  EXPECT_GT(onStop.first, 0.7);
  EXPECT_GT(onStop.second, 0.99);
}

}  // namespace
}  // namespace ballast::test
