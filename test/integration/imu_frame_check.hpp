// One check for every simulation backend: its IMU is where Config::imu_frame (the profile's
// robot.imu_frame) puts it, turned as it is turned, unless the backend's own section places it.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "backend/plugin_loader.hpp"

namespace ballast::test {

/// The IMU readings of a simulation of the humanoid, passive and pushed at a hand for 0.1 s
/// (it turns about every axis as it starts to fall), for `ticks` ticks: with Config::imu_frame
/// `imu` (null: none), the section `sectionYaml` (noise-free IMU added), and each tick's truth.
struct ImuRun {
  std::vector<backend::Imu> imu;
  std::vector<backend::Truth> truth;
};
inline ImuRun imuWhilePushed(const backend::Plugin& plugin, const backend::SensorFrame* imu,
                             const std::string& sectionYaml, int ticks) {
  backend::BackendPtr sim = plugin.create();
  const std::string urdf = std::string(BALLAST_SOURCE_DIR) + "/urdf/humanoid.urdf";
  const std::string section =
      sectionYaml + "imu: {gyro_noise_density: 0, accel_noise_density: 0}\nlidar: {enabled: false}\n";
  const char* const contacts[] = {"left_toe", "left_heel", "right_toe", "right_heel"};
  backend::Config config;
  config.section_yaml = section.c_str();
  config.section_origin = "imu_test.yaml:1";
  config.urdf_path = urdf.c_str();
  config.contact_frames = contacts;
  config.num_contacts = 4;
  config.imu_frame = imu;
  config.lockstep = true;
  backend::Error error;
  if (!sim->configure(config, error) || !sim->start(error))
    throw std::runtime_error(std::string(plugin.entry().name) + ": " + error.message);
  backend::Push push;
  std::snprintf(push.body, sizeof push.body, "left_hand");  // off the middle: it yaws too
  push.force[0] = 60, push.force[1] = 90;
  push.duration = 0.1;
  if (!sim->push(push, error)) throw std::runtime_error(error.message);
  backend::Commands passive;
  passive.num_joints = sim->capabilities().num_joints;
  ImuRun run;
  backend::Sensors s;
  for (int k = 0; k < ticks; ++k) {
    if (sim->write(passive) != backend::Status::kOk || sim->advance() != backend::Status::kOk ||
        sim->read(s) != backend::Status::kOk)
      throw std::runtime_error(sim->lastError().message);
    run.imu.push_back(s.imu);
    run.truth.push_back(s.truth);
  }
  return run;
}

/// a ⊗ b, quaternions (x, y, z, w).
inline std::array<double, 4> quaternionProduct(const double* a, const double* b) {
  return {a[3] * b[0] + b[3] * a[0] + a[1] * b[2] - a[2] * b[1],
          a[3] * b[1] + b[3] * a[1] + a[2] * b[0] - a[0] * b[2],
          a[3] * b[2] + b[3] * a[2] + a[0] * b[1] - a[1] * b[0],
          a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2]};
}

/// v in the frame of q (world <- frame): q⁻¹ v q.
inline std::array<double, 3> intoFrame(const double* q, const double* v) {
  const double qi[4] = {-q[0], -q[1], -q[2], q[3]};
  const double vq[4] = {v[0], v[1], v[2], 0.0};
  const std::array<double, 4> t = quaternionProduct(qi, vq);
  const std::array<double, 4> r = quaternionProduct(t.data(), q);
  return {r[0], r[1], r[2]};
}

/// An IMU on the base turned 90° about z reads the base's yaw rate as it is and its x, y rates
/// (and specific forces) swapped: (y, −x, z); its orientation is the base's turned by 90° about
/// z. The base's own reads the truth's rates in the base frame. A section's imu.frame wins.
inline void expectTheImuWhereConfigPutsIt(const backend::Plugin& plugin) {
  constexpr int kTicks = 300;
  backend::SensorFrame plain, turned;
  plain.link = turned.link = "pelvis";
  turned.rpy[2] = M_PI / 2;
  const ImuRun base = imuWhilePushed(plugin, &plain, "", kTicks);
  const ImuRun imu = imuWhilePushed(plugin, &turned, "", kTicks);
  const ImuRun own = imuWhilePushed(plugin, &turned, "imu: {frame: pelvis}\n", kTicks);
  const double s = std::sqrt(0.5), qz[4] = {0, 0, s, s};
  double largest[3] = {};
  for (int k = 0; k < kTicks; ++k) {
    const backend::Imu &b = base.imu[k], &t = imu.imu[k];
    const std::array<double, 3> w =
        intoFrame(base.truth[k].base_orientation, base.truth[k].base_angular_velocity);
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(b.angular_velocity[i], w[i], 1e-6) << "tick " << k << " axis " << i;
      EXPECT_EQ(own.imu[k].angular_velocity[i], b.angular_velocity[i]) << "tick " << k;
      largest[i] = std::max(largest[i], std::abs(b.angular_velocity[i]));
    }
    EXPECT_NEAR(t.angular_velocity[0], b.angular_velocity[1], 1e-9) << "tick " << k;
    EXPECT_NEAR(t.angular_velocity[1], -b.angular_velocity[0], 1e-9) << "tick " << k;
    EXPECT_NEAR(t.angular_velocity[2], b.angular_velocity[2], 1e-9) << "tick " << k;
    EXPECT_NEAR(t.linear_acceleration[0], b.linear_acceleration[1], 1e-6) << "tick " << k;
    EXPECT_NEAR(t.linear_acceleration[1], -b.linear_acceleration[0], 1e-6) << "tick " << k;
    EXPECT_NEAR(t.linear_acceleration[2], b.linear_acceleration[2], 1e-6) << "tick " << k;
    const std::array<double, 4> q = quaternionProduct(b.orientation, qz);
    const double sign = q[3] * t.orientation[3] < 0 ? -1.0 : 1.0;  // q and -q: one rotation
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(t.orientation[i], sign * q[i], 1e-9) << "tick " << k;
  }
  // The push turned the base about every axis (a test of something).
  for (int i = 0; i < 3; ++i) EXPECT_GT(largest[i], 0.05) << "axis " << i;
}

}  // namespace ballast::test
