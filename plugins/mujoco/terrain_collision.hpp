// The map's terrain boxes in MuJoCo's collision detection, found through the columns' grid.
//
// MuJoCo 2.2.2 tests every geom of the world body against every geom of every body that may
// collide, each step, and moves every geom each step: a building's map as boxes in the world
// body (thousands) cost 2.3 ms a step standing, against 0.03 ms on flat ground, and
// acceptance.map.building.mujoco took minutes. So the boxes (mjcf_model.hpp: the columns, equal
// neighbours merged) are not geoms. One height field geom stands for them, the proxy: MuJoCo
// pairs it with each robot geom, and the collision function installed here for height fields
// (mjCOLLISIONFUNC, MuJoCo's documented way to replace a narrow phase) collides that geom with
// the boxes whose columns lie under its bounding sphere: each box in turn is given to a probe,
// a box geom of the world body that collides with nothing by itself, and MuJoCo's own function
// for the robot geom's shape and a box gives the contacts. They are those the boxes as geoms
// gave (the same function on the same box), reported between the proxy and the robot geom,
// normal from the terrain to the robot.
//
// The grid travels in the model, as two height fields whose data are numbers, not elevations
// (only the function here reads them; a renderer or mj_ray would see nonsense, and the lidar
// casts on the columns themselves):
//   - kTerrainIndex, the proxy's: ncol × nrow = the columns' nx × ny over the proxy's x and y
//     extent (the grid's corner is its pos − size; its pos z is the boxes' common bottom, pos z
//     + size[2] the highest top); per column (ix + nx·iy) the number of its box, −1 for none
//     (a floor-level column is the floor's);
//   - kTerrainBoxes: a row per box, the columns it covers (ix0, iy0, ix1, iy1, the ends
//     excluded) and its top (world z, m).
// The probe is the geom after the proxy; it is the only geom of the model the function moves
// and resizes. A height field by another name collides as MuJoCo's own.
#pragma once

#include <mujoco/mujoco.h>

#include <vector>

#include "terrain_columns.hpp"  // plugins/common

namespace ballast::mujoco {

inline constexpr const char* kTerrainIndex = "terrain_index";  ///< the proxy's height field
inline constexpr const char* kTerrainBoxes = "terrain_boxes";  ///< the boxes' height field

/// Installs the height field collision functions (once per process; later calls do nothing).
void installTerrainCollision();

/// Fills the compiled model's kTerrainIndex and kTerrainBoxes from the columns and
/// `boxOfColumn` (per column, ix + nx·iy, the number of its box in the order terrainBoxes()
/// gives, −1 for none).
void writeTerrainIndex(mjModel* m, const plugin::TerrainColumns& columns,
                       const std::vector<int>& boxOfColumn);

}  // namespace ballast::mujoco
