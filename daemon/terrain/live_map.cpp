#include "terrain/live_map.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>

#include <octomap/OcTree.h>

#include "terrain/octree_file.hpp"

namespace ballast::terrain {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// OctoMap key k is the cell [n·res, (n+1)·res) with n = k - 2^15 on each axis.
constexpr long kKeyOffset = 32768;

/// Columns added around the grid when it grows, so that a robot walking off its edge does not
/// reallocate it every scan.
constexpr long kGrowMargin = 64;

/// OcTree::search for a run of nearby keys (a ray's cells, one after another): the path of the
/// last key found is kept, and the next one descends from the deepest node the two share
/// instead of from the root (16 levels of pointer chasing each was a third of a scan's
/// insertion). Valid while the tree does not change.
class NodeCursor {
 public:
  explicit NodeCursor(const octomap::OcTree& tree) : tree_(tree) { path_[0] = tree.getRoot(); }

  /// The leaf holding `key` (a pruned node above it counts), nullptr if the tree has none.
  const octomap::OcTreeNode* find(const octomap::OcTreeKey& key) {
    constexpr int kDepth = 16;  // OctoMap's tree depth: 16-bit keys
    if (!path_[0]) return nullptr;
    int depth = valid_;
    for (int a = 0; a < 3; ++a) {
      const unsigned diff = static_cast<unsigned>(last_[a] ^ key[a]);
      if (diff) depth = std::min(depth, kDepth - 1 - (31 - __builtin_clz(diff)));
    }
    last_ = key;
    const octomap::OcTreeNode* node = path_[depth];
    for (; depth < kDepth; ++depth) {
      const unsigned child = octomap::computeChildIdx(key, kDepth - 1 - depth);
      if (!tree_.nodeChildExists(node, child)) {
        valid_ = depth;
        return tree_.nodeHasChildren(node) ? nullptr : node;
      }
      node = tree_.getNodeChild(node, child);
      path_[depth + 1] = node;
    }
    valid_ = kDepth;
    return node;
  }

 private:
  const octomap::OcTree& tree_;
  std::array<const octomap::OcTreeNode*, 17> path_{};  // path_[d]: last_'s node at depth d
  int valid_ = 0;                                       // path_[0..valid_] hold
  octomap::OcTreeKey last_{0, 0, 0};
};

/// A key as one integer, for sorting and searching.
std::uint64_t packed(const octomap::OcTreeKey& k) {
  return (std::uint64_t{k[0]} << 32) | (std::uint64_t{k[1]} << 16) | k[2];
}
octomap::OcTreeKey unpacked(std::uint64_t p) {
  return octomap::OcTreeKey(static_cast<octomap::key_type>(p >> 32),
                            static_cast<octomap::key_type>(p >> 16),
                            static_cast<octomap::key_type>(p));
}

}  // namespace

LiveMap::LiveMap(const LiveMapSettings& settings) : settings_(settings), grid_(settings.ground) {
  grid_.floorKnown_ = false;
  const auto fail = [](const std::string& why) { return MapError("mapping: " + why); };
  const LiveMapSettings& s = settings_;
  if (!(s.resolution >= 1e-3 && s.resolution <= 1.0))
    throw fail("resolution " + std::to_string(s.resolution) + " m: expected 1 mm to 1 m");
  if (!(s.probHit > 0.5 && s.probHit < 1.0)) throw fail("prob_hit must be in (0.5, 1)");
  if (!(s.probMiss > 0.0 && s.probMiss < 0.5)) throw fail("prob_miss must be in (0, 0.5)");
  if (!(s.clampMin > 0.0 && s.clampMin < s.clampMax && s.clampMax < 1.0))
    throw fail("clamping needs 0 < clamp_min < clamp_max < 1");
  if (!(s.maxRange > 0.0)) throw fail("max_range must be positive");
  if (!(s.clearDistance >= 0.0)) throw fail("clear_distance must not be negative");
  tree_ = std::make_unique<octomap::OcTree>(s.resolution);
  configureTree(*tree_);
  grid_.rule_ = s.rule;
  builtReference_ = s.rule.reference;
}

LiveMap::~LiveMap() = default;

void LiveMap::configureTree(octomap::OcTree& tree) const {
  tree.setProbHit(settings_.probHit);
  tree.setProbMiss(settings_.probMiss);
  tree.setClampingThresMin(settings_.clampMin);
  tree.setClampingThresMax(settings_.clampMax);
  tree.enableChangeDetection(true);
}

ScanUpdate LiveMap::insert(const float* xyz, int count, const ScanPose& pose,
                           const std::array<double, 3>& origin) {
  ScanUpdate update;
  const auto t0 = Clock::now();
  octomap::OcTree& tree = *tree_;
  const double res = tree.getResolution();
  const double lower = 0.25 * res;
  const octomap::point3d sensor(static_cast<float>(origin[0]), static_cast<float>(origin[1]),
                                static_cast<float>(origin[2]));
  occupied_.clear();
  clear_.clear();
  if (ends_.size() < static_cast<std::size_t>(count)) ends_.resize(static_cast<std::size_t>(count));
  // The rays' ends first: a cell a ray ends in is occupied even if another ray crosses it
  // (OctoMap's computeUpdate).
  const auto& R = pose.R;
  for (int i = 0; i < count; ++i) {
    const double x = xyz[3 * i], y = xyz[3 * i + 1], z = xyz[3 * i + 2];
    const double wx = R[0] * x + R[1] * y + R[2] * z + pose.t[0];
    const double wy = R[3] * x + R[4] * y + R[5] * z + pose.t[1];
    const double wz = R[6] * x + R[7] * y + R[8] * z + pose.t[2] - lower;
    if (!std::isfinite(wx) || !std::isfinite(wy) || !std::isfinite(wz)) continue;
    const octomap::point3d end(static_cast<float>(wx), static_cast<float>(wy), static_cast<float>(wz));
    const octomap::point3d ray = end - sensor;
    const double range = ray.norm();
    if (range > settings_.maxRange || range <= 0.0) continue;
    octomap::OcTreeKey key;
    if (!tree.coordToKeyChecked(end, key)) continue;
    ends_[update.points++] = end;
    occupied_.push_back(packed(key));
  }
  std::sort(occupied_.begin(), occupied_.end());
  occupied_.erase(std::unique(occupied_.begin(), occupied_.end()), occupied_.end());
  // Then the cells each ray crosses in its last clearDistance (see the header comment). Only
  // cells the tree holds above the free clamp are cleared (see the header comment).
  const float freeClamp = tree.getClampingThresMinLog();
  NodeCursor cursor(tree);
  for (int i = 0; i < update.points; ++i) {
    const octomap::point3d& end = ends_[i];
    const octomap::point3d ray = end - sensor;
    const double range = ray.norm();
    const double clear = std::min(range, settings_.clearDistance);
    const octomap::point3d from = end - ray * static_cast<float>(clear / range);
    if (!tree.computeRayKeys(from, end, ray_)) continue;
    for (const octomap::OcTreeKey& k : ray_) {
      const octomap::OcTreeNode* node = cursor.find(k);
      if (node && node->getLogOdds() > freeClamp &&
          !std::binary_search(occupied_.begin(), occupied_.end(), packed(k)))
        clear_.push_back(packed(k));
    }
  }
  std::sort(clear_.begin(), clear_.end());
  clear_.erase(std::unique(clear_.begin(), clear_.end()), clear_.end());
  tree.resetChangeDetection();
  for (std::uint64_t k : clear_) tree.updateNode(unpacked(k), false);
  for (std::uint64_t k : occupied_) tree.updateNode(unpacked(k), true);
  update.insertSeconds = since(t0);

  const auto t1 = Clock::now();
  // The columns whose ground may have changed: a cell within the searched heights that turned
  // occupied or free, or that is new and occupied (a new free cell leaves its column's ground
  // as it was: there was no occupied cell there before).
  const GroundRule& rule = grid_.rule_;
  const long zTop = static_cast<long>(std::floor(rule.limit() / res + 1e-6)) + kKeyOffset;
  const long zBottom = static_cast<long>(std::floor((rule.reference - settings_.depth) / res)) + kKeyOffset;
  columns_.clear();
  for (auto it = tree.changedKeysBegin(), end = tree.changedKeysEnd(); it != end; ++it) {
    const octomap::OcTreeKey& k = it->first;
    if (k[2] > zTop || k[2] < zBottom) continue;
    ++update.changedCells;
    if (it->second) {
      const octomap::OcTreeNode* node = tree.search(k);
      if (!node || !tree.isNodeOccupied(node)) continue;
    }
    columns_.push_back({static_cast<long>(k[0]) - kKeyOffset, static_cast<long>(k[1]) - kKeyOffset});
  }
  std::sort(columns_.begin(), columns_.end());
  columns_.erase(std::unique(columns_.begin(), columns_.end()), columns_.end());
  tree.resetChangeDetection();
  if (!columns_.empty()) {
    long x0 = std::numeric_limits<long>::max(), y0 = x0, x1 = std::numeric_limits<long>::min(), y1 = x1;
    for (const auto& c : columns_) {
      x0 = std::min(x0, c[0]), x1 = std::max(x1, c[0] + 1);
      y0 = std::min(y0, c[1]), y1 = std::max(y1, c[1] + 1);
    }
    if (cover(x0, x1, y0, y1))
      for (const auto& c : columns_) updateColumn(c[0], c[1]);
    update.changedColumns = columns_.size();
  }
  update.gridSeconds = since(t1);
  return update;
}

bool LiveMap::cover(long x0, long x1, long y0, long y1) {
  const double res = tree_->getResolution();
  const long gx0 = std::lround(grid_.xMin_ / (grid_.nx_ ? grid_.resolution_ : res));
  const long gy0 = std::lround(grid_.yMin_ / (grid_.ny_ ? grid_.resolution_ : res));
  const long gx1 = gx0 + static_cast<long>(grid_.nx_), gy1 = gy0 + static_cast<long>(grid_.ny_);
  if (grid_.nx_ > 0 && x0 >= gx0 && x1 <= gx1 && y0 >= gy0 && y1 <= gy1) return true;
  long nx0 = x0 - kGrowMargin, nx1 = x1 + kGrowMargin, ny0 = y0 - kGrowMargin, ny1 = y1 + kGrowMargin;
  if (grid_.nx_ > 0) {
    nx0 = std::min(nx0, gx0), nx1 = std::max(nx1, gx1);
    ny0 = std::min(ny0, gy0), ny1 = std::max(ny1, gy1);
  }
  const auto nx = static_cast<std::size_t>(nx1 - nx0), ny = static_cast<std::size_t>(ny1 - ny0);
  if (nx > HeightMap::kMaxColumns / ny) return false;
  std::vector<double> cells(nx * ny, settings_.ground);
  std::vector<std::uint8_t> known(nx * ny, 0);
  for (std::size_t y = 0; y < grid_.ny_; ++y) {
    const std::size_t from = y * grid_.nx_;
    const std::size_t to = static_cast<std::size_t>(gy0 - ny0 + static_cast<long>(y)) * nx +
                           static_cast<std::size_t>(gx0 - nx0);
    std::copy_n(grid_.cells_.begin() + from, grid_.nx_, cells.begin() + to);
    std::copy_n(grid_.known_.begin() + from, grid_.nx_, known.begin() + to);
  }
  grid_.cells_ = std::move(cells);
  grid_.known_ = std::move(known);
  grid_.nx_ = nx, grid_.ny_ = ny;
  grid_.resolution_ = res;
  grid_.inverseResolution_ = 1.0 / res;
  grid_.xMin_ = static_cast<double>(nx0) * res;
  grid_.yMin_ = static_cast<double>(ny0) * res;
  return true;
}

void LiveMap::updateColumn(long ix, long iy) {
  const double res = tree_->getResolution();
  const GroundRule& rule = grid_.rule_;
  // Cells from the one holding the limit (its bottom is within it) down to `depth` below the
  // reference; the first occupied one is the column's ground.
  const long top = static_cast<long>(std::floor(rule.limit() / res + 1e-6));
  const long bottom = static_cast<long>(std::floor((rule.reference - settings_.depth) / res));
  const auto key = [](long n) { return static_cast<octomap::key_type>(n + kKeyOffset); };
  double height = settings_.ground;
  bool found = false;
  for (long iz = top; iz >= bottom; --iz) {
    const octomap::OcTreeNode* node = tree_->search(octomap::OcTreeKey(key(ix), key(iy), key(iz)));
    if (node && tree_->isNodeOccupied(node)) {
      height = static_cast<double>(iz + 1) * res;
      found = true;
      break;
    }
  }
  const long gx0 = std::lround(grid_.xMin_ * grid_.inverseResolution_);
  const long gy0 = std::lround(grid_.yMin_ * grid_.inverseResolution_);
  const std::size_t i = static_cast<std::size_t>(iy - gy0) * grid_.nx_ + static_cast<std::size_t>(ix - gx0);
  if (grid_.known_[i] && !found) --grid_.knownCount_;
  if (!grid_.known_[i] && found) ++grid_.knownCount_;
  grid_.known_[i] = found ? 1 : 0;
  grid_.cells_[i] = height;
}

void LiveMap::rebuild() {
  builtReference_ = grid_.rule_.reference;
  bool occupied = false;
  for (auto it = tree_->begin_leafs(), end = tree_->end_leafs(); it != end && !occupied; ++it)
    occupied = tree_->isNodeOccupied(*it);
  const GroundRule rule = grid_.rule_;
  const bool floor = grid_.floorKnown_;
  grid_ = occupied ? HeightMap::fromOcTree(*tree_, settings_.ground, "", rule)
                   : HeightMap(settings_.ground);
  grid_.rule_ = rule;
  grid_.floorKnown_ = floor;
}

void LiveMap::seed(const octomap::OcTree& tree, double ground, const std::string& path) {
  HeightMap grid = HeightMap::fromOcTree(tree, ground, path, grid_.rule_);
  auto copy = std::make_unique<octomap::OcTree>(tree);
  configureTree(*copy);
  settings_.ground = ground;
  tree_ = std::move(copy);
  grid_ = std::move(grid);
  builtReference_ = grid_.rule_.reference;
}

void LiveMap::clear(double ground, bool floor) {
  settings_.ground = ground;
  // Back to the profile's resolution (a seeded file's stays only as long as its cells).
  tree_ = std::make_unique<octomap::OcTree>(settings_.resolution);
  configureTree(*tree_);
  const GroundRule rule = grid_.rule_;
  grid_ = HeightMap(settings_.ground);
  grid_.rule_ = rule;
  grid_.floorKnown_ = floor;
}

bool LiveMap::setReference(double z) {
  grid_.rule_.reference = z;
  if (std::abs(z - builtReference_) <= 0.25 * grid_.rule_.clearance) return false;
  rebuild();
  return true;
}

bool LiveMap::save(const std::string& path, std::string& error) const {
  std::ofstream out(path, std::ios::binary);
  if (!out || !tree_->writeBinaryConst(out) || !(out.flush())) {
    error = "map " + path + ": cannot write it";
    return false;
  }
  return true;
}

std::shared_ptr<const HeightMap> LiveMap::heights() const {
  return std::make_shared<const HeightMap>(grid_);
}

}  // namespace ballast::terrain
