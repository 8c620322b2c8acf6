// An IMU on the CAN bus: three standard frames per sample from consecutive ids, the layout many
// CAN IMUs use (int16, little-endian, full scales below). ballast's emulators send it; a real
// IMU with another layout needs its own decoder here.
//
//   id base + 0: orientation quaternion w, x, y, z (world <- IMU), each int16 / 32767
//   id base + 1: angular velocity x, y, z (IMU frame), int16 over ±2000 °/s; uint16 counter
//   id base + 2: specific force x, y, z (IMU frame), int16 over ±16 g; uint16 counter
//
// A sample is complete when the angular velocity and specific force with the same counter, and
// an orientation frame since the last sample, have arrived (an IMU that stops sending its
// orientation stops completing samples: it never reports a stale attitude as new). Resolution: 1.1e-3 rad/s, 4.8e-3 m/s², 3e-5.
#pragma once

#include <linux/can.h>

#include <cstdint>

namespace ballast::socketcan {

inline constexpr double kGyroFullScale = 2000.0 * 3.14159265358979323846 / 180.0;  // rad/s
inline constexpr double kAccelFullScale = 16.0 * 9.80665;                           // m/s²

struct ImuSample {
  double orientation[4] = {0, 0, 0, 1};  ///< (x, y, z, w), as backend::Imu
  double angular_velocity[3] = {};
  double linear_acceleration[3] = {};
  std::uint16_t counter = 0;
};

/// The three frames of a sample.
void packImu(int baseId, const ImuSample& sample, can_frame (&frames)[3]);

/// Puts samples back together from frames (any order within a sample; a frame of another id is
/// ignored).
class ImuAssembler {
 public:
  explicit ImuAssembler(int baseId = 0x100) : base_(baseId) {}
  void setBaseId(int baseId) { base_ = baseId; }
  /// True if the frame is one of the IMU's (consumed); `completed` turns true when it completed
  /// a sample (then latest() is it).
  bool take(const can_frame& frame, bool& completed);
  const ImuSample& latest() const { return latest_; }
  /// Samples completed so far.
  std::uint64_t samples() const { return samples_; }

 private:
  int base_;
  ImuSample building_, latest_;
  bool haveGyro_ = false, haveAccel_ = false, haveOrientation_ = false;
  std::uint16_t gyroCounter_ = 0, accelCounter_ = 0;
  std::uint64_t samples_ = 0;
};

}  // namespace ballast::socketcan
