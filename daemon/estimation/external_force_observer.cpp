#include "estimation/external_force_observer.hpp"

#include <algorithm>

namespace ballast::estimation {

void ExternalForceObserver::update(const Eigen::Vector3d& momentum,
                                   const Eigen::Vector3d& contactForceSum,
                                   const Eigen::Vector3d& weight, double dt, double bandwidth,
                                   double contactBandwidth) {
  if (!started_ || !(dt > 0.0)) {
    momentum_ = momentum;
    force_.setZero();
    started_ = true;
    return;
  }
  // p_f: the momentum through the contact forces' low-pass (the same discrete form).
  const double c = contactBandwidth > 0.0 ? std::min(1.0, contactBandwidth * dt) : 1.0;
  const Eigen::Vector3d filtered = momentum_ + c * (momentum - momentum_);
  const double a = std::min(1.0, bandwidth * dt);
  force_ = (1.0 - a) * force_ + bandwidth * (filtered - momentum_) -
           a * (contactForceSum + weight);
  momentum_ = filtered;
}

Eigen::Vector3d ExternalForceObserver::horizontal(double deadband) const {
  Eigen::Vector3d f(force_.x(), force_.y(), 0.0);
  const double n = f.norm();
  if (n <= deadband) return Eigen::Vector3d::Zero();
  return f * ((n - deadband) / n);
}

}  // namespace ballast::estimation
