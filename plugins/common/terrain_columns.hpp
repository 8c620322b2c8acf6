// An OctoMap terrain map (.bt/.ot) as solid columns: what the simulation backends (simbody,
// mujoco) make of the map the planner uses, so both simulate the same ground.
//
// Each occupied leaf of the map fills the columns (map-resolution squares) it covers up to its
// top face; a column is solid from its top down (overhangs become solid). So a 10 cm stage in a
// 2 cm map is a block with vertical sides and sharp edges.
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
};

/// Reads the map. Throws std::runtime_error naming the file and what is wrong (unreadable, not
/// an OctoMap OcTree, too large). A map without occupied cells gives empty columns.
TerrainColumns loadTerrainColumns(const std::string& path);

/// A backend section's terrain_map as a path to open: as given when it is absolute or readable,
/// else beside the profile the section comes from (origin "file:line"). Throws
/// std::runtime_error starting with `where` (the key's location) when neither is readable.
std::string resolveTerrainMap(const std::string& map, const std::string& origin,
                              const std::string& where);

}  // namespace ballast::plugin
