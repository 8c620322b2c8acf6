#include "control/map_terrain.hpp"

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

}  // namespace ballast::control
