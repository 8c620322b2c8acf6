// Reading a terrain map file: an OctoMap occupancy tree from a .bt (binary) or .ot (full) file.
// One place for every way that fails, so the daemon's `map load`, the profile's terrain.map and
// the planner's height grid all refuse a bad file with the same words: the message names the
// file and the reason (cannot be read, not an OctoMap file of that kind, wrong extension).
#pragma once

#include <memory>
#include <stdexcept>
#include <string>

namespace octomap {
class OcTree;
}

namespace ballast::terrain {

/// A terrain map that cannot be used; what() is "map <path>: <reason>".
class MapError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Reads path by its extension: .bt with OcTree::readBinary, .ot with AbstractOcTree::read (it
/// must hold an OcTree). Throws MapError. Never returns null.
std::unique_ptr<octomap::OcTree> readOcTree(const std::string& path);

}  // namespace ballast::terrain
