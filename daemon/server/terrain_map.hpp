// The terrain map file the daemon holds: `ballast map load FILE`, terrain.map, and the `map`
// of `map info` and status. Loads OctoMap files (.bt binary, .ot full; daemon/terrain reads
// them) and checks, here on the IO thread, that a height grid can be made of them under the
// profile's ground rule, so a file that is missing, of another kind, corrupt, empty or too large
// is refused with its name and the reason before anything changes, and the map in use stays.
// The planner's height grid is built once, by the live map it seeds (control::TerrainMapper,
// handTo), with the live ground rule: what `map info` shows under "live".
#pragma once

#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "terrain/height_map.hpp"

namespace octomap {
class OcTree;
}
namespace ballast::control {
class TerrainMapper;
}

namespace ballast::server {

class TerrainMap {
 public:
  /// No file: the flat floor at `ground` (terrain.ground_height).
  explicit TerrainMap(double ground = 0.0);
  ~TerrainMap();
  TerrainMap(TerrainMap&&) noexcept;
  TerrainMap& operator=(TerrainMap&&) noexcept;
  /// Loads path, with `ground` where the map knows nothing, and checks it under `rule` (the
  /// profile's clearance); on failure returns false with a message and keeps the current map.
  bool load(const std::string& path, double ground, const terrain::GroundRule& rule,
            std::string& error);
  bool loaded() const { return tree_ != nullptr; }
  /// The map's tree (loaded() only).
  const octomap::OcTree& tree() const { return *tree_; }
  /// The path of the map in use, "" for the flat floor.
  const std::string& path() const { return path_; }
  double ground() const { return ground_; }
  /// Makes it the live map's: seeded with the file, or the flat floor known without one.
  /// Throws terrain::MapError as TerrainMapper::seed does.
  void handTo(control::TerrainMapper& mapper) const;
  /// {"path", "resolution", "leaves", "min": [x,y,z], "max": [x,y,z]}, or null without a map.
  nlohmann::json info() const;

 private:
  std::shared_ptr<octomap::OcTree> tree_;
  std::string path_;
  double ground_ = 0.0;
};

}  // namespace ballast::server
