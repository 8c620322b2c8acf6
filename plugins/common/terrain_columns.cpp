#include "terrain_columns.hpp"

#include <octomap/OcTree.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>
#include <stdexcept>

#include <unistd.h>

namespace ballast::plugin {
namespace {

constexpr long kMaxColumns = 16L * 1024 * 1024;  // 64 MB of heights: a 80 m square at 2 cm

bool endsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

std::unique_ptr<octomap::OcTree> readTree(const std::string& path) {
  if (!std::ifstream(path)) throw std::runtime_error(path + ": cannot read the terrain map");
  if (endsWith(path, ".bt")) {
    auto tree = std::make_unique<octomap::OcTree>(0.1);
    if (!tree->readBinary(path))
      throw std::runtime_error(path + ": not a binary OctoMap file (.bt)");
    return tree;
  }
  if (endsWith(path, ".ot")) {
    std::unique_ptr<octomap::AbstractOcTree> any(octomap::AbstractOcTree::read(path));
    if (!any) throw std::runtime_error(path + ": not an OctoMap file (.ot)");
    if (auto* tree = dynamic_cast<octomap::OcTree*>(any.get())) {
      any.release();
      return std::unique_ptr<octomap::OcTree>(tree);
    }
    throw std::runtime_error(path + ": holds a " + any->getTreeType() +
                             ", the simulation reads an OcTree");
  }
  throw std::runtime_error(path + ": a terrain map is an OctoMap file ending in .bt or .ot");
}

}  // namespace

TerrainColumns loadTerrainColumns(const std::string& path) {
  const std::unique_ptr<octomap::OcTree> tree = readTree(path);
  const double res = tree->getResolution();
  struct Leaf {
    double x, y, size, top;
  };
  std::vector<Leaf> leaves;
  constexpr double inf = std::numeric_limits<double>::infinity();
  double minX = inf, minY = inf, maxX = -inf, maxY = -inf;
  for (auto it = tree->begin_leafs(), end = tree->end_leafs(); it != end; ++it) {
    if (!tree->isNodeOccupied(*it)) continue;
    const double s = it.getSize();
    const Leaf leaf{it.getX() - s / 2, it.getY() - s / 2, s, it.getZ() + s / 2};
    minX = std::min(minX, leaf.x);
    minY = std::min(minY, leaf.y);
    maxX = std::max(maxX, leaf.x + s);
    maxY = std::max(maxY, leaf.y + s);
    leaves.push_back(leaf);
  }
  TerrainColumns columns;
  columns.resolution = res;
  if (leaves.empty()) return columns;
  const long nx = std::lround((maxX - minX) / res), ny = std::lround((maxY - minY) / res);
  if (nx * ny > kMaxColumns)
    throw std::runtime_error(path + ": the map covers " + std::to_string(nx) + " x " +
                             std::to_string(ny) + " columns, more than the simulation takes (" +
                             std::to_string(kMaxColumns) + ")");
  std::vector<float> tops(static_cast<std::size_t>(nx * ny), TerrainColumns::kNone);
  for (const Leaf& leaf : leaves) {
    const long ix0 = std::lround((leaf.x - minX) / res), iy0 = std::lround((leaf.y - minY) / res);
    const long n = std::max(1L, std::lround(leaf.size / res));
    for (long iy = iy0; iy < std::min(iy0 + n, ny); ++iy)
      for (long ix = ix0; ix < std::min(ix0 + n, nx); ++ix) {
        float& top = tops[static_cast<std::size_t>(ix + nx * iy)];
        top = std::max(top, static_cast<float>(leaf.top));
      }
  }
  columns.x0 = minX;
  columns.y0 = minY;
  columns.nx = static_cast<int>(nx);
  columns.ny = static_cast<int>(ny);
  columns.tops = std::move(tops);
  return columns;
}

std::string resolveTerrainMap(const std::string& map, const std::string& origin,
                              const std::string& where) {
  auto readable = [](const std::string& path) { return access(path.c_str(), R_OK) == 0; };
  if (map.empty() || map[0] == '/' || readable(map)) return map;
  const std::string profile = origin.substr(0, origin.rfind(':'));
  const auto slash = profile.rfind('/');
  const std::string dir = slash == std::string::npos ? "." : profile.substr(0, slash);
  const std::string beside = dir + "/" + map;
  if (readable(beside)) return beside;
  throw std::runtime_error(where + "cannot read " + map + " (nor " + beside + ")");
}

}  // namespace ballast::plugin
