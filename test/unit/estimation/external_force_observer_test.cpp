// The external force observer on made-up signals: a body whose contact forces the estimator sees
// through a first-order low-pass (as the contact force observer gives them), with and without a
// push, and a load that changes hands the way it does at a touch-down.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "estimation/external_force_observer.hpp"

namespace ballast::estimation {
namespace {

using Eigen::Vector3d;

constexpr double kDt = 0.001, kMass = 60.0, kContactBandwidth = 50.0, kBandwidth = 10.0;

/// Runs 1 s: the true contact force is `contact(t)` (world), the push `push(t)`; the momentum
/// follows Newton, the estimator sees the contact force low-passed at kContactBandwidth.
/// Returns the largest |estimate − push| after `from` s (the push's own step response aside).
template <typename Contact, typename Push>
double largestError(Contact contact, Push push, double contactBandwidth, double from,
                    Vector3d* last = nullptr) {
  ExternalForceObserver observer;
  const Vector3d weight(0.0, 0.0, -kMass * 9.81);
  Vector3d momentum = Vector3d::Zero(), seen = contact(0.0);
  double worst = 0.0;
  for (int k = 0; k <= 1000; ++k) {
    const double t = k * kDt;
    momentum += kDt * (contact(t) + weight + push(t));
    seen += std::min(1.0, kContactBandwidth * kDt) * (contact(t) - seen);
    observer.update(momentum, seen, weight, kDt, kBandwidth, contactBandwidth);
    if (t >= from) worst = std::max(worst, (observer.raw() - push(t)).norm());
  }
  if (last) *last = observer.raw();
  return worst;
}

TEST(ExternalForceObserver, AConstantPushIsFoundWithinItsTimeConstant) {
  const auto contact = [](double) { return Vector3d(0.0, 0.0, kMass * 9.81); };
  const auto push = [](double) { return Vector3d(0.0, 60.0, 0.0); };
  Vector3d f;
  // 0.5 s is five time constants (1/K): within 1 % of the push.
  EXPECT_LT(largestError(contact, push, kContactBandwidth, 0.5, &f), 0.6);
  EXPECT_NEAR(f.y(), 60.0, 0.1);
}

TEST(ExternalForceObserver, ALoadChangingHandsIsNoPush) {
  // At a touch-down the ground force jumps within a few ms: here a 600 N step in z and a 100 N
  // sideways one (the feet's friction as the weight moves across), with no push. The momentum
  // follows the true force, the contact estimate its low-pass; filtering the momentum alike
  // leaves nothing. Unfiltered, the difference read as a push of up to K/K_c of the step.
  const auto contact = [](double t) {
    return t < 0.3 ? Vector3d(0.0, 0.0, kMass * 9.81)
                   : Vector3d(0.0, 100.0, kMass * 9.81 + 600.0);
  };
  const auto none = [](double) { return Vector3d::Zero(); };
  // The body is accelerated by the step (100 N sideways, 600 N up are real forces here, not a
  // push): the estimate must stay at zero through it.
  EXPECT_LT(largestError(contact, none, kContactBandwidth, 0.0), 1.0);
  const double unfiltered = largestError(contact, none, 0.0, 0.0);
  EXPECT_GT(unfiltered, 50.0);  // what the matched filter removes (78 N)
}

TEST(ExternalForceObserver, TheLoadAStretchedLegCannotSenseIsNoPush) {
  // One foot carries the body along a leaning leg d while a 60 N push acts sideways (the body
  // accelerates with it). Its leg straight, the contact force observer misses W·F of the foot's
  // force, W = d dᵀ (contact_force_observer.hpp): the force along the leg. Told W, the observer
  // takes that part from the vertical balance and finds the push; not told, it reads the missing
  // force's horizontal part as a push too.
  const Vector3d d = Vector3d(-0.25, 0.3, 0.92).normalized();
  const Eigen::Matrix3d W = d * d.transpose();
  const Vector3d weight(0.0, 0.0, -kMass * 9.81), push(0.0, 60.0, 0.0);
  const Vector3d F = (kMass * 9.81 / d.z()) * d;  // holds the weight, along the leg
  auto run = [&](const Eigen::Matrix3d& told) {
    ExternalForceObserver observer;
    Vector3d momentum = Vector3d::Zero(), seen = Vector3d::Zero(), last = Vector3d::Zero();
    const double c = std::min(1.0, kContactBandwidth * kDt);
    for (int k = 0; k <= 1000; ++k) {
      // The leg straightens at 0.2 s: from then on its load goes unseen.
      const bool straight = k * kDt >= 0.2;
      const Eigen::Matrix3d missed = straight ? W : Eigen::Matrix3d::Zero();
      momentum += kDt * (F + weight + push);
      seen += c * ((Eigen::Matrix3d::Identity() - missed) * F - seen);
      observer.update(momentum, seen, weight, kDt, kBandwidth, kContactBandwidth,
                      straight ? told : Eigen::Matrix3d::Zero());
      last = observer.raw();
    }
    return Vector3d(last.x(), last.y(), 0.0);
  };
  const Vector3d told = run(W), blind = run(Eigen::Matrix3d::Zero());
  std::printf("estimate told (%.1f, %.1f) N, not told (%.1f, %.1f) N, true (0, 60) N\n", told.x(),
              told.y(), blind.x(), blind.y());
  // The estimate falls ε/(W_zz + ε) of the missing force short (external_force_observer.hpp).
  EXPECT_LT((told - push).norm(), 2.0);
  EXPECT_GT((blind - push).norm(), 100.0);
}

}  // namespace
}  // namespace ballast::estimation
