// Simulated lidar: a rolling scan from a frame on the robot, for any simulation that can cast a
// ray at its terrain (the simbody and mujoco backends).
//
// A scan is horizontal_rays × vertical_rays rays in the sensor frame (x forward, z up): azimuth
// across horizontal_fov centred on x, elevation from vertical_min to vertical_max. Like a
// spinning sensor it sweeps during 1/rate s: each tick casts the rays due by then, from the pose
// the sensor has then, so a scan costs the same every tick and moving shows up as it would. A
// finished scan is published in the sensor frame at the sweep's end (ABI ScanFrame::kSensor:
// each point, cast from the pose the sensor had when its ray was due, is brought to the last
// pose, as a driver deskews a sweep with its IMU), with the link the sensor is mounted on and
// its placement there, so ballastd places it by its own estimate of the robot's pose. Hits
// within [min_range, max_range] only, with optional range noise from its own generator.
// Nothing allocates after configure().
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "backend_abi.hpp"

namespace ballast::plugin {

struct LidarSettings {
  double rate = 10.0;  ///< scans per second
  int horizontal_rays = 180, vertical_rays = 16;
  double horizontal_fov = 6.283185307179586;  ///< rad, centred on x
  double vertical_min = -1.0, vertical_max = 0.25;  ///< elevation, rad
  double min_range = 0.1, max_range = 10.0, range_noise = 0.0;  ///< m
  /// The mount, as PointCloudView says it: the URDF link the sensor is on and the sensor frame's
  /// placement in it (origin, and fixed-axis roll, pitch, yaw).
  std::string link;
  double offset[3] = {0.0, 0.0, 0.0}, rpy[3] = {0.0, 0.0, 0.0};
};

/// LidarSettings from a simulation plugin's lidar.* keys (fields lidar_rate, ..., lidar_frame).
template <typename Settings>
LidarSettings lidarSettings(const Settings& s) {
  LidarSettings l;
  l.rate = s.lidar_rate;
  l.horizontal_rays = s.lidar_horizontal_rays;
  l.vertical_rays = s.lidar_vertical_rays;
  l.horizontal_fov = s.lidar_horizontal_fov;
  l.vertical_min = s.lidar_vertical_min;
  l.vertical_max = s.lidar_vertical_max;
  l.min_range = s.lidar_min_range;
  l.max_range = s.lidar_max_range;
  l.range_noise = s.lidar_range_noise;
  l.link = s.lidar_frame.link;
  for (int k = 0; k < 3; ++k) l.offset[k] = s.lidar_frame.offset[k], l.rpy[k] = s.lidar_frame.rpy[k];
  return l;
}

class RollingLidar {
 public:
  void configure(const LidarSettings& settings, std::uint64_t seed);
  /// Starts a new scan at time t (drops any partial one; re-seeds the noise).
  void start(double t);
  /// Casts the rays due by time t from the sensor at `origin` (world) with orientation R
  /// (world <- sensor, row-major 3×3). cast(origin, direction, maxRange, range) -> bool finds
  /// the first hit of the terrain along a unit direction (world), within maxRange.
  template <typename Cast>
  void tick(double t, const double origin[3], const double R[9], Cast&& cast);
  /// The latest finished scan if it was not taken yet.
  bool take(backend::PointCloudView& view);
  int raysPerScan() const { return static_cast<int>(directions_.size() / 3); }

 private:
  void publish(double t, const double origin[3], const double R[9]);

  std::vector<double> directions_;       ///< sensor frame, unit, 3 per ray, in sweep order
  std::vector<float> building_, ready_;  ///< 3 floats per point, capacity for a full scan
  int buildingCount_ = 0, readyCount_ = 0;
  bool readyNew_ = false;
  double readyTime_ = 0.0;
  char link_[backend::kNameLength] = {};
  double offset_[3] = {}, rpy_[3] = {};
  double scanPeriod_ = 0.1, scanStart_ = 0.0;
  int nextRay_ = 0;
  double minRange_ = 0.0, maxRange_ = 10.0, rangeNoise_ = 0.0;
  std::uint64_t seed_ = 0;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
};

// ---- implementation of the template ----

template <typename Cast>
void RollingLidar::tick(double t, const double origin[3], const double R[9], Cast&& cast) {
  const int total = raysPerScan();
  const double fraction = (t - scanStart_) / scanPeriod_;
  const int due = std::min(total, static_cast<int>(std::floor(fraction * total + 1e-9)));
  for (; nextRay_ < due; ++nextRay_) {
    const double* s = &directions_[static_cast<std::size_t>(3 * nextRay_)];
    double d[3];
    for (int i = 0; i < 3; ++i) d[i] = R[3 * i] * s[0] + R[3 * i + 1] * s[1] + R[3 * i + 2] * s[2];
    double range;
    if (!cast(origin, static_cast<const double*>(d), maxRange_, range) || range < minRange_)
      continue;
    if (rangeNoise_ > 0.0) range += rangeNoise_ * normal_(rng_);
    float* out = &building_[static_cast<std::size_t>(3 * buildingCount_++)];
    for (int k = 0; k < 3; ++k) out[k] = static_cast<float>(origin[k] + range * d[k]);
  }
  if (nextRay_ >= total) publish(t, origin, R);
}

}  // namespace ballast::plugin
