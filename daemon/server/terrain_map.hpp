// The terrain map the daemon holds for the planner: `ballast map load FILE` and `map info`.
// Loads OctoMap files (.bt binary, .ot full) and describes them; the planner reads the map
// through daemon/terrain once that exists. A file that is missing, of another kind or corrupt
// is refused with its name and the reason, and the map in use stays.
#pragma once

#include <memory>
#include <string>

#include <nlohmann/json.hpp>

namespace octomap {
class OcTree;
}

namespace ballast::server {

class TerrainMap {
 public:
  TerrainMap();
  ~TerrainMap();
  TerrainMap(TerrainMap&&) noexcept;
  TerrainMap& operator=(TerrainMap&&) noexcept;
  /// Loads path; on failure returns false with a message and keeps the current map.
  bool load(const std::string& path, std::string& error);
  bool loaded() const { return tree_ != nullptr; }
  /// The path of the map in use, "" for the flat floor.
  const std::string& path() const { return path_; }
  /// Back to the flat floor.
  void clear() {
    tree_.reset();
    path_.clear();
  }
  /// {"path", "resolution", "leaves", "min": [x,y,z], "max": [x,y,z]}, or null without a map.
  nlohmann::json info() const;

 private:
  std::shared_ptr<octomap::OcTree> tree_;
  std::string path_;
};

}  // namespace ballast::server
