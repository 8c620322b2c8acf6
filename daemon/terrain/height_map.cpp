#include "terrain/height_map.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <limits>

#include <octomap/OcTree.h>

#include "terrain/octree_file.hpp"

namespace ballast::terrain {
namespace {

/// The columns an occupied leaf covers, in whole cells of the tree's resolution (index n is
/// [n·res, (n+1)·res)), and the z of the top face of its highest cell that is ground.
struct Footprint {
  long x0, x1, y0, y1;  // [x0, x1) × [y0, y1)
  double top;
  bool ground;  // some cell of it has its bottom within the rule's limit
};

Footprint footprint(const octomap::OcTree::leaf_iterator& it, double resolution,
                    const GroundRule& rule) {
  const double half = 0.5 * it.getSize();
  const long cells = std::max(1L, std::lround(it.getSize() / resolution));
  const long x0 = std::lround((it.getX() - half) / resolution);
  const long y0 = std::lround((it.getY() - half) / resolution);
  const double bottom = it.getZ() - half;
  // The leaf's cells from its bottom up; the highest one whose bottom is within the limit
  // (a small tolerance: a cell whose bottom is the limit itself, to rounding, counts).
  const double above = (rule.limit() - bottom) / resolution + 1e-6;
  Footprint f{x0, x0 + cells, y0, y0 + cells, 0.0, above >= 0.0};
  if (f.ground) f.top = bottom + resolution * static_cast<double>(std::min(cells - 1, static_cast<long>(above)) + 1);
  return f;
}

/// A length for people: "0.2", "0.05", not "0.200000".
std::string metresText(double m) {
  std::ostringstream out;
  out << std::setprecision(4) << m;
  return out.str();
}

}  // namespace

HeightMap::HeightMap(double ground) : ground_(ground) {}

HeightMap::Extent HeightMap::groundExtent(const octomap::OcTree& tree, const std::string& path,
                                          const GroundRule& rule) {
  const auto fail = [&](const std::string& why) {
    return MapError(path.empty() ? why : "map " + path + ": " + why);
  };
  const double res = tree.getResolution();
  if (!(res >= 1e-3 && res <= 1.0))
    throw fail("cells of " + metresText(res) + " m: a terrain map's cells are 1 mm to 1 m");
  Extent e{std::numeric_limits<long>::max(), std::numeric_limits<long>::max(),
           std::numeric_limits<long>::min(), std::numeric_limits<long>::min()};
  std::size_t occupied = 0;
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    ++occupied;
    const Footprint f = footprint(it, res, rule);
    if (!f.ground) continue;
    e.x0 = std::min(e.x0, f.x0), e.x1 = std::max(e.x1, f.x1);
    e.y0 = std::min(e.y0, f.y0), e.y1 = std::max(e.y1, f.y1);
  }
  if (occupied == 0) throw fail("the map has no occupied cells");
  if (e.x1 <= e.x0) return e;  // all of it above the clearance: no ground known anywhere
  const auto nx = static_cast<std::size_t>(e.x1 - e.x0), ny = static_cast<std::size_t>(e.y1 - e.y0);
  if (nx > kMaxColumns / ny) {
    const auto metres = [&](std::size_t n) {
      return std::to_string(static_cast<long>(std::lround(static_cast<double>(n) * res)));
    };
    throw fail("the map's ground covers " + metres(nx) + " m × " + metres(ny) + " m (" +
               std::to_string(nx) + " × " + std::to_string(ny) + " cells of " +
               metresText(res) + " m): too large for a height grid (at most " +
               std::to_string(kMaxColumns) + " columns)");
  }
  return e;
}

void HeightMap::check(const octomap::OcTree& tree, const std::string& path, const GroundRule& rule) {
  groundExtent(tree, path, rule);
}

HeightMap HeightMap::fromOcTree(const octomap::OcTree& tree, double ground, const std::string& path,
                                const GroundRule& rule) {
  const Extent e = groundExtent(tree, path, rule);
  const long x0 = e.x0, y0 = e.y0, x1 = e.x1, y1 = e.y1;
  const double res = tree.getResolution();
  HeightMap map(ground);
  map.rule_ = rule;
  map.floorKnown_ = false;  // a map: what it does not show is not known
  if (x1 <= x0) return map;
  map.nx_ = static_cast<std::size_t>(x1 - x0);
  map.ny_ = static_cast<std::size_t>(y1 - y0);
  map.resolution_ = res;
  map.inverseResolution_ = 1.0 / res;
  map.xMin_ = static_cast<double>(x0) * res;
  map.yMin_ = static_cast<double>(y0) * res;
  constexpr double kUnknown = -std::numeric_limits<double>::infinity();
  map.cells_.assign(map.nx_ * map.ny_, kUnknown);
  map.known_.assign(map.nx_ * map.ny_, 0);
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    const Footprint f = footprint(it, res, rule);
    if (!f.ground) continue;
    for (long y = f.y0; y < f.y1; ++y) {
      double* row = map.cells_.data() + static_cast<std::size_t>(y - y0) * map.nx_;
      for (long x = f.x0; x < f.x1; ++x) {
        double& top = row[x - x0];
        top = std::max(top, f.top);
      }
    }
  }
  for (std::size_t i = 0; i < map.cells_.size(); ++i) {
    if (map.cells_[i] == kUnknown) {
      map.cells_[i] = ground;
    } else {
      map.known_[i] = 1;
      ++map.knownCount_;
    }
  }
  return map;
}

HeightMap HeightMap::fromFile(const std::string& path, double ground, const GroundRule& rule) {
  return fromOcTree(*readOcTree(path), ground, path, rule);
}

bool HeightMap::filled(std::size_t i, double& h) const {
  const long x = static_cast<long>(i % nx_), y = static_cast<long>(i / nx_);
  const long nx = static_cast<long>(nx_), ny = static_cast<long>(ny_);
  // The eight neighbours, each opposite pair k and k + 4 (E W, NE SW, N S, NW SE).
  static constexpr int kDx[8] = {1, 1, 0, -1, -1, -1, 0, 1};
  static constexpr int kDy[8] = {0, 1, 1, 1, 0, -1, -1, -1};
  bool ground[8];
  double lo = INFINITY, hi = -INFINITY;
  for (int k = 0; k < 8; ++k) {
    const long u = x + kDx[k], v = y + kDy[k];
    ground[k] = u >= 0 && u < nx && v >= 0 && v < ny && known_[static_cast<std::size_t>(v * nx + u)];
    if (!ground[k]) continue;
    const double z = cells_[static_cast<std::size_t>(v * nx + u)];
    lo = std::min(lo, z), hi = std::max(hi, z);
  }
  const bool between = (ground[0] && ground[4]) || (ground[1] && ground[5]) ||
                       (ground[2] && ground[6]) || (ground[3] && ground[7]);
  // One cell's height: the grid's own resolution in z (a floor between two cells' tops).
  if (!between || hi - lo > resolution_ * (1.0 + 1e-6)) return false;
  h = hi;
  return true;
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
