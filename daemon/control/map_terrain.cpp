#include "control/map_terrain.hpp"

#include <atomic>
#include <stdexcept>
#include <utility>

namespace ballast::control {
namespace {

std::shared_ptr<const terrain::HeightMap> checked(std::shared_ptr<const terrain::HeightMap> map) {
  if (!map) throw std::invalid_argument("MapTerrain: a terrain map is never null");
  return map;
}

}  // namespace

MapTerrain::MapTerrain(std::shared_ptr<const terrain::HeightMap> map)
    : published_(checked(std::move(map))), current_(published_) {}

void MapTerrain::publish(std::shared_ptr<const terrain::HeightMap> map) {
  std::atomic_store(&published_, checked(std::move(map)));
}

bool MapTerrain::refresh() {
  std::shared_ptr<const terrain::HeightMap> newest = std::atomic_load(&published_);
  if (newest == current_) return false;
  current_ = std::move(newest);
  return true;
}

}  // namespace ballast::control
