#include "terrain_maps.hpp"

#include <cmath>
#include <fstream>

namespace ballast::maps {
namespace {

bool endsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

/// A well-mixed 64-bit hash (splitmix64): patch heights that depend on the seed only.
std::uint64_t mix(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

}  // namespace

std::unique_ptr<octomap::OcTree> makeTerrainMap(const HeightFunction& height, double resolution,
                                                const MapExtent& extent) {
  auto tree = std::make_unique<octomap::OcTree>(resolution);
  const long nx = std::lround((extent.xMax - extent.xMin) / resolution);
  const long ny = std::lround((extent.yMax - extent.yMin) / resolution);
  const float occupied = tree->getClampingThresMaxLog();
  for (long iy = 0; iy < ny; ++iy)
    for (long ix = 0; ix < nx; ++ix) {
      const double x = extent.xMin + (static_cast<double>(ix) + 0.5) * resolution;
      const double y = extent.yMin + (static_cast<double>(iy) + 0.5) * resolution;
      const double h = std::max(0.0, height(x, y));
      // The floor cell (centre −res/2) and every cell whose centre is below h.
      for (long k = -1; (static_cast<double>(k) + 0.5) * resolution < h; ++k)
        tree->setNodeValue(
            octomap::point3d(static_cast<float>(x), static_cast<float>(y),
                             static_cast<float>((static_cast<double>(k) + 0.5) * resolution)),
            occupied, true);
    }
  tree->updateInnerOccupancy();
  tree->prune();
  return tree;
}

HeightFunction stage(double height, double start, double depth, double width) {
  return [=](double x, double y) {
    return x >= start && x < start + depth && std::abs(y) <= width / 2 ? height : 0.0;
  };
}

HeightFunction steps(int count, double rise, double run, double start, double width) {
  return [=](double x, double y) {
    if (x < start || std::abs(y) > width / 2) return 0.0;
    const int step = std::min(count, 1 + static_cast<int>(std::floor((x - start) / run)));
    return step * rise;
  };
}

HeightFunction rough(double amplitude, double patch, std::uint64_t seed) {
  return [=](double x, double y) {
    const auto px = static_cast<std::int64_t>(std::floor(x / patch));
    const auto py = static_cast<std::int64_t>(std::floor(y / patch));
    const std::uint64_t h = mix(seed ^ mix(static_cast<std::uint64_t>(px) * 0x100000001b3ULL ^
                                           static_cast<std::uint64_t>(py)));
    return amplitude * static_cast<double>(h >> 11) / static_cast<double>(1ULL << 53);
  };
}

bool writeTerrainMap(const octomap::OcTree& tree, const std::string& path, std::string& error) {
  bool ok;
  if (endsWith(path, ".bt")) {
    ok = tree.writeBinaryConst(path);
  } else if (endsWith(path, ".ot")) {
    ok = tree.write(path);
  } else {
    error = path + ": a map file ends in .bt (binary) or .ot (full)";
    return false;
  }
  if (!ok) error = path + ": cannot write the map";
  return ok;
}

}  // namespace ballast::maps
