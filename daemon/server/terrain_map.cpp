#include "server/terrain_map.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>

#include <octomap/OcTree.h>

namespace ballast::server {

TerrainMap::TerrainMap() = default;
TerrainMap::~TerrainMap() = default;
TerrainMap::TerrainMap(TerrainMap&&) noexcept = default;
TerrainMap& TerrainMap::operator=(TerrainMap&&) noexcept = default;

bool TerrainMap::load(const std::string& path, std::string& error) {
  if (access(path.c_str(), R_OK) != 0) {
    error = "map " + path + ": cannot read it: " + std::strerror(errno);
    return false;
  }
  const auto dot = path.rfind('.');
  const std::string ext = dot == std::string::npos ? "" : path.substr(dot);
  std::shared_ptr<octomap::OcTree> tree;
  if (ext == ".bt") {
    std::ifstream in(path, std::ios::binary);
    // OcTree::readBinary checks the header and the node data and returns false on a bad file.
    tree = std::make_shared<octomap::OcTree>(0.1);
    if (!tree->readBinary(in)) {
      error = "map " + path + ": not a readable OctoMap binary (.bt) file";
      return false;
    }
  } else if (ext == ".ot") {
    std::unique_ptr<octomap::AbstractOcTree> any(octomap::AbstractOcTree::read(path));
    auto* oc = dynamic_cast<octomap::OcTree*>(any.get());
    if (!oc) {
      error = "map " + path + ": not an OctoMap OcTree (.ot) file";
      return false;
    }
    any.release();
    tree.reset(oc);
  } else {
    error = "map " + path + ": expected an OctoMap file (.bt or .ot)";
    return false;
  }
  tree_ = std::move(tree);
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
          {"max", {x1, y1, z1}}};
}

}  // namespace ballast::server
