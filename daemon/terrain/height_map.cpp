#include "terrain/height_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <octomap/OcTree.h>

#include "terrain/octree_file.hpp"

namespace ballast::terrain {
namespace {

/// The columns an occupied leaf covers, in whole cells of the tree's resolution (index n is
/// [n·res, (n+1)·res)), and the z of its top face.
struct Footprint {
  long x0, x1, y0, y1;  // [x0, x1) × [y0, y1)
  double top;
};

Footprint footprint(const octomap::OcTree::leaf_iterator& it, double resolution) {
  const double half = 0.5 * it.getSize();
  const long cells = std::max(1L, std::lround(it.getSize() / resolution));
  const long x0 = std::lround((it.getX() - half) / resolution);
  const long y0 = std::lround((it.getY() - half) / resolution);
  return {x0, x0 + cells, y0, y0 + cells, it.getZ() + half};
}

}  // namespace

HeightMap::HeightMap(double ground) : ground_(ground) {}

HeightMap HeightMap::fromOcTree(const octomap::OcTree& tree, double ground,
                                const std::string& path) {
  const auto fail = [&](const std::string& why) {
    return MapError(path.empty() ? why : "map " + path + ": " + why);
  };
  const double res = tree.getResolution();
  long x0 = std::numeric_limits<long>::max(), y0 = x0;
  long x1 = std::numeric_limits<long>::min(), y1 = x1;
  std::size_t occupied = 0;
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    const Footprint f = footprint(it, res);
    x0 = std::min(x0, f.x0), x1 = std::max(x1, f.x1);
    y0 = std::min(y0, f.y0), y1 = std::max(y1, f.y1);
    ++occupied;
  }
  if (occupied == 0) throw fail("the map has no occupied cells");
  HeightMap map(ground);
  map.nx_ = static_cast<std::size_t>(x1 - x0);
  map.ny_ = static_cast<std::size_t>(y1 - y0);
  if (map.nx_ > kMaxColumns / map.ny_)
    throw fail("the map covers " + std::to_string(map.nx_) + " × " + std::to_string(map.ny_) +
               " cells: too large for a height grid (at most " + std::to_string(kMaxColumns) +
               " columns)");
  map.resolution_ = res;
  map.inverseResolution_ = 1.0 / res;
  map.xMin_ = static_cast<double>(x0) * res;
  map.yMin_ = static_cast<double>(y0) * res;
  constexpr double kUnknown = -std::numeric_limits<double>::infinity();
  map.cells_.assign(map.nx_ * map.ny_, kUnknown);
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    const Footprint f = footprint(it, res);
    for (long y = f.y0; y < f.y1; ++y) {
      double* row = map.cells_.data() + static_cast<std::size_t>(y - y0) * map.nx_;
      for (long x = f.x0; x < f.x1; ++x) {
        double& top = row[x - x0];
        top = std::max(top, f.top);
      }
    }
  }
  for (double& top : map.cells_) {
    if (top == kUnknown)
      top = ground;
    else
      ++map.known_;
  }
  return map;
}

HeightMap HeightMap::fromFile(const std::string& path, double ground) {
  return fromOcTree(*readOcTree(path), ground, path);
}

Slope HeightMap::slope(double x, double y) const {
  if (nx_ == 0) return {};
  const double d = resolution_;
  return {(height(x + d, y) - height(x - d, y)) / (2.0 * d),
          (height(x, y + d) - height(x, y - d)) / (2.0 * d)};
}

std::array<double, 3> HeightMap::normal(double x, double y) const {
  const Slope s = slope(x, y);
  const double n = std::sqrt(1.0 + s.dzdx * s.dzdx + s.dzdy * s.dzdy);
  return {-s.dzdx / n, -s.dzdy / n, 1.0 / n};
}

}  // namespace ballast::terrain
