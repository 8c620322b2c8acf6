#include "imu_protocol.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace ballast::socketcan {
namespace {

std::int16_t toInt16(double x, double fullScale) {
  const double v = std::round(std::clamp(x / fullScale, -1.0, 1.0) * 32767.0);
  return static_cast<std::int16_t>(v);
}
double fromInt16(std::int16_t v, double fullScale) { return v / 32767.0 * fullScale; }

void put16(std::uint8_t* d, std::uint16_t v) {
  d[0] = static_cast<std::uint8_t>(v & 0xFF);
  d[1] = static_cast<std::uint8_t>(v >> 8);
}
std::uint16_t get16(const std::uint8_t* d) {
  return static_cast<std::uint16_t>(d[0] | (std::uint16_t{d[1]} << 8));
}

}  // namespace

void packImu(int baseId, const ImuSample& s, can_frame (&frames)[3]) {
  for (int i = 0; i < 3; ++i) {
    std::memset(&frames[i], 0, sizeof frames[i]);
    frames[i].can_id = static_cast<canid_t>(baseId + i);
    frames[i].can_dlc = 8;
  }
  const double wxyz[4] = {s.orientation[3], s.orientation[0], s.orientation[1], s.orientation[2]};
  for (int k = 0; k < 4; ++k)
    put16(frames[0].data + 2 * k, static_cast<std::uint16_t>(toInt16(wxyz[k], 1.0)));
  for (int k = 0; k < 3; ++k) {
    put16(frames[1].data + 2 * k,
          static_cast<std::uint16_t>(toInt16(s.angular_velocity[k], kGyroFullScale)));
    put16(frames[2].data + 2 * k,
          static_cast<std::uint16_t>(toInt16(s.linear_acceleration[k], kAccelFullScale)));
  }
  put16(frames[1].data + 6, s.counter);
  put16(frames[2].data + 6, s.counter);
}

bool ImuAssembler::take(const can_frame& f, bool& completed) {
  completed = false;
  if ((f.can_id & (CAN_EFF_FLAG | CAN_RTR_FLAG | CAN_ERR_FLAG)) || f.can_dlc != 8) return false;
  const int which = static_cast<int>(f.can_id & CAN_SFF_MASK) - base_;
  if (which < 0 || which > 2) return false;
  if (which == 0) {
    double wxyz[4];
    for (int k = 0; k < 4; ++k) wxyz[k] = fromInt16(static_cast<std::int16_t>(get16(f.data + 2 * k)), 1.0);
    const double n = std::sqrt(wxyz[0] * wxyz[0] + wxyz[1] * wxyz[1] + wxyz[2] * wxyz[2] + wxyz[3] * wxyz[3]);
    if (n < 0.5) return true;  // not a rotation: keep the last one
    building_.orientation[3] = wxyz[0] / n;
    for (int k = 0; k < 3; ++k) building_.orientation[k] = wxyz[k + 1] / n;
    haveOrientation_ = true;
  } else {
    const std::uint16_t counter = get16(f.data + 6);
    for (int k = 0; k < 3; ++k) {
      const auto v = static_cast<std::int16_t>(get16(f.data + 2 * k));
      if (which == 1)
        building_.angular_velocity[k] = fromInt16(v, kGyroFullScale);
      else
        building_.linear_acceleration[k] = fromInt16(v, kAccelFullScale);
    }
    if (which == 1) haveGyro_ = true, gyroCounter_ = counter;
    else haveAccel_ = true, accelCounter_ = counter;
  }
  if (haveGyro_ && haveAccel_ && haveOrientation_ && gyroCounter_ == accelCounter_) {
    building_.counter = gyroCounter_;
    latest_ = building_;
    haveGyro_ = haveAccel_ = haveOrientation_ = false;
    ++samples_;
    completed = true;
  }
  return true;
}

}  // namespace ballast::socketcan
