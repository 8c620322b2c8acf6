// The planner's terrain: gait::TerrainQuery over a terrain::HeightMap, and the hand-over of a
// new map from the IO thread (`ballast map load`, a profile switch) to the planner thread.
//
//   IO thread       publish(map)  -- builds the HeightMap first, then one atomic store
//   planner thread  refresh()     -- at the start of an update: takes the newest map, if any
//                   height(x, y)  -- reads the map taken last; never waits, never allocates
//
// The map is a std::shared_ptr<const HeightMap> published with std::atomic_store and taken with
// std::atomic_load: the only lock either side may meet is the standard library's for the
// pointer copy itself (a few instructions, never held across a map build or a file read). One
// update plans on one map; a swap shows from the next. The planner thread drops the old map (a
// free() there is fine: the 1 kHz loop never sees the terrain). Maps are never null.
#pragma once

#include <memory>

#include "gait/terrain_query.hpp"
#include "terrain/height_map.hpp"

namespace ballast::control {

class MapTerrain final : public gait::TerrainQuery {
 public:
  /// Throws std::invalid_argument for a null map.
  explicit MapTerrain(std::shared_ptr<const terrain::HeightMap> map);

  /// Any thread: the map the planner takes at its next refresh(). Throws std::invalid_argument
  /// for a null map.
  void publish(std::shared_ptr<const terrain::HeightMap> map);
  /// Planner thread: takes the newest published map; true if it changed.
  bool refresh();

  /// Planner thread: the map in use (until the next refresh()).
  const terrain::HeightMap& map() const { return *current_; }
  double height(double x, double y) const override { return current_->height(x, y); }
  /// A map's unknown columns are not known; without a map (a flat floor, no columns at all)
  /// the floor is the ground everywhere, as the profile says.
  bool known(double x, double y) const override {
    return current_->columnsX() == 0 || current_->known(x, y);
  }

 private:
  std::shared_ptr<const terrain::HeightMap> published_;  // atomic_load / atomic_store only
  std::shared_ptr<const terrain::HeightMap> current_;    // planner thread only
};

}  // namespace ballast::control
