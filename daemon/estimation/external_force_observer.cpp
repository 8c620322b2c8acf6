#include "estimation/external_force_observer.hpp"

#include <algorithm>

namespace ballast::estimation {

void ExternalForceObserver::update(const Eigen::Vector3d& momentum,
                                   const Eigen::Vector3d& contactForceSum,
                                   const Eigen::Vector3d& weight, double dt, double bandwidth) {
  if (!started_ || !(dt > 0.0)) {
    momentum_ = momentum;
    force_.setZero();
    started_ = true;
    return;
  }
  const double a = std::min(1.0, bandwidth * dt);
  force_ = (1.0 - a) * force_ + bandwidth * (momentum - momentum_) -
           a * (contactForceSum + weight);
  momentum_ = momentum;
}

Eigen::Vector3d ExternalForceObserver::horizontal(double deadband) const {
  Eigen::Vector3d f(force_.x(), force_.y(), 0.0);
  const double n = f.norm();
  if (n <= deadband) return Eigen::Vector3d::Zero();
  return f * ((n - deadband) / n);
}

}  // namespace ballast::estimation
