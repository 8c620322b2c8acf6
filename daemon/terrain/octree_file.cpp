#include "terrain/octree_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

#include <octomap/OcTree.h>

namespace ballast::terrain {
namespace {

/// OctoMap trees are 16 levels deep: a node at depth 16 is a leaf of the finest cells.
constexpr int kTreeDepth = 16;

/// Where a file's node data begins: after the header's "data" line. npos if there is none.
std::size_t dataStart(const std::string& bytes, std::string& id) {
  std::size_t pos = 0;
  while (pos < bytes.size()) {
    const std::size_t eol = bytes.find('\n', pos);
    if (eol == std::string::npos) return std::string::npos;
    std::istringstream line(bytes.substr(pos, eol - pos));
    std::string token;
    line >> token;
    pos = eol + 1;
    if (token == "id") line >> id;
    if (token == "data") return pos;
  }
  return std::string::npos;
}

/// Walks the node stream of a tree file without building it and returns where it ends, or
/// npos when it runs past the end of the file or deeper than a tree can be. OctoMap's own
/// readers do neither check: a truncated file reads uninitialised bytes as child flags.
/// Binary (.bt): 2 bytes per inner node, 2 bits per child, 11 = has children. Full (.ot,
/// OcTree): a float log-odds and 1 byte, a bit per existing child, for every node.
std::size_t walkNodes(const std::string& bytes, std::size_t pos, int depth, bool binary) {
  if (binary) {
    if (pos + 2 > bytes.size()) return std::string::npos;
    const auto a = static_cast<unsigned char>(bytes[pos]), b = static_cast<unsigned char>(bytes[pos + 1]);
    pos += 2;
    for (int i = 0; i < 8; ++i) {
      const unsigned bits = ((i < 4 ? a : b) >> (2 * (i % 4))) & 3u;
      if (bits != 3u) continue;
      if (depth + 1 >= kTreeDepth) return std::string::npos;
      pos = walkNodes(bytes, pos, depth + 1, binary);
      if (pos == std::string::npos) return pos;
    }
    return pos;
  }
  if (pos + sizeof(float) + 1 > bytes.size()) return std::string::npos;
  const auto children = static_cast<unsigned char>(bytes[pos + sizeof(float)]);
  pos += sizeof(float) + 1;
  for (int i = 0; i < 8; ++i) {
    if (!((children >> i) & 1u)) continue;
    if (depth + 1 > kTreeDepth) return std::string::npos;
    pos = walkNodes(bytes, pos, depth + 1, binary);
    if (pos == std::string::npos) return pos;
  }
  return pos;
}

}  // namespace

std::unique_ptr<octomap::OcTree> readOcTree(const std::string& path) {
  const auto fail = [&](const std::string& why) { return MapError("map " + path + ": " + why); };
  if (access(path.c_str(), R_OK) != 0)
    throw fail(std::string("cannot read it: ") + std::strerror(errno));
  const auto dot = path.rfind('.');
  const std::string ext = dot == std::string::npos ? "" : path.substr(dot);
  if (ext != ".bt" && ext != ".ot") throw fail("expected an OctoMap file (.bt or .ot)");
  const bool binary = ext == ".bt";
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof()) throw fail(std::string("cannot read it: ") + std::strerror(errno));
  const std::string kind = binary ? "not a readable OctoMap binary (.bt) file"
                                  : "not an OctoMap OcTree (.ot) file";
  // OctoMap's headers: "# Octomap OcTree binary file" (.bt), "# Octomap OcTree" then more (.ot).
  const std::string header = "# Octomap OcTree", binaryHeader = header + " binary file";
  if (bytes.compare(0, header.size(), header) != 0 ||
      (bytes.compare(0, binaryHeader.size(), binaryHeader) == 0) != binary)
    throw fail(kind);
  std::string id;
  const std::size_t data = dataStart(bytes, id);
  if (data == std::string::npos) throw fail(kind + " (no data in it)");
  if (id != "OcTree") throw fail(kind + " (it holds a " + (id.empty() ? "tree of no kind" : id) + ")");
  if (data < bytes.size()) {
    const std::size_t end = walkNodes(bytes, data, 0, binary);
    if (end == std::string::npos)
      throw fail("the file is cut short or corrupt: its tree runs past the end (" +
                 std::to_string(bytes.size()) + " bytes)");
  }
  std::istringstream stream(bytes);
  if (binary) {
    // OcTree::readBinary checks the header and reads the node data.
    auto tree = std::make_unique<octomap::OcTree>(0.1);
    if (!tree->readBinary(stream)) throw fail(kind);
    return tree;
  }
  std::unique_ptr<octomap::AbstractOcTree> any(octomap::AbstractOcTree::read(stream));
  auto* tree = dynamic_cast<octomap::OcTree*>(any.get());
  if (!tree) throw fail(kind);
  any.release();
  return std::unique_ptr<octomap::OcTree>(tree);
}

}  // namespace ballast::terrain
