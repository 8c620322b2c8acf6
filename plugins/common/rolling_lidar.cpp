#include "rolling_lidar.hpp"

#include <cstdio>
#include <cstring>

namespace ballast::plugin {

void RollingLidar::configure(const LidarSettings& s, std::uint64_t seed) {
  const int nh = s.horizontal_rays, nv = s.vertical_rays;
  const bool fullCircle = s.horizontal_fov >= 2 * M_PI - 1e-9;
  directions_.clear();
  directions_.reserve(static_cast<std::size_t>(3 * nh * nv));
  for (int i = 0; i < nh; ++i) {
    // A full circle has no duplicate ray at ±π; a sector includes both edges.
    const double azimuth =
        nh == 1 ? 0.0 : -s.horizontal_fov / 2 + s.horizontal_fov * i / (fullCircle ? nh : nh - 1);
    for (int j = 0; j < nv; ++j) {
      const double elevation =
          nv == 1 ? (s.vertical_min + s.vertical_max) / 2
                  : s.vertical_min + (s.vertical_max - s.vertical_min) * j / (nv - 1);
      directions_.push_back(std::cos(elevation) * std::cos(azimuth));
      directions_.push_back(std::cos(elevation) * std::sin(azimuth));
      directions_.push_back(std::sin(elevation));
    }
  }
  building_.assign(directions_.size(), 0.0f);
  ready_.assign(directions_.size(), 0.0f);
  scanPeriod_ = 1.0 / s.rate;
  minRange_ = s.min_range;
  maxRange_ = s.max_range;
  rangeNoise_ = s.range_noise;
  seed_ = seed;
  std::snprintf(link_, sizeof(link_), "%s", s.link.c_str());
  for (int k = 0; k < 3; ++k) offset_[k] = s.offset[k], rpy_[k] = s.rpy[k];
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

void RollingLidar::publish(double t, const double origin[3], const double R[9]) {
  // Into the sensor frame at the sweep's end: p_s = Rᵀ (p_w − origin).
  for (int i = 0; i < buildingCount_; ++i) {
    float* p = &building_[static_cast<std::size_t>(3 * i)];
    const double d[3] = {p[0] - origin[0], p[1] - origin[1], p[2] - origin[2]};
    for (int k = 0; k < 3; ++k)
      p[k] = static_cast<float>(R[k] * d[0] + R[3 + k] * d[1] + R[6 + k] * d[2]);
  }
  std::swap(building_, ready_);
  readyCount_ = buildingCount_;
  readyTime_ = t;
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
  view.frame = backend::ScanFrame::kSensor;
  std::memcpy(view.sensor_link, link_, sizeof(view.sensor_link));
  for (int k = 0; k < 3; ++k) {
    view.sensor_origin[k] = 0.0;
    view.sensor_offset[k] = offset_[k];
    view.sensor_rpy[k] = rpy_[k];
  }
  return true;
}

}  // namespace ballast::plugin
