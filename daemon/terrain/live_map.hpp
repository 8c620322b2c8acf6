// The terrain map the robot makes from its own lidar: an OctoMap occupancy tree that scans are
// inserted into with ray casting, and the planner's height grid (HeightMap) kept up to date
// column by column.
//
// insert(scan): the points, moved into the world by the given transform (the estimated pose of
// the frame they are in, at the scan's time), are cast as rays from the sensor's origin: the
// cell a ray ends in is observed occupied (log-odds probHit), the cells it crosses in its last
// clearDistance free (probMiss), both clamped to [clampMin, clampMax] so that a map keeps up
// with a world that changes. Clearing stops there because casting whole rays is what a scan
// costs (a 10 m ray is 250 cells at 4 cm; 2880 of them took 0.3 s per scan, three times the
// lidar's period), and what the ground needs cleared — something taken off the floor — lies
// just before the floor hits that now pass through it. Of the crossed cells, only those the
// tree holds (observed occupied once, or free but not yet at the clamp) are updated: clearing
// removes what was seen, it does not record space nothing was seen in. Creating a node for every
// unknown cell a ray crosses (and pruning the blocks that then agree) was 80 % of a scan's
// insertion (BM_LiveMapScan, CPU time 45-60 ms -> 9-10 ms at 4 cm), and the ground (the
// highest occupied cell) is the same either way. The crossed cells are looked up along each ray
// from the node the last lookup passed through, and gathered in flat sorted arrays rather than
// hash sets (9-10 ms -> 2 ms); the cost is that a cell first seen as a hit
// is not held down by earlier misses, so a spurious hit reads occupied until about three
// scans' rays cross it. Hits beyond maxRange are not inserted.
// The tree reports the cells whose occupancy changed (OctoMap change detection); only the
// columns of those within the searched heights are recomputed, by the rule
// HeightMap::fromOcTree has (GroundRule: the highest occupied cell whose bottom is within the
// clearance above the reference), searched from the limit down to `depth` below the
// reference. The grid grows to take columns off its edge.
//
// Hits are lowered by a quarter cell before insertion: a surface that lies on a cell boundary
// (a floor at z = 0 in a map aligned to it) is hit by rays whose rounding puts half of them in
// the cell above; lowered, they land in the cell below and the surface reads where it is, not
// a cell higher. A surface inside a cell reads as that cell's top: within one cell, as a file
// map's columns do.
//
// heights() copies the grid into an immutable HeightMap for the planner (a copy of the columns,
// not a rebuild from the tree: ~0.1 ms for 10 m × 10 m at 4 cm).
//
// Not thread-safe: one thread inserts (the daemon's mapping thread, never the control loop); the
// daemon serialises map save, clear and load with it. Frame: world, z up; metres.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "terrain/height_map.hpp"

#include <octomap/OcTreeKey.h>
#include <octomap/octomap_types.h>

namespace octomap {
class OcTree;
}  // namespace octomap

namespace ballast::terrain {

struct LiveMapSettings {
  double resolution = 0.04;  ///< m, cell size of the tree and the grid
  double maxRange = 6.0;     ///< m, hits farther from the sensor are not inserted
  double clearDistance = 1.0;  ///< m, the part of a ray before its hit that is cleared
  double probHit = 0.7, probMiss = 0.4;     ///< OctoMap sensor model
  double clampMin = 0.12, clampMax = 0.97;  ///< OctoMap clamping thresholds
  double depth = 2.0;        ///< m below the reference searched for ground in a column
  double ground = 0.0;       ///< what unknown columns read (terrain.ground_height)
  GroundRule rule;
};

/// A rigid transform, world <- points: p_world = R p + t, R row-major.
struct ScanPose {
  std::array<double, 9> R{1, 0, 0, 0, 1, 0, 0, 0, 1};
  std::array<double, 3> t{0, 0, 0};
};

/// What one insert() did.
struct ScanUpdate {
  int points = 0;               ///< hits inserted (within maxRange)
  std::size_t changedCells = 0;    ///< cells whose occupancy changed or that were new
  std::size_t changedColumns = 0;  ///< grid columns recomputed
  double insertSeconds = 0.0;   ///< ray casting and the tree's update
  double gridSeconds = 0.0;     ///< the columns' recomputation
};

class LiveMap {
 public:
  /// Throws MapError for settings OctoMap cannot use (a resolution outside [1 mm, 1 m],
  /// probabilities outside (0, 1) or on the wrong side of 0.5, clampMin >= clampMax).
  explicit LiveMap(const LiveMapSettings& settings);
  ~LiveMap();
  LiveMap(const LiveMap&) = delete;
  LiveMap& operator=(const LiveMap&) = delete;

  /// Inserts `count` points (xyz, 3 floats each, in the frame `pose` places in the world),
  /// observed from `origin` (world), and updates the grid's columns they changed.
  ScanUpdate insert(const float* xyz, int count, const ScanPose& pose,
                    const std::array<double, 3>& origin);
  /// Replaces the map with a copy of `tree` (`ballast map load`): its cells, and its resolution
  /// from then on, and `ground` the ground default (terrain.ground_height, which a profile
  /// switch may change); the grid is rebuilt. Throws MapError as HeightMap::fromOcTree does,
  /// leaving the map as it was.
  void seed(const octomap::OcTree& tree, double ground, const std::string& path = "");
  /// Forgets everything (`ballast map clear`): the tree back at settings().resolution, `ground`
  /// the ground default, and every column unknown; or, `floor`, the floor at the ground default
  /// known where no scan finds ground (a profile without a map file, whose floor is flat:
  /// HeightMap::floorKnown). A new LiveMap knows nothing.
  void clear(double ground, bool floor = false);
  /// Moves the ground rule's reference (the feet's height). The grid is rebuilt from the tree
  /// when it moved by more than a quarter of the clearance since the last build; true if so.
  bool setReference(double z);
  /// Writes the tree as an OctoMap binary file (.bt); false with a message naming the file.
  bool save(const std::string& path, std::string& error) const;

  /// A copy of the grid as it is now, for the planner.
  std::shared_ptr<const HeightMap> heights() const;
  const HeightMap& grid() const { return grid_; }
  const octomap::OcTree& tree() const { return *tree_; }
  const LiveMapSettings& settings() const { return settings_; }

 private:
  void configureTree(octomap::OcTree& tree) const;
  void rebuild();
  /// Makes the grid cover column indices [x0, x1) × [y0, y1); false if it would be too large.
  bool cover(long x0, long x1, long y0, long y1);
  void updateColumn(long ix, long iy);

  LiveMapSettings settings_;
  std::unique_ptr<octomap::OcTree> tree_;
  octomap::KeyRay ray_;                          // scratch: one ray's cells
  // Scratch, kept to spare a scan allocations: its hits (world), the cells they end in and the
  // cells to clear (OcTreeKeys packed in one integer, sorted).
  std::vector<octomap::point3d> ends_;
  std::vector<std::uint64_t> occupied_, clear_;
  HeightMap grid_;
  double builtReference_ = 0.0;
  std::vector<std::array<long, 2>> columns_;  // scratch: the columns a scan changed
};

}  // namespace ballast::terrain
