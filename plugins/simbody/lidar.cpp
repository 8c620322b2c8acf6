#include "lidar.hpp"

#include <algorithm>
#include <cmath>

namespace ballast::simbody {

void RollingLidar::configure(const SimSettings& s, std::uint64_t seed) {
  const int nh = s.lidar_horizontal_rays, nv = s.lidar_vertical_rays;
  const bool fullCircle = s.lidar_horizontal_fov >= 2 * SimTK::Pi - 1e-9;
  directions_.clear();
  directions_.reserve(static_cast<std::size_t>(nh * nv));
  for (int i = 0; i < nh; ++i) {
    // A full circle has no duplicate ray at ±π; a sector includes both edges.
    const double azimuth =
        nh == 1 ? 0.0
                : -s.lidar_horizontal_fov / 2 +
                      s.lidar_horizontal_fov * i / (fullCircle ? nh : nh - 1);
    for (int j = 0; j < nv; ++j) {
      const double elevation =
          nv == 1 ? (s.lidar_vertical_min + s.lidar_vertical_max) / 2
                  : s.lidar_vertical_min + (s.lidar_vertical_max - s.lidar_vertical_min) * j / (nv - 1);
      directions_.emplace_back(std::cos(elevation) * std::cos(azimuth),
                               std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
    }
  }
  building_.assign(3 * directions_.size(), 0.0f);
  ready_.assign(3 * directions_.size(), 0.0f);
  scanPeriod_ = 1.0 / s.lidar_rate;
  minRange_ = s.lidar_min_range;
  maxRange_ = s.lidar_max_range;
  rangeNoise_ = s.lidar_range_noise;
  seed_ = seed;
  start(0.0);
}

void RollingLidar::start(double t) {
  scanStart_ = t;
  nextRay_ = 0;
  buildingCount_ = readyCount_ = 0;
  readyNew_ = false;
  rng_.seed(seed_ ^ 0x6c696461725f7365ULL);  // its own stream: lidar noise leaves the IMU's alone
  normal_.reset();
}

void RollingLidar::tick(double t, const SimTK::Transform& X_GL, const Terrain& terrain) {
  const int total = raysPerScan();
  const double fraction = (t - scanStart_) / scanPeriod_;
  const int due = std::min(total, static_cast<int>(std::floor(fraction * total + 1e-9)));
  const SimTK::Vec3& origin = X_GL.p();
  for (; nextRay_ < due; ++nextRay_) {
    const SimTK::Vec3 d = X_GL.R() * directions_[static_cast<std::size_t>(nextRay_)];
    double range;
    if (!terrain.castRay(origin, d, maxRange_, range) || range < minRange_) continue;
    if (rangeNoise_ > 0.0) range += rangeNoise_ * normal_(rng_);
    const SimTK::Vec3 p = origin + range * d;
    float* out = &building_[static_cast<std::size_t>(3 * buildingCount_++)];
    for (int k = 0; k < 3; ++k) out[k] = static_cast<float>(p[k]);
  }
  if (nextRay_ < total) return;
  std::swap(building_, ready_);
  readyCount_ = buildingCount_;
  readyTime_ = t;
  readyOrigin_ = origin;
  readyNew_ = true;
  buildingCount_ = 0;
  nextRay_ = 0;
  scanStart_ += scanPeriod_;
}

bool RollingLidar::take(backend::PointCloudView& view) {
  if (!readyNew_) return false;
  readyNew_ = false;
  view.xyz = ready_.data();
  view.count = readyCount_;
  view.time = readyTime_;
  for (int k = 0; k < 3; ++k) view.sensor_origin[k] = readyOrigin_[k];
  return true;
}

}  // namespace ballast::simbody
