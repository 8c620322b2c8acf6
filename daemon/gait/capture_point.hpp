// The capture point (divergent component of motion, DCM) of the linear inverted pendulum: the
// model in which the footholds are chosen (step_adjustment.hpp) and standing decides to step.
//
// Linear inverted pendulum (LIP): the centre of mass c at constant height z above the contact
// point p (the centre of pressure), an external horizontal force f on the body:
//     c̈ = ω² (c − p) + f/m,          ω = sqrt(g / z).
// The capture point ξ = c + ċ/ω is where p must be for the body to come to rest over it; it
// obeys the first-order, unstable
//     ξ̇ = ω (ξ + d − p),             d = f / (m ω²)
// (d: how far ahead of ξ the centre of pressure must be to hold it against the force: leaning
// into a push), so with p held for Δt
//     ξ(t + Δt) = p − d + (ξ(t) + d − p)·e^{ωΔt},
// which along a LIP trajectory does not change with t for a fixed touch-down time: that is why
// footholds aimed at the predicted capture point hold still through a swing, where a foothold fed
// back from the instantaneous velocity moves with the sway of every step.
//
// Double support: after a touch-down the centre of pressure moves from the foot about to lift
// to the one that landed, taken as linear over the double support time T_d; then it stays on the
// stance foot. Over a time T with p moving from p_a to p_b in the first T_r ≤ T,
//     ξ(T) = e ξ(0) − α p_a − (e − 1 − α) p_b + (e − 1) d,        e = e^{ωT},
//     α = e·[(1 − e^{−x}) − (1 − e^{−x}(1 + x))/x],  x = ω T_r      (α → 0 as T_r → 0).
// A periodic gait (steps of time T, each with T_d of double support; the left foot landing Δ_L
// after the right, the right Δ_R after the left) has at each touch-down the capture point a
// fixed offset b from the foot that just landed (ξ_td − p_new = b, ξ_next = p_new + e b + α Δ,
// p_next = ξ_next − b_next):
//     b_L = (e Δ'_R + Δ'_L)/(e² − 1),  b_R = (e Δ'_L + Δ'_R)/(e² − 1),
//     Δ'_R = Δ_R − α Δ_L,  Δ'_L = Δ_L − α Δ_R   (α with T_r = T_d).
// Forward walking, Δ = (L, ±W): b = ((1 − α) L/(e − 1), ∓(1 + α) W/(e + 1)): ahead of the new
// foot and towards the other one. The double support matters: at 0.4 s steps with 0.08 s of it
// (α ≈ 0.5), the sideways offset is half as large again as with an instant transfer, which is
// what this robot's walking shows; without it the footholds would narrow step by step.
//
// Everything here is 2-D (x, y) in the world frame unless a name says heading frame (x forward,
// y left, rotated by the yaw about z). No allocation.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

namespace ballast::gait {

/// A world vector (x, y) in the heading frame of `yaw` (x forward, y left), and back.
inline Eigen::Vector2d toHeading(const Eigen::Vector2d& v, double yaw) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  return Eigen::Vector2d(c * v.x() + s * v.y(), -s * v.x() + c * v.y());
}
inline Eigen::Vector2d fromHeading(const Eigen::Vector2d& v, double yaw) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  return Eigen::Vector2d(c * v.x() - s * v.y(), s * v.x() + c * v.y());
}

/// ω of the pendulum for a centre of mass `height` above the contact points, 1/s.
inline double pendulumFrequency(double height, double gravity = 9.81) {
  return std::sqrt(gravity / height);
}

/// ξ = c + ċ/ω.
inline Eigen::Vector2d capturePoint(const Eigen::Vector2d& com, const Eigen::Vector2d& comVelocity,
                                    double omega) {
  return com + comVelocity / omega;
}

/// d = f/(m ω²): how far ahead of ξ the centre of pressure holds ξ still against a constant
/// horizontal force f (N).
inline Eigen::Vector2d forceOffset(const Eigen::Vector2d& force, double mass, double omega) {
  return force / (mass * omega * omega);
}

/// ξ after `dt` s with the centre of pressure held at `cop` and the force offset d.
inline Eigen::Vector2d predictCapturePoint(const Eigen::Vector2d& xi, const Eigen::Vector2d& cop,
                                           double omega, double dt,
                                           const Eigen::Vector2d& d = Eigen::Vector2d::Zero()) {
  return cop - d + (xi + d - cop) * std::exp(omega * dt);
}

/// α of the header comment: the weight of the centre of pressure's start point p_a when it moves
/// linearly to p_b over `ramp` s and stays there until `dt` s.
inline double rampWeight(double omega, double ramp, double dt) {
  const double x = omega * ramp;
  const double shape = x < 1e-6 ? 0.5 * x
                                : (1.0 - std::exp(-x)) - (1.0 - std::exp(-x) * (1.0 + x)) / x;
  return std::exp(omega * dt) * shape;
}

/// ξ after `dt` s with the centre of pressure moving linearly from `from` to `to` over the first
/// `ramp` s (clamped to [0, dt]) and held at `to` after, and the force offset d.
inline Eigen::Vector2d predictCapturePoint(const Eigen::Vector2d& xi, const Eigen::Vector2d& from,
                                           const Eigen::Vector2d& to, double omega, double ramp,
                                           double dt,
                                           const Eigen::Vector2d& d = Eigen::Vector2d::Zero()) {
  const double e = std::exp(omega * dt);
  const double a = rampWeight(omega, std::clamp(ramp, 0.0, dt), dt);
  return e * xi - a * from - (e - 1.0 - a) * to + (e - 1.0) * d;
}

/// The capture point offsets of a periodic gait at touch-down, from the foot that just landed
/// (see the header comment). stepToLeft: the left foot's landing relative to the right foot
/// before it; stepToRight likewise. Any frame, as long as both steps are in it.
struct PeriodicOffsets {
  Eigen::Vector2d left = Eigen::Vector2d::Zero();   ///< b_L: when the left foot lands
  Eigen::Vector2d right = Eigen::Vector2d::Zero();  ///< b_R
};
inline PeriodicOffsets periodicOffsets(const Eigen::Vector2d& stepToLeft,
                                       const Eigen::Vector2d& stepToRight, double omega,
                                       double stepTime, double doubleSupportTime = 0.0) {
  const double e = std::exp(omega * stepTime);
  const double a = rampWeight(omega, std::clamp(doubleSupportTime, 0.0, stepTime), stepTime);
  const Eigen::Vector2d toLeft = stepToLeft - a * stepToRight;
  const Eigen::Vector2d toRight = stepToRight - a * stepToLeft;
  const double den = e * e - 1.0;
  PeriodicOffsets b;
  b.left = (e * toRight + toLeft) / den;
  b.right = (e * toLeft + toRight) / den;
  return b;
}

/// Signed distance from q to the convex polygon `points` (any order; the hull is taken), m:
/// negative inside (the distance to the nearest edge), positive outside.
template <int N>
double signedDistanceToHull(const Eigen::Matrix<double, 2, N>& points, const Eigen::Vector2d& q) {
  // Gift wrapping over at most N points (N is 4 here: the contact points).
  int hull[N];
  int h = 0;
  int start = 0;
  for (int i = 1; i < N; ++i)
    if (points(0, i) < points(0, start) ||
        (points(0, i) == points(0, start) && points(1, i) < points(1, start)))
      start = i;
  int current = start;
  do {
    hull[h++] = current;
    int next = (current + 1) % N;
    for (int i = 0; i < N; ++i) {
      const Eigen::Vector2d a = points.col(next) - points.col(current);
      const Eigen::Vector2d b = points.col(i) - points.col(current);
      const double cross = a.x() * b.y() - a.y() * b.x();
      if (cross < 0.0 || (cross == 0.0 && b.squaredNorm() > a.squaredNorm())) next = i;
    }
    current = next;
  } while (current != start && h < N);
  // Counter-clockwise hull: inside is left of every edge.
  double inside = -1e300, outside = 1e300;
  bool out = false;
  for (int i = 0; i < h; ++i) {
    const Eigen::Vector2d a = points.col(hull[i]), b = points.col(hull[(i + 1) % h]);
    const Eigen::Vector2d e = b - a;
    const double len = e.norm();
    if (len < 1e-12) continue;
    const double side = (e.x() * (q - a).y() - e.y() * (q - a).x()) / len;  // > 0: left (inside)
    inside = std::max(inside, -side);
    if (side < 0.0) out = true;
    const double s = std::clamp((q - a).dot(e) / (len * len), 0.0, 1.0);
    outside = std::min(outside, (a + s * e - q).norm());
  }
  if (h == 1) return (q - points.col(hull[0])).norm();
  if (h == 2) return outside;
  return out ? outside : inside;
}

}  // namespace ballast::gait
