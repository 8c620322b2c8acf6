// The simulated terrain: an OctoMap map turned into a height field of solid columns
// (plugins/common/terrain_columns.hpp, as the mujoco backend does too), plus an optional infinite
// floor plane. World frame, z up, metres.
//
// A 10 cm stage in a 2 cm map is a block with vertical sides and sharp edges: a foot can stand
// on it and catch its edge. Queries are exact for this geometry:
//   - signedDistance(): distance from a point to the union of the columns and the floor, with
//     the outward surface normal (a point beside a stage sees the side face or the edge);
//   - castRay(): the first hit along a ray (simulated lidar);
//   - heightAt(): the top of the terrain at (x, y).
// None of them allocates.
#pragma once

#include <Simbody.h>

#include <string>
#include <vector>

#include "terrain_columns.hpp"  // plugins/common

namespace ballast::simbody {

class Terrain {
 public:
  /// A floor at floorHeight only.
  static Terrain flat(double floorHeight);
  /// The map in path (.bt or .ot), with or without a floor. Throws std::runtime_error naming
  /// the file and what is wrong.
  static Terrain fromOctomap(const std::string& path, bool floor, double floorHeight,
                             double overhangHeight);
  /// Columns given directly: tops[ix + nx * iy] (−infinity for none) over cells of size
  /// resolution whose grid starts at (x0, y0). For tests and tools.
  static Terrain fromHeights(double x0, double y0, double resolution, int nx, int ny,
                             std::vector<float> tops, bool floor, double floorHeight);

  /// Signed distance from p to the terrain surface (negative inside) and the outward normal
  /// there, considering only surface within `reach` of p (farther: returns false).
  bool signedDistance(const SimTK::Vec3& p, double reach, double& distance,
                      SimTK::Vec3& normal) const;
  /// First hit of origin + t·direction (direction unit) for t in [0, maxRange].
  bool castRay(const SimTK::Vec3& origin, const SimTK::Vec3& direction, double maxRange,
               double& t) const;
  /// Top of the terrain at (x, y); −infinity where there is none.
  double heightAt(double x, double y) const;
  /// Highest point of the terrain (−infinity if empty).
  double maxHeight() const { return maxTop_; }
  double resolution() const { return grid_.resolution; }
  bool hasFloor() const { return floor_; }
  int columns() const { return grid_.nx * grid_.ny; }

 private:
  float top(int ix, int iy) const { return grid_.top(ix, iy); }
  /// Distance from p to column (ix, iy) (negative inside, measured to its top).
  double columnDistance(const SimTK::Vec3& p, int ix, int iy, SimTK::Vec3& normal) const;

  bool floor_ = true;
  double floorHeight_ = 0.0;
  plugin::TerrainColumns grid_;
  double maxTop_ = -SimTK::Infinity;
  double maxColumnTop_ = -SimTK::Infinity;
};

}  // namespace ballast::simbody
