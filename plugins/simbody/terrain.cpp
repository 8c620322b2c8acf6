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
  t.x0_ = x0;
  t.y0_ = y0;
  t.res_ = resolution;
  t.nx_ = nx;
  t.ny_ = ny;
  t.tops_ = std::move(tops);
  for (float h : t.tops_) t.maxColumnTop_ = std::max<double>(t.maxColumnTop_, h);
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
  const int ix = static_cast<int>(std::floor((x - x0_) / res_));
  const int iy = static_cast<int>(std::floor((y - y0_) / res_));
  if (ix >= 0 && ix < nx_ && iy >= 0 && iy < ny_) h = std::max<double>(h, top(ix, iy));
  return h;
}

double Terrain::columnDistance(const SimTK::Vec3& p, int ix, int iy, SimTK::Vec3& normal) const {
  const double lx = x0_ + ix * res_, ly = y0_ + iy * res_, h = top(ix, iy);
  // Vector from the closest point of the column to p.
  const SimTK::Vec3 q(p[0] < lx ? p[0] - lx : (p[0] > lx + res_ ? p[0] - lx - res_ : 0.0),
                      p[1] < ly ? p[1] - ly : (p[1] > ly + res_ ? p[1] - ly - res_ : 0.0),
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
  if (nx_ > 0 && p[2] - reach < maxColumnTop_) {
    const int ix0 = std::max(0, static_cast<int>(std::floor((p[0] - reach - x0_) / res_)));
    const int ix1 = std::min(nx_ - 1, static_cast<int>(std::floor((p[0] + reach - x0_) / res_)));
    const int iy0 = std::max(0, static_cast<int>(std::floor((p[1] - reach - y0_) / res_)));
    const int iy1 = std::min(ny_ - 1, static_cast<int>(std::floor((p[1] + reach - y0_) / res_)));
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
  double best = maxRange;
  bool hit = false;
  if (floor_ && direction[2] < 0) {
    const double tf = (floorHeight_ - origin[2]) / direction[2];
    if (tf >= 0 && tf <= best) best = tf, hit = true;
  }
  double tc;
  if (nx_ > 0 && castRayColumns(origin, direction, best, tc)) best = tc, hit = true;
  t = best;
  return hit;
}

bool Terrain::castRayColumns(const SimTK::Vec3& o, const SimTK::Vec3& d, double tMax,
                             double& t) const {
  double tIn = 0.0, tOut = tMax;
  // Nothing stands above the highest column top.
  if (o[2] > maxColumnTop_) {
    if (d[2] >= 0) return false;
    tIn = (maxColumnTop_ - o[2]) / d[2];
  }
  // Clip to the grid's footprint.
  const double lo[2] = {x0_, y0_}, hi[2] = {x0_ + nx_ * res_, y0_ + ny_ * res_};
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
  int ix = std::clamp(static_cast<int>(std::floor((px - x0_) / res_)), 0, nx_ - 1);
  int iy = std::clamp(static_cast<int>(std::floor((py - y0_) / res_)), 0, ny_ - 1);
  const int stepX = d[0] > 0 ? 1 : -1, stepY = d[1] > 0 ? 1 : -1;
  const double inf = SimTK::Infinity;
  const double dtX = d[0] != 0.0 ? res_ / std::abs(d[0]) : inf;
  const double dtY = d[1] != 0.0 ? res_ / std::abs(d[1]) : inf;
  double nextX = d[0] != 0.0 ? (x0_ + (ix + (stepX > 0 ? 1 : 0)) * res_ - o[0]) / d[0] : inf;
  double nextY = d[1] != 0.0 ? (y0_ + (iy + (stepY > 0 ? 1 : 0)) * res_ - o[1]) / d[1] : inf;
  double tEnter = tIn;
  for (;;) {
    const double tExit = std::min({nextX, nextY, tOut});
    const double h = top(ix, iy);
    if (h != kNoColumn) {
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
    if (ix < 0 || ix >= nx_ || iy < 0 || iy >= ny_) return false;
  }
}

}  // namespace ballast::simbody
