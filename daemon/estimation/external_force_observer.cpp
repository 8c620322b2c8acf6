#include "estimation/external_force_observer.hpp"

#include <algorithm>

namespace ballast::estimation {

void ExternalForceObserver::update(const Eigen::Vector3d& momentum,
                                   const Eigen::Vector3d& contactForceSum,
                                   const Eigen::Vector3d& weight, double dt, double bandwidth,
                                   double contactBandwidth, const Eigen::Matrix3d& unsensedLoad) {
  if (!started_ || !(dt > 0.0)) {
    momentum_ = momentum;
    force_.setZero();
    unsensed_.setZero();
    started_ = true;
    return;
  }
  // p_f: the momentum through the contact forces' low-pass (the same discrete form).
  const double c = contactBandwidth > 0.0 ? std::min(1.0, contactBandwidth * dt) : 1.0;
  const Eigen::Vector3d filtered = momentum_ + c * (momentum - momentum_);
  // The load the stance legs could not sense, from the vertical balance (header); W through the
  // same low-pass. Under kSensed nothing is added (header).
  unsensed_ += c * (unsensedLoad - unsensed_);
  constexpr double kEpsilon = 0.005, kSensed = 1e-3;
  const double wzz = unsensed_(2, 2);
  Eigen::Vector3d contacts = contactForceSum;
  if (wzz > kSensed) {
    const double deficit = (filtered.z() - momentum_.z()) / dt - contactForceSum.z() - weight.z();
    contacts += unsensed_.col(2) * (deficit / (wzz + kEpsilon));
  }
  const double a = std::min(1.0, bandwidth * dt);
  force_ = (1.0 - a) * force_ + bandwidth * (filtered - momentum_) - a * (contacts + weight);
  momentum_ = filtered;
}

Eigen::Vector3d ExternalForceObserver::horizontal(double deadband) const {
  Eigen::Vector3d f(force_.x(), force_.y(), 0.0);
  const double n = f.norm();
  if (n <= deadband) return Eigen::Vector3d::Zero();
  return f * ((n - deadband) / n);
}

}  // namespace ballast::estimation
