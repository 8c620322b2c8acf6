// The relaxed log barrier of the paper's eq. (rbf) (Grandia et al. 2019):
//     B(h) = −ξ ln h                  for h ≥ δ
//     B(h) =  ξ β(h; δ)               for h < δ,   β = ½[((h − 2δ)/δ)² − 1] − ln δ
// β continues −ln h from δ on with equal value, slope and curvature, so B is C² and finite
// everywhere: an SQP iterate may leave the feasible set and is pushed back smoothly.
#pragma once

#include <cmath>

namespace ballast::mpc {

struct RelaxedBarrier {
  double weight = 0.1;   ///< ξ
  double delta = 5e-3;   ///< δ, where the log turns quadratic

  double value(double h) const {
    if (h >= delta) return -weight * std::log(h);
    const double r = (h - 2.0 * delta) / delta;
    return weight * (0.5 * (r * r - 1.0) - std::log(delta));
  }
  double firstDerivative(double h) const {
    if (h >= delta) return -weight / h;
    return weight * (h - 2.0 * delta) / (delta * delta);
  }
  double secondDerivative(double h) const {
    if (h >= delta) return weight / (h * h);
    return weight / (delta * delta);
  }
};

}  // namespace ballast::mpc
