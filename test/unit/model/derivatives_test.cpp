// Exact derivatives by ceres::Jet through the templated algorithms, against central finite
// differences: contact positions, A(q)·v, and the Jacobians of the planner's dynamics eq. (1).
#include <gtest/gtest.h>

#include "model/autodiff.hpp"
#include "test/unit/test_support.hpp"

namespace ballast::test {
namespace {

using namespace model;
constexpr int kChunk = 8;
using Jet = ceres::Jet<double, kChunk>;

/// Central-difference Jacobian of y = f(x) (f: VecX -> VecX).
template <typename F>
MatX<double> finiteDifferenceJacobian(F&& f, const VecX<double>& x, int ny, double h = 1e-6) {
  MatX<double> J(ny, x.size());
  for (int i = 0; i < x.size(); ++i) {
    VecX<double> xp = x, xm = x;
    xp[i] += h;
    xm[i] -= h;
    J.col(i) = (f(xp) - f(xm)) / (2 * h);
  }
  return J;
}

::testing::AssertionResult jacobiansAgree(const MatX<double>& ad, const MatX<double>& fd) {
  const double err = (ad - fd).cwiseAbs().maxCoeff();
  const double tol = 1e-6 * std::max(1.0, fd.cwiseAbs().maxCoeff());
  if (err <= tol) return ::testing::AssertionSuccess();
  Eigen::Index r, c;
  (ad - fd).cwiseAbs().maxCoeff(&r, &c);
  return ::testing::AssertionFailure() << "max error " << err << " at (" << r << ", " << c
                                       << "): AD " << ad(r, c) << " FD " << fd(r, c);
}

class Derivatives : public ::testing::Test {
 protected:
  const Model& m = humanoid();
  const std::vector<int> contacts{m.frameId("left_toe"), m.frameId("left_heel"),
                                  m.frameId("right_toe"), m.frameId("right_heel")};
  Data<double> data{m};
  Data<Jet> dataJet{m};
  std::mt19937 rng{5};

  /// A random ZYX-coordinate configuration [p, zyx, q_j] away from the Euler singularity.
  VecX<double> randomZyxConfiguration() {
    const VecX<double> q = randomConfiguration(m, rng);
    VecX<double> x(6 + m.nj());
    Vec3<double> zyx = zyxFromRotation(quaternionToRotation<double>(q.segment<4>(3)));
    zyx[1] *= 0.8;
    x << q.head<3>(), zyx, q.tail(m.nj());
    return x;
  }

  template <typename S>
  VecX<S> configuration(const VecX<S>& xq) const {
    VecX<S> q(m.nq);
    q << xq.template head<3>(), quaternionXyzwFromZyx<S>(xq.template segment<3>(3)),
        xq.tail(m.nj());
    return q;
  }

  template <typename S>
  void contactPositions(Data<S>& d, const VecX<S>& xq, VecX<S>& out) const {
    forwardKinematics(m, d, configuration<S>(xq));
    for (int c = 0; c < 4; ++c) out.template segment<3>(3 * c) = framePlacement(m, d, contacts[c]).p;
  }
};

TEST_F(Derivatives, ContactPositions) {
  for (int k = 0; k < 20; ++k) {
    const VecX<double> x = randomZyxConfiguration();
    ForwardJacobianWorkspace<kChunk> ws(x.size(), 12);
    MatX<double> Jad(12, x.size());
    forwardJacobian([&](const auto& xj, auto& yj) { contactPositions(dataJet, xj, yj); }, x, ws, Jad);
    const MatX<double> Jfd = finiteDifferenceJacobian(
        [&](const VecX<double>& xx) {
          VecX<double> y(12);
          contactPositions(data, xx, y);
          return y;
        },
        x, 12);
    EXPECT_TRUE(jacobiansAgree(Jad, Jfd));
  }
}

TEST_F(Derivatives, CentroidalMomentumMatrixTimesVelocity) {
  std::uniform_real_distribution<double> u(-2, 2);
  for (int k = 0; k < 20; ++k) {
    const VecX<double> x = randomZyxConfiguration();
    const VecX<double> v = VecX<double>::NullaryExpr(m.nv, [&] { return u(rng); });
    auto Av = [&](auto& d, const auto& xq, auto& out) {
      using S = typename std::decay_t<decltype(xq)>::Scalar;
      ccrba(m, d, configuration<S>(xq), v.template cast<S>());
      out = d.hg;
    };
    ForwardJacobianWorkspace<kChunk> ws(x.size(), 6);
    MatX<double> Jad(6, x.size());
    forwardJacobian([&](const auto& xj, auto& yj) { Av(dataJet, xj, yj); }, x, ws, Jad);
    const MatX<double> Jfd = finiteDifferenceJacobian(
        [&](const VecX<double>& xx) {
          VecX<double> y(6);
          Av(data, xx, y);
          return y;
        },
        x, 6);
    EXPECT_TRUE(jacobiansAgree(Jad, Jfd));
  }
}

TEST_F(Derivatives, CentroidalDynamicsJacobians) {
  const CentroidalLayout L{m.nj(), 4};
  std::normal_distribution<double> n(0, 1);
  for (int k = 0; k < 10; ++k) {
    const VecX<double> xq = randomZyxConfiguration();
    VecX<double> z(L.nx() + L.nu());  // [x; u]
    z << VecX<double>::NullaryExpr(6, [&] { return 10 * n(rng); }), xq,
        VecX<double>::NullaryExpr(12, [&] { return 150 * n(rng); }),
        VecX<double>::NullaryExpr(m.nj(), [&] { return n(rng); });
    auto f = [&](auto& d, const auto& zz, auto& out) {
      centroidalDynamics(m, d, contacts, zz.head(L.nx()), zz.tail(L.nu()), out);
    };
    ForwardJacobianWorkspace<kChunk> ws(z.size(), L.nx());
    MatX<double> Jad(L.nx(), z.size());
    forwardJacobian([&](const auto& zj, auto& yj) { f(dataJet, zj, yj); }, z, ws, Jad);
    const MatX<double> Jfd = finiteDifferenceJacobian(
        [&](const VecX<double>& zz) {
          VecX<double> y(L.nx());
          f(data, zz, y);
          return y;
        },
        z, L.nx());
    EXPECT_TRUE(jacobiansAgree(Jad, Jfd));
    // Translation invariance: nothing depends on the base position.
    EXPECT_LT(Jad.middleCols<3>(L.kBasePosition).cwiseAbs().maxCoeff(), 1e-9);

    // The analytic O(n) Jacobians agree with automatic differentiation to rounding.
    VecX<double> xdot(L.nx()), xdotRef(L.nx());
    MatX<double> Ax(L.nx(), L.nx()), Bu(L.nx(), L.nu());
    centroidalDynamicsDerivatives(m, data, contacts, z.head(L.nx()), z.tail(L.nu()), xdot, Ax, Bu);
    f(data, z, xdotRef);
    EXPECT_LT((xdot - xdotRef).norm(), 1e-9 * std::max(1.0, xdotRef.norm()));
    const double scale = std::max(1.0, Jad.cwiseAbs().maxCoeff());
    EXPECT_LT((Ax - Jad.leftCols(L.nx())).cwiseAbs().maxCoeff(), 1e-9 * scale);
    EXPECT_LT((Bu - Jad.rightCols(L.nu())).cwiseAbs().maxCoeff(), 1e-9 * scale);
  }
}

TEST_F(Derivatives, FramePositionAndVelocityInPlannerCoordinates) {
  const CentroidalLayout L{m.nj(), 4};
  std::normal_distribution<double> n(0, 1);
  const int frames[] = {m.frameId("left_toe"), m.frameId("right_heel"), m.frameId("left_hand"),
                        m.frameId("pelvis")};
  for (int k = 0; k < 10; ++k) {
    const VecX<double> xq = randomZyxConfiguration();
    VecX<double> z(L.nx() + L.nu());
    z << VecX<double>::NullaryExpr(6, [&] { return 10 * n(rng); }), xq,
        VecX<double>::NullaryExpr(12, [&] { return 150 * n(rng); }),
        VecX<double>::NullaryExpr(m.nj(), [&] { return n(rng); });
    for (int f : frames) {
      // Position and velocity as plain functions of z, for finite differences.
      auto value = [&](const VecX<double>& zz) {
        VecX<double> xdot(L.nx()), out(6);
        MatX<double> Ax(L.nx(), L.nx()), Bu(L.nx(), L.nu());
        centroidalDynamicsDerivatives(m, data, contacts, zz.head(L.nx()), zz.tail(L.nu()), xdot, Ax, Bu);
        FrameKinematicsZyx fk(L.nx(), L.nu());
        frameKinematicsZyx(m, data, f, zz.head(L.nx()), Ax, Bu, fk);
        out << fk.position, fk.velocity;
        return out;
      };
      VecX<double> xdot(L.nx());
      MatX<double> Ax(L.nx(), L.nx()), Bu(L.nx(), L.nu());
      centroidalDynamicsDerivatives(m, data, contacts, z.head(L.nx()), z.tail(L.nu()), xdot, Ax, Bu);
      FrameKinematicsZyx fk(L.nx(), L.nu());
      frameKinematicsZyx(m, data, f, z.head(L.nx()), Ax, Bu, fk);
      // The velocity is the time derivative of the position along ẋ = f(x, u).
      EXPECT_LT((fk.velocity - fk.dPosition_dx * xdot).norm(), 1e-9 * std::max(1.0, fk.velocity.norm()));
      const MatX<double> Jfd = finiteDifferenceJacobian(value, z, 6);
      MatX<double> Jan(6, z.size());
      Jan << fk.dPosition_dx, MatX<double>::Zero(3, L.nu()), fk.dVelocity_dx, fk.dVelocity_du;
      EXPECT_TRUE(jacobiansAgree(Jan, Jfd)) << m.frames[f].name;
    }
  }
}

}  // namespace
}  // namespace ballast::test
