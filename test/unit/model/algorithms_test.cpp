// The algorithms against each other and against finite differences of kinematics, on random
// states of the humanoid. (Against Simbody: test/oracle.)
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include "test/unit/test_support.hpp"

namespace ballast::test {
namespace {

using namespace model;

constexpr int kStates = 50;

class Algorithms : public ::testing::Test {
 protected:
  const Model& m = humanoid();
  Data<double> data{m};
  std::mt19937 rng{3};

  VecX<double> stepped(const VecX<double>& q, const VecX<double>& v, double t) const {
    VecX<double> out(m.nq);
    integrate(m, q, v, t, out);
    return out;
  }
};

TEST_F(Algorithms, InverseDynamicsIsMassMatrixTimesAccelerationPlusBias) {
  for (int k = 0; k < kStates; ++k) {
    const RandomState s = randomState(m, rng);
    const MatX<double> M = crba(m, data, s.q);
    const VecX<double> n = nonLinearEffects(m, data, s.q, s.v);
    EXPECT_LT((rnea(m, data, s.q, s.v, s.a) - (M * s.a + n)).norm(), 1e-10);
    EXPECT_LT((M - M.transpose()).norm(), 1e-12);
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<MatX<double>>(M).eigenvalues().minCoeff(), 0.0);
  }
}

TEST_F(Algorithms, ArmatureAddsToTheJointDiagonalAndActsOnTheJointsAccelerationOnly) {
  Model withArmature = m;
  std::uniform_real_distribution<double> value(0.001, 0.05);
  for (int j = 0; j < m.nj(); ++j) withArmature.armature[j] = value(rng);
  Data<double> armed(withArmature);
  for (int k = 0; k < kStates; ++k) {
    const RandomState s = randomState(m, rng);
    const MatX<double> M = crba(m, data, s.q);
    const MatX<double> Ma = crba(withArmature, armed, s.q);
    MatX<double> expected = M;
    expected.diagonal().tail(m.nj()) += withArmature.armature;
    EXPECT_LT((Ma - expected).norm(), 1e-12);
    // Inverse dynamics stays M a + n with the armed M, and n does not change.
    const VecX<double> n = nonLinearEffects(m, data, s.q, s.v);
    EXPECT_LT((nonLinearEffects(withArmature, armed, s.q, s.v) - n).norm(), 1e-12);
    EXPECT_LT((rnea(withArmature, armed, s.q, s.v, s.a) - (Ma * s.a + n)).norm(), 1e-10);
  }
}

TEST_F(Algorithms, KineticEnergyFromMassMatrixEqualsSumOverBodies) {
  for (int k = 0; k < kStates; ++k) {
    const RandomState s = randomState(m, rng);
    const double fromM = 0.5 * s.v.dot(crba(m, data, s.q) * s.v);
    forwardKinematics(m, data, s.q, s.v);
    double sum = 0.0;
    for (int i = 0; i < m.nbodies(); ++i) sum += 0.5 * dot(data.v[i], m.inertia[i] * data.v[i]);
    EXPECT_NEAR(fromM, sum, 1e-10 * std::max(1.0, sum));
  }
}

TEST_F(Algorithms, GravityOnTheBaseIsTheWeight) {
  const RandomState s = randomState(m, rng);
  const VecX<double> n = nonLinearEffects(m, data, s.q, VecX<double>::Zero(m.nv));
  const Mat3<double> R = quaternionToRotation<double>(s.q.segment<4>(3));
  const Vec3<double> weightUp(0, 0, m.totalMass() * 9.81);
  EXPECT_LT((n.head<3>() - R.transpose() * weightUp).norm(), 1e-9);
}

TEST_F(Algorithms, FrameJacobianAndVelocityMatchFiniteDifferences) {
  for (int k = 0; k < kStates; ++k) {
    const RandomState s = randomState(m, rng);
    for (const char* name : {"left_toe", "right_heel", "left_hand", "pelvis"}) {
      const int f = m.frameId(name);
      forwardKinematics(m, data, s.q, s.v);
      Mat6X<double> J(6, m.nv);
      frameJacobian(m, data, f, J);
      const Motion<double> vel = frameVelocity(m, data, f);
      EXPECT_LT((J * s.v - vel.toVector()).norm(), 1e-10) << name;

      const Vec3<double> fd = centralDifference([&](double t) {
        forwardKinematics(m, data, stepped(s.q, s.v, t));
        return framePlacement(m, data, f).p;
      });
      EXPECT_LT((vel.linear - fd).norm(), 1e-6 * std::max(1.0, fd.norm())) << name;
    }
  }
}

TEST_F(Algorithms, BiasAccelerationIsTheDerivativeOfJacobianTimesVelocity) {
  for (int k = 0; k < kStates; ++k) {
    const RandomState s = randomState(m, rng);
    for (const char* name : {"left_toe", "right_heel", "right_hand"}) {
      const int f = m.frameId(name);
      forwardKinematicsBias(m, data, s.q, s.v);
      const Vec6<double> bias = frameClassicalAcceleration(m, data, f).toVector();
      const Vec6<double> fd = centralDifference([&](double t) {
        forwardKinematics(m, data, stepped(s.q, s.v, t));
        Mat6X<double> J(6, m.nv);
        frameJacobian(m, data, f, J);
        return Vec6<double>(J * s.v);
      });
      EXPECT_LT((bias - fd).norm(), 1e-5 * std::max(1.0, fd.norm())) << name;
    }
  }
}

TEST_F(Algorithms, CentroidalMomentumMatrixAndItsBias) {
  for (int k = 0; k < kStates; ++k) {
    const RandomState s = randomState(m, rng);
    ccrba(m, data, s.q, s.v);
    const Mat6X<double> A = data.Ag;
    const Vec6<double> h = data.hg;
    // Linear rows are m·J_com.
    const Vec3<double> comRate = centralDifference([&](double t) {
      return Vec3<double>(centerOfMass(m, data, stepped(s.q, s.v, t)));
    });
    EXPECT_LT((A.topRows<3>() * s.v / m.totalMass() - comRate).norm(), 1e-6);
    // Ȧ v = d/dt (A(q) v) at constant v.
    centroidalMomentumBias(m, data, s.q, s.v);
    EXPECT_LT((data.hg - h).norm(), 1e-10);
    const Vec6<double> fd = centralDifference([&](double t) {
      ccrba(m, data, stepped(s.q, s.v, t), s.v);
      return Vec6<double>(data.hg);
    });
    EXPECT_LT((data.dhg - fd).norm(), 1e-5 * std::max(1.0, fd.norm()));
  }
}

TEST_F(Algorithms, ZyxConventions) {
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  for (int k = 0; k < kStates; ++k) {
    const Vec3<double> zyx(u(rng) * 2.5, u(rng), u(rng) * 2.5);
    const Mat3<double> R = rotationFromZyx(zyx);
    EXPECT_LT((zyxFromRotation(R) - zyx).norm(), 1e-12);
    const Mat3<double> expected = Eigen::AngleAxisd(zyx[0], Vec3<double>::UnitZ()).toRotationMatrix() *
                                  Eigen::AngleAxisd(zyx[1], Vec3<double>::UnitY()).toRotationMatrix() *
                                  Eigen::AngleAxisd(zyx[2], Vec3<double>::UnitX()).toRotationMatrix();
    EXPECT_LT((R - expected).norm(), 1e-12);
    // ω = E ż: compare [ω]x = Ṙ Rᵀ by finite differences.
    const Vec3<double> rate(u(rng), u(rng), u(rng));
    const Mat3<double> Rdot = centralDifference([&](double t) {
      return Mat3<double>(rotationFromZyx<double>(zyx + t * rate));
    });
    const Mat3<double> W = Rdot * R.transpose();
    const Vec3<double> omega = zyxRateToAngularVelocity(zyx) * rate;
    EXPECT_LT((Vec3<double>(W(2, 1), W(0, 2), W(1, 0)) - omega).norm(), 1e-8);
    EXPECT_LT((angularVelocityToZyxRate(zyx, omega) - rate).norm(), 1e-10);
    for (int k = 0; k < 3; ++k) {
      const Vec3<double> dE = centralDifference([&](double t) {
        Vec3<double> z = zyx;
        z[k] += t;
        return Vec3<double>(zyxRateToAngularVelocity(z) * rate);
      });
      EXPECT_LT((zyxRateToAngularVelocityDerivative(zyx, k, rate) - dE).norm(), 1e-8);
    }
    const Vec3<double> rpy = rpyFromRotation(R);
    EXPECT_NEAR(rpy[0], zyx[2], 1e-12);
    EXPECT_NEAR(rpy[2], zyx[0], 1e-12);
  }
}

TEST_F(Algorithms, CentroidalDynamicsReproducesTheBaseVelocity) {
  // With h = A(q) v and u = [f, q̇_j], eq. (1) must return the base rates v implies.
  const std::vector<int> contacts = {m.frameId("left_toe"), m.frameId("left_heel"),
                                     m.frameId("right_toe"), m.frameId("right_heel")};
  const CentroidalLayout L{m.nj(), 4};
  std::normal_distribution<double> force(0.0, 100.0);
  for (int k = 0; k < kStates; ++k) {
    RandomState s = randomState(m, rng);
    const Mat3<double> R = quaternionToRotation<double>(s.q.segment<4>(3));
    const Vec3<double> zyx = zyxFromRotation(R);
    ccrba(m, data, s.q, s.v);
    VecX<double> x(L.nx()), u(L.nu()), xdot(L.nx());
    x << data.hg, s.q.head<3>(), zyx, s.q.tail(m.nj());
    for (int i = 0; i < 12; ++i) u[i] = force(rng);
    u.tail(m.nj()) = s.v.tail(m.nj());
    centroidalDynamics(m, data, contacts, x, u, xdot);

    EXPECT_LT((xdot.segment<3>(L.kBasePosition) - R * s.v.head<3>()).norm(), 1e-9);
    EXPECT_LT((xdot.segment<3>(L.kBaseZyx) -
               angularVelocityToZyxRate<double>(zyx, R * s.v.segment<3>(3)))
                  .norm(),
              1e-8);
    EXPECT_LT((xdot.tail(m.nj()) - s.v.tail(m.nj())).norm(), 1e-15);
    // Momentum rate: forces and gravity, torques about the CoM.
    centerOfMass(m, data, s.q);
    forwardKinematics(m, data, s.q);
    Vec3<double> f = m.totalMass() * m.gravity, tau = Vec3<double>::Zero();
    for (int c = 0; c < 4; ++c) {
      const Vec3<double> fc = u.segment<3>(3 * c);
      f += fc;
      tau += (framePlacement(m, data, contacts[c]).p - data.com).cross(fc);
    }
    EXPECT_LT((xdot.head<3>() - f).norm(), 1e-9);
    EXPECT_LT((xdot.segment<3>(3) - tau).norm(), 1e-9);
  }
}

TEST_F(Algorithms, IntegrateFollowsTheBodyTwist) {
  const RandomState s = randomState(m, rng);
  forwardKinematics(m, data, s.q, s.v);
  const Motion<double> vBase = frameVelocity(m, data, m.frameId("pelvis"));
  const Vec3<double> fd = centralDifference([&](double t) { return Vec3<double>(stepped(s.q, s.v, t).head<3>()); });
  EXPECT_LT((vBase.linear - fd).norm(), 1e-8);
  // Integrating for a long step along a pure rotation keeps the quaternion normalised.
  VecX<double> q = s.q;
  for (int i = 0; i < 1000; ++i) integrate(m, q, s.v, 0.01, q);
  EXPECT_NEAR(q.segment<4>(3).norm(), 1.0, 1e-12);
}

TEST_F(Algorithms, NeutralConfigurationRespectsLimits) {
  const VecX<double> q = neutralConfiguration(m);
  for (int j = 0; j < m.nj(); ++j) {
    EXPECT_GE(q[Model::qIndexOfJoint(j)], m.lowerPositionLimit[j]);
    EXPECT_LE(q[Model::qIndexOfJoint(j)], m.upperPositionLimit[j]);
  }
  EXPECT_DOUBLE_EQ(q[6], 1.0);
}

}  // namespace
}  // namespace ballast::test
