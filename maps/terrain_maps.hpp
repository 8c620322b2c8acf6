// Terrain maps for the simulation and the planner: OctoMap occupancy trees of a floor with
// stages, steps or rough patches, built from a height function. Used by ballast-mkmap (the
// example maps in this directory) and by tests that need a map.
//
// A map covers [x_min, x_max] × [y_min, y_max] at `resolution`. Every column is occupied from the
// floor cell (top at z = 0) up to the terrain height there, rounded to whole cells (a cell is
// occupied when its centre is below the height): a 10 cm stage in a 2 cm map is 5 cells above the
// floor cell, with its top face at exactly 0.10. Free space is left unknown (the simulation and
// the planner read occupied cells only). Heights are in metres, world frame, z up.
#pragma once

#include <octomap/OcTree.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace ballast::maps {

struct MapExtent {
  double xMin = -2.0, xMax = 4.0, yMin = -2.0, yMax = 2.0;
};

/// Height of the terrain (>= 0) at (x, y).
using HeightFunction = std::function<double(double x, double y)>;

/// The occupancy tree of that terrain.
std::unique_ptr<octomap::OcTree> makeTerrainMap(const HeightFunction& height, double resolution,
                                                const MapExtent& extent);

/// A stage: a block `height` high from x = start to start + depth, across |y| <= width / 2.
HeightFunction stage(double height, double start, double depth, double width);
/// A staircase up: `count` steps of `rise` and `run` from x = start, across |y| <= width / 2;
/// the top step extends to x = +infinity (a landing).
HeightFunction steps(int count, double rise, double run, double start, double width);
/// Rough ground: square patches of side `patch`, each at a height uniform in [0, amplitude]
/// drawn from `seed` (the same seed gives the same map).
HeightFunction rough(double amplitude, double patch, std::uint64_t seed);

/// Writes .bt (binary, writeBinaryConst) or .ot (full, with log-odds) by the file's extension.
/// Returns false with a message naming the file.
bool writeTerrainMap(const octomap::OcTree& tree, const std::string& path, std::string& error);

}  // namespace ballast::maps
