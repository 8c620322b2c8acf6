#include "terrain/octree_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>

#include <octomap/OcTree.h>

namespace ballast::terrain {

std::unique_ptr<octomap::OcTree> readOcTree(const std::string& path) {
  const auto fail = [&](const std::string& why) { return MapError("map " + path + ": " + why); };
  if (access(path.c_str(), R_OK) != 0)
    throw fail(std::string("cannot read it: ") + std::strerror(errno));
  const auto dot = path.rfind('.');
  const std::string ext = dot == std::string::npos ? "" : path.substr(dot);
  if (ext == ".bt") {
    std::ifstream in(path, std::ios::binary);
    // OcTree::readBinary checks the header and the node data and returns false on a bad file.
    auto tree = std::make_unique<octomap::OcTree>(0.1);
    if (!tree->readBinary(in)) throw fail("not a readable OctoMap binary (.bt) file");
    return tree;
  }
  if (ext == ".ot") {
    std::unique_ptr<octomap::AbstractOcTree> any(octomap::AbstractOcTree::read(path));
    auto* tree = dynamic_cast<octomap::OcTree*>(any.get());
    if (!tree) throw fail("not an OctoMap OcTree (.ot) file");
    any.release();
    return std::unique_ptr<octomap::OcTree>(tree);
  }
  throw fail("expected an OctoMap file (.bt or .ot)");
}

}  // namespace ballast::terrain
