// The relaxed log barrier of the paper's eq. (rbf) (Grandia et al. 2019):
//     B(h) = −ξ ln h                  for h ≥ δ
//     B(h) =  ξ β(h; δ)               for h < δ,   β = ½[((h − 2δ)/δ)² − 1] − ln δ
// β continues −ln h from δ on with equal value, slope and curvature, so B is C² and finite
// everywhere: an SQP iterate may leave the feasible set and is pushed back smoothly.
//
// With a reach r (finite), the barrier acts only closer than r to its bound:
//     B_r(h) = B(h) − B(r) − B'(r)(h − r)   for h < r,     0 for h ≥ r,
// convex, C¹, zero with zero slope from r on: a stiff barrier that leaves whatever is farther
// from its bound than r to the other costs (the plain log pulls everything towards the middle of
// its range, by ξ/h).
#pragma once

#include <cmath>
#include <limits>

namespace ballast::mpc {

struct RelaxedBarrier {
  double weight = 0.1;   ///< ξ
  double delta = 5e-3;   ///< δ, where the log turns quadratic
  double reach = std::numeric_limits<double>::infinity();  ///< r: no cost from here on

  double value(double h) const {
    if (!std::isfinite(reach)) return plainValue(h);
    if (h >= reach) return 0.0;
    return plainValue(h) - plainValue(reach) - plainFirstDerivative(reach) * (h - reach);
  }
  double firstDerivative(double h) const {
    if (!std::isfinite(reach)) return plainFirstDerivative(h);
    if (h >= reach) return 0.0;
    return plainFirstDerivative(h) - plainFirstDerivative(reach);
  }
  double secondDerivative(double h) const {
    if (std::isfinite(reach) && h >= reach) return 0.0;
    if (h >= delta) return weight / (h * h);
    return weight / (delta * delta);
  }

 private:
  double plainValue(double h) const {
    if (h >= delta) return -weight * std::log(h);
    const double r = (h - 2.0 * delta) / delta;
    return weight * (0.5 * (r * r - 1.0) - std::log(delta));
  }
  double plainFirstDerivative(double h) const {
    if (h >= delta) return -weight / h;
    return weight * (h - 2.0 * delta) / (delta * delta);
  }
};

}  // namespace ballast::mpc
