// The terrain as the planner sees it: a 2.5-D height grid made once from an OctoMap occupancy
// tree, answering "how high is the ground under (x, y)" in O(1) without allocating.
//
// What it computes: the grid has the tree's resolution and is aligned with its cells (OctoMap
// cell n covers [n·res, (n+1)·res) on each axis). Each column holds the top face of its highest
// occupied cell (cell centre z + res/2; a pruned leaf covers all the columns under it). Columns
// with no occupied cell — unknown or free space, inside the map or off it — read as the ground
// default (terrain.ground_height): the floor the robot stands on when nothing says otherwise.
//
// Queries are nearest-cell, not interpolated: height(x, y) is the value of the column whose
// cell contains (x, y). A step stays a step, its edge where the map has it (within one cell),
// and a foothold is never placed on a ramp that blurring would invent between two levels.
// slope(x, y) is the central difference over the two neighbouring columns on each axis: the
// plane's gradient on smooth ground, rise / (2·res) across a step edge (an edge detector as much
// as a slope).
//
// Frame: world, z up; metres. Building allocates and walks the whole tree (milliseconds for a
// lab map): do it off the control and planner threads and hand the result over (control binds
// it for the planner). A built HeightMap is immutable; share it as shared_ptr<const HeightMap>.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace octomap {
class OcTree;
}

namespace ballast::terrain {

/// dz/dx and dz/dy of the terrain surface (dimensionless).
struct Slope {
  double dzdx = 0.0, dzdy = 0.0;
};

class HeightMap {
 public:
  /// Grids larger than this many columns are refused (8 m × 4 m at 2 cm is 80 000).
  static constexpr std::size_t kMaxColumns = std::size_t{1} << 26;

  /// A flat floor at `ground` everywhere (no map).
  explicit HeightMap(double ground = 0.0);
  /// The grid of `tree`. Throws MapError when the tree has no occupied cell or would make a
  /// grid of more than kMaxColumns columns; the message names `path` (the tree's file) if given.
  static HeightMap fromOcTree(const octomap::OcTree& tree, double ground,
                              const std::string& path = "");
  /// readOcTree(path) then fromOcTree; every MapError names the file ("map <path>: ...").
  static HeightMap fromFile(const std::string& path, double ground);

  /// Height (world z, m) of the terrain under (x, y); the ground default off the map.
  double height(double x, double y) const {
    const double fx = (x - xMin_) * inverseResolution_, fy = (y - yMin_) * inverseResolution_;
    // Written so that NaN coordinates fall off the map too.
    if (!(fx >= 0.0 && fx < static_cast<double>(nx_) && fy >= 0.0 && fy < static_cast<double>(ny_)))
      return ground_;
    return cells_[static_cast<std::size_t>(fy) * nx_ + static_cast<std::size_t>(fx)];
  }
  /// Gradient of the surface at (x, y) (see the header comment); 0 on a flat map.
  Slope slope(double x, double y) const;
  /// Unit surface normal (-dz/dx, -dz/dy, 1) / norm at (x, y).
  std::array<double, 3> normal(double x, double y) const;

  double ground() const { return ground_; }
  double resolution() const { return resolution_; }
  /// Columns along x and y (0 for a flat floor); the grid covers [xMin, xMin + nx·res) × ...
  std::size_t columnsX() const { return nx_; }
  std::size_t columnsY() const { return ny_; }
  double xMin() const { return xMin_; }
  double yMin() const { return yMin_; }
  /// Columns with an occupied cell (the rest read as the ground default).
  std::size_t knownColumns() const { return known_; }

 private:
  double ground_ = 0.0;
  double resolution_ = 0.0, inverseResolution_ = 0.0;
  double xMin_ = 0.0, yMin_ = 0.0;
  std::size_t nx_ = 0, ny_ = 0, known_ = 0;
  std::vector<double> cells_;  // row-major: ny rows of nx columns
};

}  // namespace ballast::terrain
