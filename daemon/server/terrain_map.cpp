#include "server/terrain_map.hpp"

#include <octomap/OcTree.h>

#include "control/terrain_mapper.hpp"
#include "terrain/octree_file.hpp"

namespace ballast::server {

TerrainMap::TerrainMap(double ground) : ground_(ground) {}
TerrainMap::~TerrainMap() = default;
TerrainMap::TerrainMap(TerrainMap&&) noexcept = default;
TerrainMap& TerrainMap::operator=(TerrainMap&&) noexcept = default;

bool TerrainMap::load(const std::string& path, double ground, const terrain::GroundRule& rule,
                      std::string& error) {
  std::shared_ptr<octomap::OcTree> tree;
  try {
    tree = terrain::readOcTree(path);
    terrain::HeightMap::check(*tree, path, rule);
  } catch (const terrain::MapError& e) {
    error = e.what();
    return false;
  }
  tree_ = std::move(tree);
  path_ = path;
  ground_ = ground;
  return true;
}

void TerrainMap::handTo(control::TerrainMapper& mapper) const {
  if (tree_)
    mapper.seed(*tree_, path_, ground_);
  else
    mapper.clear(ground_, true);
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
          {"max", {x1, y1, z1}}};
}

}  // namespace ballast::server
