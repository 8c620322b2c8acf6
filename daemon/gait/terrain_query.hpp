// What the gait needs to know about the ground: its height under a point, and whether it was
// observed there. The terrain module
// (OctoMap) provides the real one; control binds it here, since gait does not include terrain.
#pragma once

#include <algorithm>
#include <cmath>

namespace ballast::gait {

class TerrainQuery {
 public:
  virtual ~TerrainQuery() = default;
  /// Height (world z) of the terrain surface under (x, y).
  virtual double height(double x, double y) const = 0;
  /// Whether the ground under (x, y) was observed (a map's unknown columns answer false: their
  /// height is a default, not ground anyone saw). Without a map everything is known.
  virtual bool known(double /*x*/, double /*y*/) const { return true; }
  /// Highest terrain along the segment (x0, y0)–(x1, y1), sampled every `step` metres.
  virtual double maxHeightAlong(double x0, double y0, double x1, double y1,
                                double step = 0.02) const {
    const double dx = x1 - x0, dy = y1 - y0;
    const int n = std::max(1, static_cast<int>(std::hypot(dx, dy) / step));
    double z = height(x0, y0);
    for (int i = 1; i <= n; ++i) z = std::max(z, height(x0 + dx * i / n, y0 + dy * i / n));
    return z;
  }
};

class FlatTerrain final : public TerrainQuery {
 public:
  explicit FlatTerrain(double z = 0.0) : z_(z) {}
  double height(double, double) const override { return z_; }

 private:
  double z_;
};

}  // namespace ballast::gait
