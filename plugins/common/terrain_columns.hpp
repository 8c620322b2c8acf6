// An OctoMap terrain map (.bt/.ot) as solid columns: what the simulation backends (simbody,
// mujoco) make of the map the planner uses, so both simulate the same ground.
//
// Each map-resolution square of the map is a column, solid from its top down, so a 10 cm stage
// in a 2 cm map is a block with vertical sides and sharp edges. A column holds what stands on
// the ground: the square's occupied cells joined from the bottom up (a gap of one cell, where a
// lidar missed, is bridged) in runs, and of those the runs that start at most overhang_height
// above floor_height; its top is the highest of their tops. A run that starts higher hangs over
// the ground (a building's ceiling, a table top seen without its legs) and is not simulated:
// made solid down to the floor it would fill every room of an indoor lidar map to its ceiling.
// A wall, seen from the floor up, stays a wall.
#pragma once

#include <limits>
#include <string>
#include <vector>

namespace ballast::plugin {

struct TerrainColumns {
  static constexpr float kNone = -std::numeric_limits<float>::infinity();

  double x0 = 0.0, y0 = 0.0;  ///< corner of the grid (its lowest x and y), m
  double resolution = 1.0;    ///< column size, m
  int nx = 0, ny = 0;
  std::vector<float> tops;    ///< tops[ix + nx * iy], kNone where there is no column

  float top(int ix, int iy) const { return tops[static_cast<std::size_t>(ix + nx * iy)]; }
  bool empty() const { return nx == 0 || ny == 0; }
  /// The highest top (kNone when there is no column).
  float highest() const;
};

/// The first hit of origin + t·direction (direction a unit vector) on the columns, solid from
/// their tops down, for t in [0, tMax]: t and true, else false. `highest`: c.highest(), kept by
/// the caller (a ray above it meets nothing). Walks the columns under the ray (Amanatides-Woo),
/// so a ray costs the columns it crosses, not the map's size; allocates nothing.
bool castRayOnColumns(const TerrainColumns& c, double highest, const double origin[3],
                      const double direction[3], double tMax, double& t);
/// The same on the columns and, `floor`, the floor plane at floorHeight under them: the
/// simulated lidar's terrain in both backends.
bool castRayOnTerrain(const TerrainColumns& c, double highest, bool floor, double floorHeight,
                      const double origin[3], const double direction[3], double tMax, double& t);

/// Reads the map, keeping what stands on the ground at floorHeight (see the header comment).
/// Throws std::runtime_error naming the file and what is wrong (unreadable, not an OctoMap
/// OcTree, too large, or every occupied cell above floorHeight + overhangHeight). A map without
/// occupied cells gives empty columns.
TerrainColumns loadTerrainColumns(const std::string& path, double floorHeight,
                                  double overhangHeight);

/// A backend section's terrain_map as a path to open: as given when it is absolute or readable,
/// else beside the profile the section comes from (origin "file:line"). Throws
/// std::runtime_error starting with `where` (the key's location) when neither is readable.
std::string resolveTerrainMap(const std::string& map, const std::string& origin,
                              const std::string& where);

/// The terrain map a simulator loads: its section's terrain_map (resolveTerrainMap) when the
/// section gives one, else the profile's (profileMap, already resolved; null or "": none).
/// where: the section key's location for the map's messages ("" when it is the profile's).
template <typename Settings>
std::string terrainMapToLoad(const Settings& s, const char* profileMap, std::string& where) {
  if (s.terrain_map.empty()) {
    where.clear();
    return profileMap ? profileMap : "";
  }
  where = s.where("terrain_map");
  return resolveTerrainMap(s.terrain_map, s.origin, where);
}

}  // namespace ballast::plugin
