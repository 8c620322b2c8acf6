// The 1 kHz path allocates nothing: every algorithm, run on a prepared Data, is watched by a
// counting malloc.
#include <gtest/gtest.h>

#include "test/unit/allocation_counter.hpp"
#include "model/autodiff.hpp"
#include "test/unit/test_support.hpp"

namespace ballast::test {
namespace {

using namespace model;

TEST(NoAllocation, CounterSeesAnAllocation) {
  EXPECT_GT(allocationsIn([] { VecX<double> x(100); x.setZero(); }), 0);
}

TEST(NoAllocation, RigidBodyAlgorithms) {
  const Model& m = humanoid();
  Data<double> d(m);
  std::mt19937 rng(1);
  const RandomState s = randomState(m, rng);
  const std::vector<int> contacts{m.frameId("left_toe"), m.frameId("left_heel"),
                                  m.frameId("right_toe"), m.frameId("right_heel")};
  Mat6X<double> J(6, m.nv);
  Mat3X<double> Jc(3, m.nv);
  const CentroidalLayout L{m.nj(), 4};
  VecX<double> x = VecX<double>::Zero(L.nx()), u = VecX<double>::Zero(L.nu()), xdot(L.nx());
  x.segment(L.kJoints, m.nj()) = s.q.tail(m.nj());
  ForwardJacobianWorkspace<8> ws(L.nx() + L.nu(), L.nx());
  Data<ceres::Jet<double, 8>> dj(m);
  VecX<double> z(L.nx() + L.nu());
  z << x, u;
  MatX<double> Jz(L.nx(), L.nx() + L.nu()), Ax(L.nx(), L.nx()), Bu(L.nx(), L.nu());
  const long n = allocationsIn([&] {
    forwardKinematics(m, d, s.q, s.v, s.a);
    forwardKinematicsBias(m, d, s.q, s.v);
    updateFramePlacements(m, d);
    frameJacobian(m, d, contacts[0], J);
    frameJacobian(m, d, contacts[1], Jc);
    frameClassicalAcceleration(m, d, contacts[2]);
    frameVelocity(m, d, contacts[3]);
    crba(m, d, s.q);
    rnea(m, d, s.q, s.v, s.a);
    nonLinearEffects(m, d, s.q, s.v);
    centerOfMass(m, d, s.q);
    ccrba(m, d, s.q, s.v);
    centroidalMomentumBias(m, d, s.q, s.v);
    centroidalDynamics(m, d, contacts, x, u, xdot);
    centroidalDynamicsDerivatives(m, d, contacts, x, u, xdot, Ax, Bu);
    forwardJacobian(
        [&](const auto& zj, auto& yj) {
          centroidalDynamics(m, dj, contacts, zj.head(L.nx()), zj.tail(L.nu()), yj);
        },
        z, ws, Jz);
  });
  EXPECT_EQ(n, 0);
}

}  // namespace
}  // namespace ballast::test
