// The live terrain map beside the control loop: the robot's own lidar scans inserted into an
// OctoMap (terrain::LiveMap) on a mapping thread of normal priority, and the height grid that
// comes of each scan handed to the planner (MpcPlanner::setTerrain).
//
//   loop (1 kHz)  --scan(): a preallocated slot filled, published--> mapping thread: insert
//   mapping       --MpcPlanner::setTerrain(grid, scan, handoff)--> planner (MapTerrain's ring)
//
// The loop never waits and never allocates for it: when the backend has a new scan (and at most
// mapping.rate of them per second), it copies the points into the back slot of a triple buffer
// together with what the mapping thread needs to place them (the estimated base pose and the
// measured joints at that tick, for scans in the sensor frame, and the stance feet, whose height
// is the ground rule's reference), publishes it and posts a semaphore. The mapping thread takes
// the newest slot (a scan it had no time for is skipped and counted), inserts it and publishes
// the grid. Scans in the world frame (ABI kWorld) are inserted as they are.
//
// Real time: the mapping thread is background work at the lowest normal priority (nice 19). An
// insertion takes about 2 ms of CPU per scan on an idle host (BM_LiveMapScan at 4 cm), more on
// a loaded one; beside the loop and the planner (real-time priority when the host grants it,
// normal otherwise, as on CI and in containers) and the planner's linearisation team it must
// only take what they leave. A map that comes late is seen (scans skipped, the
// scan-to-planner latency in `map info`); a plan that comes late damps the robot.
//
// Lockstep (deterministic, as the planner's slot is): the map of a scan handed off at t_k is
// due at t_k + mapping.latency; the loop waits for it then if it is not there yet and from then
// on asks the planner for the map of scans up to k (PlannerInput::map_scan), so a run is the
// same whatever the mapping thread's speed. No scan is skipped in lockstep.
//
// The IO thread's verbs (`ballast map load/clear/save/info`) take the same map under a mutex the
// mapping thread holds while it inserts (the loop never takes it).
#pragma once

#include <semaphore.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "control/triple_buffer.hpp"
#include "control/types.hpp"
#include "model/model.hpp"
#include "terrain/live_map.hpp"

namespace octomap {
class OcTree;
}

namespace ballast::control {

class MpcPlanner;

/// The mapping.* keys of a profile.
struct MappingSettings {
  bool enabled = true;   ///< insert the backend's lidar scans (when it has a lidar)
  double rate = 10.0;    ///< Hz: at most this many scans inserted per second
  double latency = 0.05;  ///< s, lockstep: controller time from a scan to the planner having its map
  terrain::LiveMapSettings map;
};

/// One scan as the loop hands it off.
struct LidarScan {
  static constexpr int kMaxPoints = 32768;
  std::uint64_t index = 0;       ///< 1, 2, ... in hand-off order
  double t = 0.0;                ///< controller time of the tick that took it
  std::uint64_t handoff_ns = 0;  ///< wall clock (monotonicNs) then
  int count = 0;
  bool truncated = false;        ///< the backend gave more than kMaxPoints
  bool sensor_frame = false;     ///< points in the sensor's frame (else the world's)
  char sensor_link[backend::kNameLength] = {};  ///< the link the sensor is mounted on
  double sensor_offset[3] = {}, sensor_rpy[3] = {};  ///< its placement there
  double origin[3] = {};
  EstimatedState state;  ///< that tick's: where the sensor was and where the stance feet are
  std::array<float, 3 * kMaxPoints> xyz{};
};

class TerrainMapper {
 public:
  /// The mapping thread's nice in real time: the lowest normal priority.
  static constexpr int kBackgroundNice = 19;

  /// Throws terrain::MapError for mapping settings OctoMap cannot use.
  TerrainMapper(const model::Model& model, const MappingSettings& settings, MpcPlanner* planner);
  ~TerrainMapper();
  TerrainMapper(const TerrainMapper&) = delete;
  TerrainMapper& operator=(const TerrainMapper&) = delete;

  const MappingSettings& settings() const { return settings_; }
  /// Starts the mapping thread (scans handed off before are inserted then). `background`: real
  /// time, at nice 19 (see the header comment). Lockstep, where the loop waits for the map,
  /// keeps the starting thread's priority, or, real-time (SCHED_FIFO, a daemon under chrt),
  /// one below it, so that the planner's team preempts it.
  void start(bool background = false);
  void stop();

  // ---- control thread (single producer) ----
  /// The slot to fill; then handOff().
  LidarScan& back() { return scans_.back(); }
  /// Publishes the slot and wakes the mapping thread. Never waits, never allocates.
  void handOff();
  /// Index of the last scan inserted and published (0: none).
  std::uint64_t done() const { return done_.load(std::memory_order_acquire); }
  /// Lockstep: waits until scan `index` is inserted (or the thread stopped).
  void waitFor(std::uint64_t index);

  // ---- IO thread ----
  /// Seeds the map with `tree` (`ballast map load`, terrain.map at start, a profile switch),
  /// unknown columns at `ground`; throws terrain::MapError as HeightMap::fromOcTree does,
  /// leaving the map as it was.
  void seed(const octomap::OcTree& tree, const std::string& path, double ground);
  /// Forgets everything: every column unknown, at `ground` (`ballast map clear`), or with
  /// `floor` the profile's flat floor at `ground` known where no scan finds ground (a profile
  /// without a map file, at start and when switched to; LiveMap::clear).
  void clear(double ground, bool floor = false);
  /// Writes the map (.bt); false with a message naming the file.
  bool save(const std::string& path, std::string& error);
  /// What `map info` shows of the live map.
  nlohmann::json info();

 private:
  void run();
  void insert(const LidarScan& scan);
  void publish(std::uint64_t handoff_ns);

  const model::Model& model_;
  MappingSettings settings_;
  MpcPlanner* planner_;
  TripleBuffer<LidarScan> scans_;
  sem_t wake_;
  std::atomic<bool> stop_{false};
  bool background_ = false;
  std::thread thread_;
  std::atomic<std::uint64_t> done_{0};

  std::mutex mutex_;  // the map and the figures below (mapping and IO threads)
  terrain::LiveMap map_;
  std::string seeded_;  // the file it was seeded from last
  std::uint64_t inserted_ = 0, skipped_ = 0, last_index_ = 0, truncated_ = 0;
  double last_t_ = -1.0;
  terrain::ScanUpdate last_;
  double insert_ms_max_ = 0.0;
  std::string problem_;  // a scan that cannot be placed (an unknown sensor link), said once
};

}  // namespace ballast::control
