// Where a foot lands on terrain that is not flat everywhere: the paper's foothold
// (footholds.hpp) where the ground under the whole foot is good, otherwise the nearest place in
// a small window around it where it is.
//
// A foot is its toe and heel contact points. A placement of the foot (the paper's foothold of
// both points moved by one horizontal offset d) is good when, around each point (the point and
// `patch` ahead, behind, left and right of it), every column is known (observed, not the
// ground default) and the heights differ by no more than `edgeTolerance` or a slope of
// `maxSlope` across the patch (no step edge, no steep cell under the point); and toe and heel
// stand on one level or one such slope. The paper's foothold (d = 0) is kept when it is good; otherwise the good d
// nearest to it on a grid of `step` within `radius`; none good: the paper's foothold, as
// before. The search is by the foot's centre (the midpoint of toe and heel), so the swings of
// its two points, planned one after the other, find the same offset.
//
// Cost: (2·radius/step + 1)² placements of 10 height samples each; 81 × 10 at the defaults,
// a few µs per foot on the planner thread. Allocates nothing.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "gait/terrain_query.hpp"

namespace ballast::gait {

struct FootholdSearchParameters {
  bool enabled = true;
  double radius = 0.08;         ///< m, half width of the searched window
  double step = 0.02;           ///< m, between the placements tried
  double patch = 0.03;          ///< m, around each contact point that must be good
  double edgeTolerance = 0.02;  ///< m, largest height difference under a foot
  double maxSlope = 0.35;       ///< dz per metre (≈ 19°)
};

/// Whether the ground under toe and heel at (toe, heel) + d is good (see the header comment).
inline bool goodPlacement(const Eigen::Vector3d& toe, const Eigen::Vector3d& heel, double dx,
                          double dy, const TerrainQuery& terrain, const FootholdSearchParameters& s) {
  // Within a point's patch (2·patch wide): a step edge, or a slope steeper than maxSlope.
  const double patchRise = std::max(s.edgeTolerance, 2.0 * s.patch * s.maxSlope);
  double level[2];
  int k = 0;
  for (const Eigen::Vector3d* p : {&toe, &heel}) {
    const double x = p->x() + dx, y = p->y() + dy;
    const double xs[5] = {x, x + s.patch, x - s.patch, x, x};
    const double ys[5] = {y, y, y, y + s.patch, y - s.patch};
    double lo = INFINITY, hi = -INFINITY;
    for (int i = 0; i < 5; ++i) {
      if (!terrain.known(xs[i], ys[i])) return false;
      const double h = terrain.height(xs[i], ys[i]);
      lo = std::min(lo, h), hi = std::max(hi, h);
    }
    if (hi - lo > patchRise) return false;
    level[k++] = terrain.height(x, y);
  }
  // Toe and heel on one level, or on one slope no steeper than maxSlope.
  const double length = std::hypot(toe.x() - heel.x(), toe.y() - heel.y());
  return std::abs(level[0] - level[1]) <= s.edgeTolerance + s.maxSlope * length;
}

/// The offset (x, y, 0) to add to both points of a foot whose paper's footholds are toe and
/// heel; zero where those are good, or where nothing in the window is.
inline Eigen::Vector3d footholdOffset(const Eigen::Vector3d& toe, const Eigen::Vector3d& heel,
                                      const TerrainQuery& terrain,
                                      const FootholdSearchParameters& s) {
  if (!s.enabled || goodPlacement(toe, heel, 0.0, 0.0, terrain, s)) return Eigen::Vector3d::Zero();
  const int n = static_cast<int>(std::floor(s.radius / s.step + 1e-9));
  double best = INFINITY;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j) {
      const double dx = i * s.step, dy = j * s.step, d2 = dx * dx + dy * dy;
      if (d2 >= best || d2 > s.radius * s.radius + 1e-12) continue;
      if (!goodPlacement(toe, heel, dx, dy, terrain, s)) continue;
      best = d2;
      offset = Eigen::Vector3d(dx, dy, 0.0);
    }
  return offset;
}

}  // namespace ballast::gait
