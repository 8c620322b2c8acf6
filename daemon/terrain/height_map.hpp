// The terrain as the planner sees it: a 2.5-D height grid made from an OctoMap occupancy tree,
// answering "how high is the ground under (x, y)" and "is it known" in O(1) without allocating.
//
// What it computes: the grid has the tree's resolution and is aligned with its cells (OctoMap
// cell n covers [n·res, (n+1)·res) on each axis). A column's height is the surface a foot could
// stand on: the top face of its highest occupied cell whose bottom is at most
// GroundRule::clearance above GroundRule::reference (the feet's height). Higher occupied cells —
// ceilings, table tops, overhangs — are not ground: a corridor's ceiling at 2.6 m leaves the
// floor under it at 0. A solid thing taller than the clearance (a wall, a high box) reads as
// rising to the clearance: an edge the footholds avoid, never a floor under it that nobody saw.
// Cells are counted at the tree's resolution; a pruned leaf covers all the cells inside it.
//
// Columns with no such occupied cell are unknown: nothing was observed there (or only free
// space). They read as the ground default (terrain.ground_height), as does everything off the
// map, and known(x, y) is false there: the footholds keep off them where they can. Unless the
// floor is known (floorKnown()): a profile without a map file says the world is a flat floor
// at the ground default (HeightMap(ground), and a live map grown from that), and there the
// columns nobody observed are that floor, known; what was observed reads as observed.
//
// One-column holes are filled: a column without ground whose neighbours on two opposite sides
// (left and right, front and back, or a diagonal pair) have ground, all its neighbours with
// ground agreeing within one cell's height, reads as the highest of them and is known. Why: a
// lidar's sweep leaves lines one column wide that no ray ended in between the lines it did
// (the simulated lidar walking at 1.2 m/s left such lines every few columns, and footholds
// searched off them moved by 2-8 cm on flat ground). A hole between observations
// that agree is the surface they lie on; it is never extrapolated past the observed area's
// edge (one side only), and a hole between different heights (an edge seen from both sides)
// stays unknown. A pit one column wide reads as the floor around it: 4 cm, less than a foot.
//
// Queries are nearest-cell, not interpolated: height(x, y) is the value of the column whose
// cell contains (x, y). A step stays a step, its edge where the map has it (within one cell),
// and a foothold is never placed on a ramp that blurring would invent between two levels.
// slope(x, y) is the central difference over the two neighbouring columns on each axis: the
// plane's gradient on smooth ground, rise / (2·res) across a step edge (an edge detector as much
// as a slope).
//
// Frame: world, z up; metres. Building from a tree allocates and walks the whole tree
// (milliseconds for a lab map): do it off the control and planner threads and hand the result
// over (control binds it for the planner). A HeightMap handed to the planner is immutable; share
// it as shared_ptr<const HeightMap>. LiveMap (live_map.hpp) keeps a mutable one and updates the
// columns a scan changed.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
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

/// Which occupied cells are ground: those whose bottom is at most `clearance` above
/// `reference` (world z, m). The reference is where the feet are; the clearance is more than
/// any step the robot takes and less than anything it could walk under (a table, 0.7 m).
struct GroundRule {
  double reference = 0.0;  ///< m, world z
  double clearance = 0.5;  ///< m
  double limit() const { return reference + clearance; }
};

class HeightMap {
 public:
  /// Grids larger than this many columns are refused: 4 M columns (32 MB of heights) is a
  /// 160 m × 160 m building at 8 cm, 80 m × 80 m at 4 cm.
  static constexpr std::size_t kMaxColumns = std::size_t{1} << 22;

  /// A flat floor at `ground` everywhere (no map), known (floorKnown()).
  explicit HeightMap(double ground = 0.0);
  /// The grid of `tree` under `rule`. Throws MapError when the tree has no occupied cell, when
  /// its resolution is not a usable cell size, or when it would make a grid of more than
  /// kMaxColumns columns; the message names `path` (the tree's file) if given.
  static HeightMap fromOcTree(const octomap::OcTree& tree, double ground,
                              const std::string& path = "", const GroundRule& rule = {});
  /// Throws MapError where fromOcTree would, without building the grid: one pass over the
  /// leaves, for a file that must be known usable before it is handed on.
  static void check(const octomap::OcTree& tree, const std::string& path, const GroundRule& rule);
  /// readOcTree(path) then fromOcTree; every MapError names the file ("map <path>: ...").
  static HeightMap fromFile(const std::string& path, double ground, const GroundRule& rule = {});

  /// Height (world z, m) of the terrain under (x, y); the ground default off the map and in
  /// unknown columns.
  double height(double x, double y) const {
    const std::size_t i = index(x, y);
    if (i == kOff) return ground_;
    if (known_[i]) return cells_[i];
    double h;
    return filled(i, h) ? h : ground_;
  }
  /// Whether the ground under (x, y) is known: observed, a filled hole, or the known floor
  /// (see the header comment); otherwise false, off the map too.
  bool known(double x, double y) const {
    const std::size_t i = index(x, y);
    if (i == kOff) return floorKnown_;
    double h;
    return known_[i] != 0 || floorKnown_ || filled(i, h);
  }
  /// Gradient of the surface at (x, y) (see the header comment); 0 on a flat map.
  Slope slope(double x, double y) const;
  /// Unit surface normal (-dz/dx, -dz/dy, 1) / norm at (x, y).
  std::array<double, 3> normal(double x, double y) const;

  double ground() const { return ground_; }
  const GroundRule& rule() const { return rule_; }
  double resolution() const { return resolution_; }
  /// Columns along x and y (0 for a flat floor); the grid covers [xMin, xMin + nx·res) × ...
  std::size_t columnsX() const { return nx_; }
  std::size_t columnsY() const { return ny_; }
  double xMin() const { return xMin_; }
  double yMin() const { return yMin_; }
  /// Columns observed to have ground (the rest read as the ground default).
  std::size_t knownColumns() const { return knownCount_; }
  /// Whether what nobody observed is the floor at the ground default, known: a profile without
  /// a map file (a flat floor), not a file's map or a cleared live map.
  bool floorKnown() const { return floorKnown_; }

 private:
  friend class LiveMap;  // keeps a mutable grid and updates it column by column
  static constexpr std::size_t kOff = static_cast<std::size_t>(-1);
  std::size_t index(double x, double y) const {
    const double fx = (x - xMin_) * inverseResolution_, fy = (y - yMin_) * inverseResolution_;
    // Written so that NaN coordinates fall off the map too.
    if (!(fx >= 0.0 && fx < static_cast<double>(nx_) && fy >= 0.0 && fy < static_cast<double>(ny_)))
      return kOff;
    return static_cast<std::size_t>(fy) * nx_ + static_cast<std::size_t>(fx);
  }
  /// The columns of `tree`'s ground under `rule` ([x0, x1) × [y0, y1), empty when none), after
  /// the checks fromOcTree documents.
  struct Extent {
    long x0, y0, x1, y1;
  };
  static Extent groundExtent(const octomap::OcTree& tree, const std::string& path,
                             const GroundRule& rule);
  /// Column i (without ground) as a filled hole (see the header comment): its height in h.
  bool filled(std::size_t i, double& h) const;

  double ground_ = 0.0;
  GroundRule rule_;
  double resolution_ = 0.0, inverseResolution_ = 0.0;
  double xMin_ = 0.0, yMin_ = 0.0;
  std::size_t nx_ = 0, ny_ = 0, knownCount_ = 0;
  bool floorKnown_ = true;  // HeightMap(ground) only; fromOcTree and a cleared LiveMap: false
  std::vector<double> cells_;         // row-major: ny rows of nx columns
  std::vector<std::uint8_t> known_;   // the same layout: 1 where the column has ground
};

}  // namespace ballast::terrain
