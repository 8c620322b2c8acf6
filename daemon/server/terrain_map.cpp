#include "server/terrain_map.hpp"

#include <octomap/OcTree.h>

#include "terrain/octree_file.hpp"

namespace ballast::server {

TerrainMap::TerrainMap(double ground)
    : heights_(std::make_shared<const terrain::HeightMap>(ground)) {}
TerrainMap::~TerrainMap() = default;
TerrainMap::TerrainMap(TerrainMap&&) noexcept = default;
TerrainMap& TerrainMap::operator=(TerrainMap&&) noexcept = default;

bool TerrainMap::load(const std::string& path, double ground, std::string& error) {
  std::shared_ptr<octomap::OcTree> tree;
  std::shared_ptr<const terrain::HeightMap> heights;
  try {
    tree = terrain::readOcTree(path);
    heights = std::make_shared<const terrain::HeightMap>(
        terrain::HeightMap::fromOcTree(*tree, ground, path, terrain::GroundRule{ground}));
  } catch (const terrain::MapError& e) {
    error = e.what();
    return false;
  }
  tree_ = std::move(tree);
  heights_ = std::move(heights);
  path_ = path;
  return true;
}

nlohmann::json TerrainMap::info() const {
  if (!tree_) return nullptr;
  double x0, y0, z0, x1, y1, z1;
  tree_->getMetricMin(x0, y0, z0);
  tree_->getMetricMax(x1, y1, z1);
  return {{"path", path_},
          {"resolution", tree_->getResolution()},
          {"leaves", tree_->getNumLeafNodes()},
          {"min", {x0, y0, z0}},
          {"max", {x1, y1, z1}},
          {"heights",
           {{"columns", {heights_->columnsX(), heights_->columnsY()}},
            {"known", heights_->knownColumns()},
            {"ground", heights_->ground()},
            {"clearance", heights_->rule().clearance}}}};
}

}  // namespace ballast::server
