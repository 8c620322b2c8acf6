// Where a foot lands on terrain that is not flat everywhere: the paper's foothold
// (footholds.hpp) where the ground under the whole foot is good, otherwise the nearest place in
// a small window around it where it is.
//
// A foot is its toe and heel contact points. A placement of the foot (the paper's foothold of
// both points moved by one horizontal offset d) is good when, around each point (the point and
// `patch` ahead, behind, left and right of it), every column is known (observed, not the
// ground default) and the heights differ by no more than `edgeTolerance` or a slope of
// `maxSlope` across the patch, nor along its lines through the point (no step edge, no steep
// cell under the point); the sole between them crosses no edge; and toe and heel stand on one
// level or one such slope. A good placement is also supported when the flat sole rests on its
// toe and heel there: no edge under it props it up (supported()). The paper's foothold (d = 0)
// is kept when it is good and supported; otherwise the good and supported d nearest to it on a
// grid of `step` within `radius` and within supportShiftAcross across the foot; none such: the
// paper's foothold if it is good, else the nearest good d; none good: the paper's foothold, as
// before. The search is by the foot's
// centre (the midpoint of toe and heel), so the swings of its two points, planned one after the
// other, find the same offset.
//
// Cost: (2·radius/step + 1)² placements of up to 48 height samples each (goodPlacement) and,
// for the good ones, up to 17 × 7 more (supported, 20 cm feet); 361 placements for the
// humanoid's 20 cm feet (the window grows to 18 cm for them, see searchRadius), where a
// placement is searched at all, once per foot and touch-down on the planner thread.
// Allocates nothing.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "gait/terrain_query.hpp"

namespace ballast::gait {

struct FootholdSearchParameters {
  bool enabled = true;
  /// m, half width of the searched window, at least: a foot straddling an edge moves off it by
  /// up to half its length plus the patch and one step, and the window grows to that where it
  /// is wider (searchRadius)
  double radius = 0.12;
  double step = 0.02;           ///< m, between the placements tried
  /// m, around each contact point that must be good: the sole beyond the point (2 cm on the
  /// humanoid) and a swing's landing error onto a step (3-4 cm onto a 15 cm stage)
  double patch = 0.06;
  double edgeTolerance = 0.02;  ///< m, largest height difference under a foot
  double maxSlope = 0.35;       ///< dz per metre (≈ 19°)
  /// m, how far the ground under a sole may stand above the line from heel to toe, and, within
  /// `patch` of either point, below it, for the sole to rest on its toe and heel (supported()).
  /// A quarter of a 2 cm map's cell: a 2 cm edge anywhere under the sole is more.
  double supportTolerance = 0.005;
  /// m, farthest a foot moves across itself (toe to heel being along it) to a supported
  /// placement: moving sideways narrows or widens the stance the robot rolls over, which the
  /// gait does not plan for (searched across the whole window, a foot could land next to the
  /// other); too tight, a foot across an edge finds no support at all.
  double supportShiftAcross = 0.04;
};

/// Height samples under a sole, heel to toe (a longer sole is sampled more sparsely).
inline constexpr int kMaxSoleSamples = 32;

/// Whether the heights along (x0, y0)-(x1, y1), sampled at n + 1 points, hold no edge: any two
/// differ by at most edgeTolerance plus maxSlope over the distance between them, not only
/// neighbours (a map's column at an edge can hold part of the rise: a lidar map's face hits read
/// 2 cm in front of a 4 cm stage, and neighbour by neighbour each part passed as within
/// edgeTolerance). n <= kMaxSoleSamples - 1.
inline bool levelAlong(double x0, double y0, double x1, double y1, int n,
                       const TerrainQuery& terrain, const FootholdSearchParameters& s) {
  const double spacing = std::hypot(x1 - x0, y1 - y0) / n;
  double h[kMaxSoleSamples];
  for (int i = 0; i <= n; ++i) {
    const double a = static_cast<double>(i) / n;
    h[i] = terrain.height(x0 + a * (x1 - x0), y0 + a * (y1 - y0));
    for (int j = 0; j < i; ++j)
      if (std::abs(h[i] - h[j]) > s.edgeTolerance + s.maxSlope * spacing * (i - j)) return false;
  }
  return true;
}

/// Whether the ground under toe and heel at (toe, heel) + d is good (see the header comment).
inline bool goodPlacement(const Eigen::Vector3d& toe, const Eigen::Vector3d& heel, double dx,
                          double dy, const TerrainQuery& terrain, const FootholdSearchParameters& s) {
  // Between a point and each sample around it: a step edge, or a slope steeper than maxSlope.
  // (Held to the patch's width, the rise a slope may make grows with it, and a wide patch took
  // a 4 cm step for a ramp.)
  const double patchRise = std::max(s.edgeTolerance, s.patch * s.maxSlope);
  // The patch's lines through the point, sampled every `step`, hold no edge either: a point on
  // an edge reads the middle of a map's interpolated rise, within patchRise of both sides (a
  // heel planned at 1.500 on a 5 cm stage from x = 1.5, read 0.02 between 0 and 0.04, landed
  // 1 cm short on the floor's side, and the foot pitched over the edge).
  const int across = std::clamp(static_cast<int>(std::ceil(2.0 * s.patch / s.step)), 1,
                                kMaxSoleSamples - 1);
  double level[2];
  int k = 0;
  for (const Eigen::Vector3d* p : {&toe, &heel}) {
    const double x = p->x() + dx, y = p->y() + dy;
    if (!terrain.known(x, y)) return false;
    const double h = terrain.height(x, y);
    const double xs[4] = {x + s.patch, x - s.patch, x, x};
    const double ys[4] = {y, y, y + s.patch, y - s.patch};
    for (int i = 0; i < 4; ++i)
      if (!terrain.known(xs[i], ys[i]) || std::abs(terrain.height(xs[i], ys[i]) - h) > patchRise)
        return false;
    if (!levelAlong(xs[1], y, xs[0], y, across, terrain, s) ||
        !levelAlong(x, ys[1], x, ys[0], across, terrain, s))
      return false;
    level[k++] = h;
  }
  // Under the sole between them, sampled every `step`: no edge (toe on a stage, heel on the
  // floor is not a slope).
  const double length = std::hypot(toe.x() - heel.x(), toe.y() - heel.y());
  const int n = std::clamp(static_cast<int>(std::ceil(length / s.step)), 1, kMaxSoleSamples - 1);
  if (!levelAlong(heel.x() + dx, heel.y() + dy, toe.x() + dx, toe.y() + dy, n, terrain, s))
    return false;
  // Toe and heel on one level, or on one slope no steeper than maxSlope.
  return std::abs(level[0] - level[1]) <= s.edgeTolerance + s.maxSlope * length;
}

/// Whether a flat sole set down at (toe, heel) + d rests on its toe and heel: nothing under it
/// (from `patch` behind the heel to `patch` ahead of the toe, `patch` to either side of the line
/// between them, sampled every `step`) stands more than supportTolerance above the line from
/// the heel's height to the toe's, and within `patch` of either point nothing lies more than
/// that below it. goodPlacement() takes an edge up to edgeTolerance under a sole for a slope
/// (a 2 cm-cell map holds a ramp as 2 cm stairs); on ground of level patches such an edge is a
/// corner the sole rests on instead of its heel or toe: on sim-rough (2 cm edges), a foot planned
/// with its heel on a 2 cm patch and its toe on the next one down pivoted on the edge between
/// them, its heel unloaded and the robot pitched over it (Simbody, 29.6 s into a 30 s walk at
/// 0.5 m/s). A gap under the sole's middle (a lower patch between toe and heel) is no harm.
inline bool supported(const Eigen::Vector3d& toe, const Eigen::Vector3d& heel, double dx,
                      double dy, const TerrainQuery& terrain, const FootholdSearchParameters& s) {
  const double length = std::hypot(toe.x() - heel.x(), toe.y() - heel.y());
  if (length < 1e-9) return true;
  const double ux = (toe.x() - heel.x()) / length, uy = (toe.y() - heel.y()) / length;
  const double hx = heel.x() + dx, hy = heel.y() + dy;
  const double heelZ = terrain.height(hx, hy);
  const double rise = (terrain.height(toe.x() + dx, toe.y() + dy) - heelZ) / length;
  const int along = static_cast<int>(std::ceil((length + 2.0 * s.patch) / s.step));
  const int across = std::max(1, static_cast<int>(std::ceil(s.patch / s.step)));
  for (int i = 0; i <= along; ++i) {
    const double a = -s.patch + (length + 2.0 * s.patch) * i / along;  // from the heel, along
    const double line = heelZ + rise * a;
    const bool nearPoint = a <= s.patch || a >= length - s.patch;
    for (int j = -across; j <= across; ++j) {
      const double b = s.patch * j / across;  // to the left of the line
      const double x = hx + a * ux - b * uy, y = hy + a * uy + b * ux;
      const double h = terrain.height(x, y);
      if (h > line + s.supportTolerance || (nearPoint && h < line - s.supportTolerance))
        return false;
    }
  }
  return true;
}

/// Half width of the window searched for a foot from toe to heel: `radius`, or, where that is
/// more, what moving the foot off an edge under its middle takes (half its length and the patch
/// ahead of its toe, and one step more for an edge between the grid's placements). With 12 cm
/// and a 20 cm foot, a foot whose toe was 5 cm over a 5 cm stage found no placement (the column
/// before the edge read as the stage in the live map) and kept the paper's foothold across it.
inline double searchRadius(const Eigen::Vector3d& toe, const Eigen::Vector3d& heel,
                           const FootholdSearchParameters& s) {
  const double length = std::hypot(toe.x() - heel.x(), toe.y() - heel.y());
  return std::max(s.radius, 0.5 * length + s.patch + s.step);
}

/// The offset (x, y, 0) to add to both points of a foot whose paper's footholds are toe and
/// heel; zero where those are good, or where nothing in the window is.
inline Eigen::Vector3d footholdOffset(const Eigen::Vector3d& toe, const Eigen::Vector3d& heel,
                                      const TerrainQuery& terrain,
                                      const FootholdSearchParameters& s) {
  if (!s.enabled) return Eigen::Vector3d::Zero();
  const bool good = goodPlacement(toe, heel, 0.0, 0.0, terrain, s);
  if (good && supported(toe, heel, 0.0, 0.0, terrain, s)) return Eigen::Vector3d::Zero();
  const double radius = searchRadius(toe, heel, s);
  const int n = static_cast<int>(std::floor(radius / s.step + 1e-9));
  // The nearest good placement that is also supported; else, the paper's foothold if it is
  // good, else the nearest good one (on a ramp's stairs a sole never rests on its two ends).
  const double length = std::hypot(toe.x() - heel.x(), toe.y() - heel.y());
  const double ux = length > 1e-9 ? (toe.x() - heel.x()) / length : 1.0;
  const double uy = length > 1e-9 ? (toe.y() - heel.y()) / length : 0.0;
  double best = INFINITY, bestGood = INFINITY;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero(), offsetGood = Eigen::Vector3d::Zero();
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j) {
      const double dx = i * s.step, dy = j * s.step, d2 = dx * dx + dy * dy;
      if (d2 >= best || d2 > radius * radius + 1e-12) continue;
      if (!goodPlacement(toe, heel, dx, dy, terrain, s)) continue;
      if (d2 < bestGood) {
        bestGood = d2;
        offsetGood = Eigen::Vector3d(dx, dy, 0.0);
      }
      if (std::abs(dy * ux - dx * uy) > s.supportShiftAcross + 1e-9 ||
          !supported(toe, heel, dx, dy, terrain, s))
        continue;
      best = d2;
      offset = Eigen::Vector3d(dx, dy, 0.0);
    }
  if (best < INFINITY) return offset;
  return good ? Eigen::Vector3d::Zero() : offsetGood;
}

}  // namespace ballast::gait
