// The planner's terrain: gait::TerrainQuery over a terrain::HeightMap, and the hand-over of new
// maps from the threads that make them (the mapping thread after each scan; the IO thread for
// `ballast map load/clear` and profile switches) to the planner thread.
//
//   mapping/IO thread  publish(map, scan, handoff_ns)  -- builds the HeightMap first, then one
//                                                         atomic store into a ring of 4
//   planner thread     refresh(wanted)  -- at the start of an update: takes the newest map made
//                                          from scans up to `wanted` (all: kNewest)
//                      height(x, y)     -- reads the map taken last; never waits, never allocates
//
// Each published map is a std::shared_ptr<const Published> stored with std::atomic_store and
// taken with std::atomic_load: the only lock either side may meet is the standard library's for
// the pointer copy itself (a few instructions, never held across a map build or a file read).
// The ring keeps the last four so that in lockstep the planner finds exactly the map of the
// scan the loop says is due (PlannerInput::map_scan), even when the mapping thread has gone on
// to the next scan: the plans do not depend on how fast that thread ran. One update plans on
// one map; a swap shows from the next. The planner thread drops the old map (a free() there is
// fine: the 1 kHz loop never sees the terrain). Maps are never null.
//
// Latency: a published map carries the wall time its scan was handed off by the loop; when the
// planner takes it, the difference is the scan-to-planner latency (last and largest kept).
//
// Agreement (checkUnderFeet, each update): the estimator takes the stance contact points'
// heights from the plan's terrain, so where the feet stand the map in use and the feet agree.
// A new map (loaded, seeded, or changed by scans) is compared with the map before it under the
// stance points: one that moves the ground under the feet by more than a tolerance disagrees
// (the first map, and one that disagrees, are compared with the estimated points themselves).
// A map that disagrees is not used, neither for footholds nor for the heights the estimator is
// given: height() reads the plane the stance points stood on when it stopped agreeing, known
// everywhere, until a map agrees with the feet again. A wrong map would otherwise lift the
// estimated base by its error, and the whole-body controller would put the robot there. The
// feet and the map are not compared between map changes: a foot that lands off its planned
// foothold (a few cm short of a step's edge) puts its estimate off the map for a moment, and
// that is the swing's error, not the map's.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>

#include "control/types.hpp"
#include "gait/terrain_query.hpp"
#include "terrain/height_map.hpp"

namespace ballast::control {

class MapTerrain final : public gait::TerrainQuery {
 public:
  static constexpr std::uint64_t kNewest = ~std::uint64_t{0};

  /// Throws std::invalid_argument for a null map.
  explicit MapTerrain(std::shared_ptr<const terrain::HeightMap> map);

  /// Any thread but the loop's: a map the planner takes at its next refresh(). `scan`: the
  /// index of the last scan in it (0: none); `handoff_ns`: the wall time (monotonicNs) that
  /// scan left the loop (0: not from a scan). Throws std::invalid_argument for a null map.
  void publish(std::shared_ptr<const terrain::HeightMap> map, std::uint64_t scan = 0,
               std::uint64_t handoff_ns = 0);
  /// Planner thread: takes the newest published map made of scans up to `wanted`; true if it
  /// changed.
  bool refresh(std::uint64_t wanted = kNewest);

  /// Planner thread: the map in use (until the next refresh()).
  const terrain::HeightMap& map() const { return *current_->map; }
  /// The map's height, or while it disagrees (checkUnderFeet) the plane the feet stood on.
  double height(double x, double y) const override {
    return agrees_ ? current_->map->height(x, y) : plane_;
  }
  /// A map's unknown columns are not known; without a map file the floor is, as the profile
  /// says (HeightMap::floorKnown). A cleared live map knows nothing it did not observe. The
  /// plane of a map that disagrees is known everywhere.
  bool known(double x, double y) const override {
    return !agrees_ || current_->map->known(x, y);
  }

  /// Planner thread, after refresh(): checks a map in use that is new since the last check
  /// (or every update while it disagrees) under the stance contact points of `state` (those the
  /// estimator has in contact, world). A point's error is the distance from its ground (the
  /// previous map's height under it, or its own z for the first map and while the map
  /// disagrees) to the nearest column height within one cell of it (a foot by a step's edge
  /// stands on one side of it), over known columns. The map disagrees when an error exceeds
  /// `tolerance` plus the map's cell (a surface reads as the top of its cell), and agrees again
  /// when every error is within half that. `tolerance` <= 0: never checked.
  void checkUnderFeet(const EstimatedState& state, double tolerance);
  /// Planner thread: whether the map in use agrees (always, when unchecked).
  bool agrees() const { return agrees_; }
  /// Planner thread: the largest error of the last check, m (NaN: no stance point over a
  /// known column then, or unchecked).
  double disagreement() const { return disagreement_; }

  /// Any thread: ms from a scan's hand-off to the planner taking its map (the last one, the
  /// largest since start); -1 before any.
  double lastLatencyMs() const { return last_latency_ms_.load(std::memory_order_relaxed); }
  double maxLatencyMs() const { return max_latency_ms_.load(std::memory_order_relaxed); }
  /// Any thread: the scan index of the map the planner uses.
  std::uint64_t scanInUse() const { return scan_in_use_.load(std::memory_order_relaxed); }

 private:
  struct Published {
    std::shared_ptr<const terrain::HeightMap> map;
    std::uint64_t scan = 0, serial = 0, handoff_ns = 0;
  };
  static constexpr std::size_t kRing = 4;
  std::array<std::shared_ptr<const Published>, kRing> ring_;  // atomic_load / atomic_store only
  std::atomic<std::uint64_t> serial_{0};  // of the newest published
  std::atomic<std::uint64_t> writing_{0};  // publishers' serials (publish() may race itself)
  std::shared_ptr<const Published> current_;  // planner thread only
  bool agrees_ = true;        // planner thread only
  double plane_ = 0.0;        // m: the feet's plane while the map disagrees
  double disagreement_ = kNaN;
  std::shared_ptr<const terrain::HeightMap> checked_;  // the map the last check passed or made
  std::atomic<double> last_latency_ms_{-1.0}, max_latency_ms_{-1.0};
  std::atomic<std::uint64_t> scan_in_use_{0};
};

}  // namespace ballast::control
