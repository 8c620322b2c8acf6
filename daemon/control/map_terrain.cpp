#include "control/map_terrain.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "control/control_loop.hpp"  // monotonicNs

namespace ballast::control {
namespace {

std::shared_ptr<const terrain::HeightMap> checked(std::shared_ptr<const terrain::HeightMap> map) {
  if (!map) throw std::invalid_argument("MapTerrain: a terrain map is never null");
  return map;
}

}  // namespace

MapTerrain::MapTerrain(std::shared_ptr<const terrain::HeightMap> map) {
  auto first = std::make_shared<Published>();
  first->map = checked(std::move(map));
  current_ = first;
  ring_[0] = std::move(first);
}

void MapTerrain::publish(std::shared_ptr<const terrain::HeightMap> map, std::uint64_t scan,
                         std::uint64_t handoff_ns) {
  auto p = std::make_shared<Published>();
  p->map = checked(std::move(map));
  p->scan = scan;
  p->handoff_ns = handoff_ns;
  p->serial = writing_.fetch_add(1, std::memory_order_acq_rel) + 1;
  std::atomic_store(&ring_[p->serial % kRing], std::shared_ptr<const Published>(p));
  // serial_ only moves forward (two publishers may finish out of order).
  std::uint64_t s = serial_.load(std::memory_order_acquire);
  while (s < p->serial && !serial_.compare_exchange_weak(s, p->serial, std::memory_order_acq_rel)) {
  }
}

bool MapTerrain::refresh(std::uint64_t wanted) {
  const std::uint64_t newest = serial_.load(std::memory_order_acquire);
  std::shared_ptr<const Published> best;
  for (std::uint64_t k = 0; k < kRing && k <= newest; ++k) {
    std::shared_ptr<const Published> p = std::atomic_load(&ring_[(newest - k) % kRing]);
    if (!p || p->serial != newest - k) continue;  // overwritten by a newer one meanwhile
    if (p->scan <= wanted) {
      best = std::move(p);
      break;
    }
  }
  if (!best || best == current_ || best->serial < current_->serial) return false;
  current_ = std::move(best);
  scan_in_use_.store(current_->scan, std::memory_order_relaxed);
  if (current_->handoff_ns != 0) {
    const double ms = static_cast<double>(monotonicNs() - current_->handoff_ns) * 1e-6;
    last_latency_ms_.store(ms, std::memory_order_relaxed);
    if (ms > max_latency_ms_.load(std::memory_order_relaxed))
      max_latency_ms_.store(ms, std::memory_order_relaxed);
  }
  return true;
}

void MapTerrain::checkUnderFeet(const EstimatedState& state, double tolerance) {
  if (!(tolerance > 0.0)) {
    agrees_ = true;
    disagreement_ = kNaN;
    checked_.reset();
    return;
  }
  // A map that agreed is checked again when it changes, against the map before it; one that
  // does not agree, or the first, against where the feet are.
  const std::shared_ptr<const terrain::HeightMap>& map = current_->map;
  if (agrees_ && map == checked_) return;
  const terrain::HeightMap* before = agrees_ ? checked_.get() : nullptr;
  const double cell = map->resolution();
  double worst = -1.0, stance_z = 0.0;
  int stance = 0;
  for (int c = 0; c < kNumContacts; ++c) {
    if (!state.contact[c]) continue;
    const double* p = state.contact_position[c];
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) continue;
    stance_z += p[2];
    ++stance;
    const double ground = before && before->known(p[0], p[1]) ? before->height(p[0], p[1]) : p[2];
    double error = HUGE_VAL;
    for (int i = -1; i <= 1; ++i)
      for (int j = -1; j <= 1; ++j) {
        const double x = p[0] + i * cell, y = p[1] + j * cell;
        if (map->known(x, y)) error = std::min(error, std::abs(ground - map->height(x, y)));
      }
    if (error < HUGE_VAL) worst = std::max(worst, error);
  }
  if (worst < 0.0) {  // nothing to compare: as it was, and checked again at the next update
    disagreement_ = kNaN;
    return;
  }
  checked_ = map;
  disagreement_ = worst;
  const double limit = tolerance + cell;
  if (agrees_ && worst > limit) {
    agrees_ = false;
    plane_ = stance_z / stance;
  } else if (!agrees_ && worst <= 0.5 * limit) {
    agrees_ = true;
  }
}

}  // namespace ballast::control
