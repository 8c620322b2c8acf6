// The MIT ("mini cheetah") motor protocol on classic CAN, as the motor drivers that speak it
// (T-motor AK, CubeMars, the Cheetah drivers) define it: fixed-point values packed big-endian
// across 8-byte command and 6-byte reply frames, each over a per-motor range.
//
//   command (host -> motor, CAN id = motor id, 8 bytes):
//     position 16 bits | velocity 12 | kp 12 | kd 12 | feed-forward torque 12
//     byte: [p15..8][p7..0][v11..4][v3..0 kp11..8][kp7..0][kd11..4][kd3..0 t11..8][t7..0]
//   reply (motor -> host, CAN id = host id, 6 bytes):
//     motor id 8 | position 16 | velocity 12 | torque 12
//   or 8 bytes, from drivers that append two (the CubeMars AK firmwares, for one):
//     ... | byte 6: driver-specific (temperature), not read | byte 7: fault code, 0 = none
//   special commands (8 bytes): FF FF FF FF FF FF FF FC enter motor mode (enable),
//     ...FD exit motor mode (disable), ...FE set the current position as zero.
//     A motor answers each with a reply.
//
// Position, velocity and torque are symmetric ranges [-r, r]; kp and kd are [0, r]. A value
// outside its range is clamped before it is packed (the drivers' own conversion would wrap it).
// A command whose fields are all at their top would pack to the bytes of a special command (a
// zero command, even): its torque is then packed four steps lower.
// Conversions are the drivers' own: truncation when packing, x·span/(2^bits − 1) + min when
// unpacking, so a value packs to the code a real driver would read.
//
// Values are the motor's output shaft (gearbox included): rad, rad/s, N·m.
#pragma once

#include <linux/can.h>

#include <cstdint>

namespace ballast::socketcan {

struct MotorRanges {
  double position = 12.5;  ///< rad
  double velocity = 45.0;  ///< rad/s
  double torque = 18.0;    ///< N·m
  double kp = 500.0;       ///< N·m/rad
  double kd = 5.0;         ///< N·m·s/rad
};

struct MitCommand {
  double position = 0.0, velocity = 0.0, kp = 0.0, kd = 0.0, torque = 0.0;
};

struct MitReply {
  int motor = 0;
  double position = 0.0, velocity = 0.0, torque = 0.0;
  int length = 6;  ///< bytes: 6, or 8 with a fault code
  int fault = 0;   ///< the driver's fault code (8-byte replies), 0 = none
};

enum class MitSpecial : std::uint8_t { kEnable = 0xFC, kDisable = 0xFD, kZero = 0xFE };

/// Fixed point over [lo, hi] in `bits` bits, as the drivers do it (truncating; clamped first).
std::uint32_t packFixed(double x, double lo, double hi, int bits);
double unpackFixed(std::uint32_t code, double lo, double hi, int bits);

/// Packs a command for motor `id`; returns how many of its five values had to be clamped.
int packCommand(int id, const MitCommand& command, const MotorRanges& ranges, can_frame& frame);
/// The command in a frame (false if it is not one: wrong length, or a special command).
bool unpackCommand(const can_frame& frame, const MotorRanges& ranges, MitCommand& command);

void packSpecial(int id, MitSpecial which, can_frame& frame);
/// Which special command a frame is (false for anything else).
bool unpackSpecial(const can_frame& frame, MitSpecial& which);

void packReply(int hostId, const MitReply& reply, const MotorRanges& ranges, can_frame& frame);
/// A reply's motor id and values (false if the frame is not a reply to `hostId`).
bool unpackReply(const can_frame& frame, int hostId, const MotorRanges& ranges, MitReply& reply);
/// The motor id of a reply frame to `hostId`, or -1 (to find its ranges before unpacking).
int replyMotor(const can_frame& frame, int hostId);

}  // namespace ballast::socketcan
