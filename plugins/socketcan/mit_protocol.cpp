#include "mit_protocol.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace ballast::socketcan {
namespace {

constexpr std::uint8_t kSpecialPrefix = 0xFF;

/// Clamps x into [lo, hi]; counts the clamp.
double clampCounted(double x, double lo, double hi, int& clamped) {
  if (x < lo || x > hi || std::isnan(x)) {
    ++clamped;
    return std::isnan(x) ? 0.0 : std::clamp(x, lo, hi);
  }
  return x;
}

}  // namespace

std::uint32_t packFixed(double x, double lo, double hi, int bits) {
  const double span = hi - lo;
  const double maxCode = static_cast<double>((1u << bits) - 1u);
  x = std::clamp(std::isnan(x) ? 0.0 : x, lo, hi);
  return static_cast<std::uint32_t>((x - lo) * maxCode / span);  // truncation, as the drivers
}

double unpackFixed(std::uint32_t code, double lo, double hi, int bits) {
  const double maxCode = static_cast<double>((1u << bits) - 1u);
  return static_cast<double>(code) * (hi - lo) / maxCode + lo;
}

int packCommand(int id, const MitCommand& c, const MotorRanges& r, can_frame& f) {
  int clamped = 0;
  const std::uint32_t p =
      packFixed(clampCounted(c.position, -r.position, r.position, clamped), -r.position, r.position, 16);
  const std::uint32_t v =
      packFixed(clampCounted(c.velocity, -r.velocity, r.velocity, clamped), -r.velocity, r.velocity, 12);
  const std::uint32_t kp = packFixed(clampCounted(c.kp, 0.0, r.kp, clamped), 0.0, r.kp, 12);
  const std::uint32_t kd = packFixed(clampCounted(c.kd, 0.0, r.kd, clamped), 0.0, r.kd, 12);
  const std::uint32_t t =
      packFixed(clampCounted(c.torque, -r.torque, r.torque, clamped), -r.torque, r.torque, 12);
  std::memset(&f, 0, sizeof f);
  f.can_id = static_cast<canid_t>(id);
  f.can_dlc = 8;
  f.data[0] = static_cast<std::uint8_t>(p >> 8);
  f.data[1] = static_cast<std::uint8_t>(p & 0xFF);
  f.data[2] = static_cast<std::uint8_t>(v >> 4);
  f.data[3] = static_cast<std::uint8_t>(((v & 0xF) << 4) | (kp >> 8));
  f.data[4] = static_cast<std::uint8_t>(kp & 0xFF);
  f.data[5] = static_cast<std::uint8_t>(kd >> 4);
  f.data[6] = static_cast<std::uint8_t>(((kd & 0xF) << 4) | (t >> 8));
  f.data[7] = static_cast<std::uint8_t>(t & 0xFF);
  MitSpecial special;
  if (unpackSpecial(f, special)) f.data[7] = 0xFB;  // never a special command by accident
  return clamped;
}

bool unpackCommand(const can_frame& f, const MotorRanges& r, MitCommand& c) {
  MitSpecial special;
  if (f.can_dlc != 8 || unpackSpecial(f, special)) return false;
  const std::uint32_t p = (std::uint32_t{f.data[0]} << 8) | f.data[1];
  const std::uint32_t v = (std::uint32_t{f.data[2]} << 4) | (f.data[3] >> 4);
  const std::uint32_t kp = ((std::uint32_t{f.data[3]} & 0xF) << 8) | f.data[4];
  const std::uint32_t kd = (std::uint32_t{f.data[5]} << 4) | (f.data[6] >> 4);
  const std::uint32_t t = ((std::uint32_t{f.data[6]} & 0xF) << 8) | f.data[7];
  c.position = unpackFixed(p, -r.position, r.position, 16);
  c.velocity = unpackFixed(v, -r.velocity, r.velocity, 12);
  c.kp = unpackFixed(kp, 0.0, r.kp, 12);
  c.kd = unpackFixed(kd, 0.0, r.kd, 12);
  c.torque = unpackFixed(t, -r.torque, r.torque, 12);
  return true;
}

void packSpecial(int id, MitSpecial which, can_frame& f) {
  std::memset(&f, 0, sizeof f);
  f.can_id = static_cast<canid_t>(id);
  f.can_dlc = 8;
  std::memset(f.data, kSpecialPrefix, 7);
  f.data[7] = static_cast<std::uint8_t>(which);
}

bool unpackSpecial(const can_frame& f, MitSpecial& which) {
  if (f.can_dlc != 8) return false;
  for (int i = 0; i < 7; ++i)
    if (f.data[i] != kSpecialPrefix) return false;
  if (f.data[7] < 0xFC || f.data[7] > 0xFE) return false;
  which = static_cast<MitSpecial>(f.data[7]);
  return true;
}

void packReply(int hostId, const MitReply& m, const MotorRanges& r, can_frame& f) {
  const std::uint32_t p = packFixed(m.position, -r.position, r.position, 16);
  const std::uint32_t v = packFixed(m.velocity, -r.velocity, r.velocity, 12);
  const std::uint32_t t = packFixed(m.torque, -r.torque, r.torque, 12);
  std::memset(&f, 0, sizeof f);
  f.can_id = static_cast<canid_t>(hostId);
  f.can_dlc = m.length == 8 ? 8 : 6;
  f.data[0] = static_cast<std::uint8_t>(m.motor);
  f.data[1] = static_cast<std::uint8_t>(p >> 8);
  f.data[2] = static_cast<std::uint8_t>(p & 0xFF);
  f.data[3] = static_cast<std::uint8_t>(v >> 4);
  f.data[4] = static_cast<std::uint8_t>(((v & 0xF) << 4) | (t >> 8));
  f.data[5] = static_cast<std::uint8_t>(t & 0xFF);
  if (f.can_dlc == 8) f.data[7] = static_cast<std::uint8_t>(m.fault);
}

int replyMotor(const can_frame& f, int hostId) {
  if ((f.can_id & CAN_EFF_FLAG) || (f.can_id & CAN_RTR_FLAG) || (f.can_id & CAN_ERR_FLAG))
    return -1;
  if (static_cast<int>(f.can_id & CAN_SFF_MASK) != hostId || f.can_dlc < 6) return -1;
  return f.data[0];
}

bool unpackReply(const can_frame& f, int hostId, const MotorRanges& r, MitReply& m) {
  const int motor = replyMotor(f, hostId);
  if (motor < 0) return false;
  const std::uint32_t p = (std::uint32_t{f.data[1]} << 8) | f.data[2];
  const std::uint32_t v = (std::uint32_t{f.data[3]} << 4) | (f.data[4] >> 4);
  const std::uint32_t t = ((std::uint32_t{f.data[4]} & 0xF) << 8) | f.data[5];
  m.motor = motor;
  m.position = unpackFixed(p, -r.position, r.position, 16);
  m.velocity = unpackFixed(v, -r.velocity, r.velocity, 12);
  m.torque = unpackFixed(t, -r.torque, r.torque, 12);
  m.length = f.can_dlc >= 8 ? 8 : 6;
  m.fault = f.can_dlc >= 8 ? f.data[7] : 0;
  return true;
}

}  // namespace ballast::socketcan
