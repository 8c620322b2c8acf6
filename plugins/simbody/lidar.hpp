// Simulated lidar: a rolling scan of the terrain from a frame on the robot.
//
// A scan is horizontal_rays × vertical_rays rays in the sensor frame (x forward, z up): azimuth
// across horizontal_fov centred on x, elevation from vertical_min to vertical_max. Like a
// spinning sensor it sweeps during 1/rate s: each tick casts the rays due by then, from the pose
// the sensor has then, so a scan costs the same every tick and moving shows up as it would. A
// finished scan is published (world-frame points, hits within [min_range, max_range] only, with
// optional range noise). The robot does not see itself. Nothing allocates after configure().
#pragma once

#include <Simbody.h>

#include <cstdint>
#include <random>
#include <vector>

#include "backend_abi.hpp"
#include "sim_settings.hpp"
#include "terrain.hpp"

namespace ballast::simbody {

class RollingLidar {
 public:
  void configure(const SimSettings& settings, std::uint64_t seed);
  /// Starts a new scan at time t (drops any partial one; re-seeds the noise).
  void start(double t);
  /// Casts the rays due by time t from pose X_GL (world <- sensor).
  void tick(double t, const SimTK::Transform& X_GL, const Terrain& terrain);
  /// The latest finished scan if it was not taken yet.
  bool take(backend::PointCloudView& view);
  int raysPerScan() const { return static_cast<int>(directions_.size()); }

 private:
  std::vector<SimTK::Vec3> directions_;  ///< sensor frame, unit, in sweep order
  std::vector<float> building_, ready_;  ///< 3 floats per point, capacity for a full scan
  int buildingCount_ = 0, readyCount_ = 0;
  bool readyNew_ = false;
  double readyTime_ = 0.0;
  SimTK::Vec3 readyOrigin_{0};
  double scanPeriod_ = 0.1, scanStart_ = 0.0;
  int nextRay_ = 0;
  double minRange_ = 0.0, maxRange_ = 10.0, rangeNoise_ = 0.0;
  std::uint64_t seed_ = 0;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
};

}  // namespace ballast::simbody
