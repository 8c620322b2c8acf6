// The terrain map the daemon holds for the planner: `ballast map load FILE` and `map info`.
// Loads OctoMap files (.bt binary, .ot full; daemon/terrain reads them), describes them, and
// builds the planner's height grid (terrain::HeightMap) from the same tree, here on the IO
// thread, so the server hands the planner a finished map (MpcPlanner::setTerrain). A file that
// is missing, of another kind, corrupt or empty is refused with its name and the reason, and
// the map in use stays. Ground is what a foot can stand on (terrain::GroundRule): occupied
// cells more than the clearance above the floor's height (terrain.ground_height) — a ceiling,
// a table — are not.
#pragma once

#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "terrain/height_map.hpp"

namespace octomap {
class OcTree;
}

namespace ballast::server {

class TerrainMap {
 public:
  /// The flat floor at `ground` (terrain.ground_height).
  explicit TerrainMap(double ground = 0.0);
  ~TerrainMap();
  TerrainMap(TerrainMap&&) noexcept;
  TerrainMap& operator=(TerrainMap&&) noexcept;
  /// Loads path, with `ground` where the map knows nothing; on failure returns false with a
  /// message and keeps the current map.
  bool load(const std::string& path, double ground, std::string& error);
  bool loaded() const { return tree_ != nullptr; }
  /// The map's tree (loaded() only): what the live map is seeded with.
  const octomap::OcTree& tree() const { return *tree_; }
  /// The path of the map in use, "" for the flat floor.
  const std::string& path() const { return path_; }
  /// The height grid for the planner (never null; flat at the ground without a map).
  std::shared_ptr<const terrain::HeightMap> heights() const { return heights_; }
  /// {"path", "resolution", "leaves", "min": [x,y,z], "max": [x,y,z], "heights": {"columns":
  /// [nx, ny], "known", "ground", "clearance"}}, or null without a map.
  nlohmann::json info() const;

 private:
  std::shared_ptr<octomap::OcTree> tree_;
  std::shared_ptr<const terrain::HeightMap> heights_;
  std::string path_;
};

}  // namespace ballast::server
