#include "terrain_columns.hpp"

#include <octomap/OcTree.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
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

TerrainColumns loadTerrainColumns(const std::string& path, double floorHeight,
                                  double overhangHeight) {
  const std::unique_ptr<octomap::OcTree> tree = readTree(path);
  const double res = tree->getResolution();
  // Every occupied cell, as the square it stands on and its bottom and top.
  struct Cell {
    long ix, iy;
    float bottom, top;
  };
  std::vector<Cell> cells;
  long minX = std::numeric_limits<long>::max(), minY = minX;
  long maxX = std::numeric_limits<long>::min(), maxY = maxX;
  for (auto it = tree->begin_leafs(), end = tree->end_leafs(); it != end; ++it) {
    if (!tree->isNodeOccupied(*it)) continue;
    const double s = it.getSize();
    const long n = std::max(1L, std::lround(s / res));
    const long ix0 = std::lround((it.getX() - s / 2) / res), iy0 = std::lround((it.getY() - s / 2) / res);
    const auto bottom = static_cast<float>(it.getZ() - s / 2), top = static_cast<float>(it.getZ() + s / 2);
    for (long iy = iy0; iy < iy0 + n; ++iy)
      for (long ix = ix0; ix < ix0 + n; ++ix) cells.push_back({ix, iy, bottom, top});
    minX = std::min(minX, ix0), maxX = std::max(maxX, ix0 + n);
    minY = std::min(minY, iy0), maxY = std::max(maxY, iy0 + n);
  }
  TerrainColumns columns;
  columns.resolution = res;
  if (cells.empty()) return columns;
  const long nx = maxX - minX, ny = maxY - minY;
  if (nx * ny > kMaxColumns)
    throw std::runtime_error(path + ": the map covers " + std::to_string(nx) + " x " +
                             std::to_string(ny) + " columns, more than the simulation takes (" +
                             std::to_string(kMaxColumns) + ")");
  // Column by column, bottom up: runs of cells, and the tops of those that start low enough.
  std::sort(cells.begin(), cells.end(), [](const Cell& a, const Cell& b) {
    return a.iy != b.iy ? a.iy < b.iy : a.ix != b.ix ? a.ix < b.ix : a.bottom < b.bottom;
  });
  const float bridged = static_cast<float>(1.5 * res);  // a gap of one cell, with rounding
  const auto highestStart = static_cast<float>(floorHeight + overhangHeight);
  std::vector<float> tops(static_cast<std::size_t>(nx * ny), TerrainColumns::kNone);
  bool any = false;
  for (std::size_t i = 0; i < cells.size();) {
    const Cell& first = cells[i];
    float& top = tops[static_cast<std::size_t>((first.ix - minX) + nx * (first.iy - minY))];
    float runBottom = first.bottom, runTop = first.top;
    for (; i < cells.size() && cells[i].ix == first.ix && cells[i].iy == first.iy; ++i) {
      if (cells[i].bottom > runTop + bridged) {  // a gap of two cells or more: a new run
        if (runBottom <= highestStart) top = std::max(top, runTop);
        runBottom = cells[i].bottom;
      }
      runTop = std::max(runTop, cells[i].top);
    }
    if (runBottom <= highestStart) top = std::max(top, runTop);
    any = any || top != TerrainColumns::kNone;
  }
  if (!any) {
    // Occupied cells, yet every one starts above the overhangs' limit: the map's ground is not
    // where the floor is said to be, and none of it would be terrain.
    float lowest = std::numeric_limits<float>::max();
    for (const Cell& c : cells) lowest = std::min(lowest, c.bottom);
    char line[320];
    std::snprintf(line, sizeof(line),
                  ": every occupied cell starts more than overhang_height (%.3g m) above "
                  "floor_height (%.3g m), the lowest at z = %.3f m: nothing in the map would be "
                  "ground; set floor_height to the map's ground",
                  overhangHeight, floorHeight, static_cast<double>(lowest));
    throw std::runtime_error(path + line);
  }
  columns.x0 = static_cast<double>(minX) * res;
  columns.y0 = static_cast<double>(minY) * res;
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

float TerrainColumns::highest() const {
  float h = kNone;
  for (float top : tops) h = std::max(h, top);
  return h;
}

bool castRayOnColumns(const TerrainColumns& c, double highest, const double o[3],
                      const double d[3], double tMax, double& t) {
  if (c.empty()) return false;
  double tIn = 0.0, tOut = tMax;
  // Nothing stands above the highest column top.
  if (o[2] > highest) {
    if (d[2] >= 0) return false;
    tIn = (highest - o[2]) / d[2];
  }
  // Clip to the grid's footprint.
  const double lo[2] = {c.x0, c.y0}, hi[2] = {c.x0 + c.nx * c.resolution, c.y0 + c.ny * c.resolution};
  for (int a = 0; a < 2; ++a) {
    if (d[a] == 0.0) {
      if (o[a] < lo[a] || o[a] >= hi[a]) return false;
      continue;
    }
    double t0 = (lo[a] - o[a]) / d[a], t1 = (hi[a] - o[a]) / d[a];
    if (t0 > t1) std::swap(t0, t1);
    tIn = std::max(tIn, t0);
    tOut = std::min(tOut, t1);
  }
  if (tIn > tOut) return false;

  // Walk the columns under the ray (Amanatides-Woo).
  const double px = o[0] + tIn * d[0], py = o[1] + tIn * d[1];
  int ix = std::clamp(static_cast<int>(std::floor((px - c.x0) / c.resolution)), 0, c.nx - 1);
  int iy = std::clamp(static_cast<int>(std::floor((py - c.y0) / c.resolution)), 0, c.ny - 1);
  const int stepX = d[0] > 0 ? 1 : -1, stepY = d[1] > 0 ? 1 : -1;
  const double inf = std::numeric_limits<double>::infinity();
  const double dtX = d[0] != 0.0 ? c.resolution / std::abs(d[0]) : inf;
  const double dtY = d[1] != 0.0 ? c.resolution / std::abs(d[1]) : inf;
  double nextX = d[0] != 0.0 ? (c.x0 + (ix + (stepX > 0 ? 1 : 0)) * c.resolution - o[0]) / d[0] : inf;
  double nextY = d[1] != 0.0 ? (c.y0 + (iy + (stepY > 0 ? 1 : 0)) * c.resolution - o[1]) / d[1] : inf;
  double tEnter = tIn;
  for (;;) {
    const double tExit = std::min({nextX, nextY, tOut});
    const double h = c.top(ix, iy);
    if (h != TerrainColumns::kNone) {
      const double zEnter = o[2] + tEnter * d[2], zExit = o[2] + tExit * d[2];
      if (zEnter <= h) {  // through the side (or starting inside)
        t = tEnter;
        return true;
      }
      if (zExit <= h) {  // through the top
        t = (h - o[2]) / d[2];
        return true;
      }
    }
    if (tExit >= tOut) return false;
    if (nextX < nextY) {
      ix += stepX;
      tEnter = nextX;
      nextX += dtX;
    } else {
      iy += stepY;
      tEnter = nextY;
      nextY += dtY;
    }
    if (ix < 0 || ix >= c.nx || iy < 0 || iy >= c.ny) return false;
  }
}

bool castRayOnTerrain(const TerrainColumns& c, double highest, bool floor, double floorHeight,
                      const double origin[3], const double direction[3], double tMax, double& t) {
  double best = tMax;
  bool hit = false;
  if (floor && direction[2] < 0.0) {
    const double tf = (floorHeight - origin[2]) / direction[2];
    if (tf >= 0.0 && tf <= best) best = tf, hit = true;
  }
  double tc;
  if (castRayOnColumns(c, highest, origin, direction, best, tc)) best = tc, hit = true;
  t = best;
  return hit;
}

}  // namespace ballast::plugin
