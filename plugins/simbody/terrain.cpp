#include "terrain.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "terrain_columns.hpp"  // plugins/common

namespace ballast::simbody {
namespace {

constexpr float kNoColumn = -std::numeric_limits<float>::infinity();

}  // namespace

Terrain Terrain::flat(double floorHeight) {
  Terrain t;
  t.floor_ = true;
  t.floorHeight_ = floorHeight;
  t.maxTop_ = floorHeight;
  return t;
}

Terrain Terrain::fromHeights(double x0, double y0, double resolution, int nx, int ny,
                             std::vector<float> tops, bool floor, double floorHeight) {
  if (!(resolution > 0) || nx < 0 || ny < 0 ||
      tops.size() != static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny))
    throw std::runtime_error("terrain columns: inconsistent grid");
  Terrain t;
  t.floor_ = floor;
  t.floorHeight_ = floorHeight;
  t.grid_.x0 = x0;
  t.grid_.y0 = y0;
  t.grid_.resolution = resolution;
  t.grid_.nx = nx;
  t.grid_.ny = ny;
  t.grid_.tops = std::move(tops);
  if (!t.grid_.empty()) t.maxColumnTop_ = t.grid_.highest();
  t.maxTop_ = std::max(t.maxColumnTop_, floor ? floorHeight : -SimTK::Infinity);
  return t;
}

Terrain Terrain::fromOctomap(const std::string& path, bool floor, double floorHeight,
                             double overhangHeight) {
  plugin::TerrainColumns columns = plugin::loadTerrainColumns(path, floorHeight, overhangHeight);
  if (columns.empty()) {
    if (!floor)
      throw std::runtime_error(path + ": the map has no occupied cells and the floor is off: "
                                      "there is no terrain");
    return fromHeights(0, 0, columns.resolution, 0, 0, {}, floor, floorHeight);
  }
  return fromHeights(columns.x0, columns.y0, columns.resolution, columns.nx, columns.ny,
                     std::move(columns.tops), floor, floorHeight);
}

double Terrain::heightAt(double x, double y) const {
  double h = floor_ ? floorHeight_ : -SimTK::Infinity;
  const int ix = static_cast<int>(std::floor((x - grid_.x0) / grid_.resolution));
  const int iy = static_cast<int>(std::floor((y - grid_.y0) / grid_.resolution));
  if (ix >= 0 && ix < grid_.nx && iy >= 0 && iy < grid_.ny) h = std::max<double>(h, top(ix, iy));
  return h;
}

double Terrain::columnDistance(const SimTK::Vec3& p, int ix, int iy, SimTK::Vec3& normal) const {
  const double lx = grid_.x0 + ix * grid_.resolution, ly = grid_.y0 + iy * grid_.resolution, h = top(ix, iy);
  // Vector from the closest point of the column to p.
  const SimTK::Vec3 q(p[0] < lx ? p[0] - lx : (p[0] > lx + grid_.resolution ? p[0] - lx - grid_.resolution : 0.0),
                      p[1] < ly ? p[1] - ly : (p[1] > ly + grid_.resolution ? p[1] - ly - grid_.resolution : 0.0),
                      p[2] > h ? p[2] - h : 0.0);
  const double d = q.norm();
  if (d == 0.0) {  // inside: out through the top (columns stand side by side)
    normal = SimTK::Vec3(0, 0, 1);
    return p[2] - h;
  }
  normal = q / d;
  return d;
}

bool Terrain::signedDistance(const SimTK::Vec3& p, double reach, double& distance,
                             SimTK::Vec3& normal) const {
  double best = reach;
  bool found = false;
  if (floor_ && p[2] - floorHeight_ < best) {
    best = p[2] - floorHeight_;
    normal = SimTK::Vec3(0, 0, 1);
    found = true;
  }
  if (grid_.nx > 0 && p[2] - reach < maxColumnTop_) {
    const int ix0 = std::max(0, static_cast<int>(std::floor((p[0] - reach - grid_.x0) / grid_.resolution)));
    const int ix1 = std::min(grid_.nx - 1, static_cast<int>(std::floor((p[0] + reach - grid_.x0) / grid_.resolution)));
    const int iy0 = std::max(0, static_cast<int>(std::floor((p[1] - reach - grid_.y0) / grid_.resolution)));
    const int iy1 = std::min(grid_.ny - 1, static_cast<int>(std::floor((p[1] + reach - grid_.y0) / grid_.resolution)));
    SimTK::Vec3 n;
    for (int iy = iy0; iy <= iy1; ++iy)
      for (int ix = ix0; ix <= ix1; ++ix) {
        if (top(ix, iy) == kNoColumn) continue;
        const double d = columnDistance(p, ix, iy, n);
        if (d < best) {
          best = d;
          normal = n;
          found = true;
        }
      }
  }
  distance = best;
  return found;
}

bool Terrain::castRay(const SimTK::Vec3& origin, const SimTK::Vec3& direction, double maxRange,
                      double& t) const {
  return plugin::castRayOnTerrain(grid_, maxColumnTop_, floor_, floorHeight_, &origin[0],
                                  &direction[0], maxRange, t);
}

}  // namespace ballast::simbody
