// The wire formats of the socketcan backend: MIT motor commands and replies (checked against
// the drivers' own fixed-point conversion), the IMU's frames, and candump's log line.
#include <gtest/gtest.h>

#include <cmath>

#include "candump_log.hpp"
#include "imu_protocol.hpp"
#include "mit_protocol.hpp"

namespace ballast::socketcan {
namespace {

TEST(MitProtocol, FixedPointIsTheDriversOwn) {
  // The drivers' float_to_uint: (int)((x - min) * (2^bits - 1) / span), truncating.
  EXPECT_EQ(packFixed(0.0, -12.5, 12.5, 16), 32767u);
  EXPECT_EQ(packFixed(-12.5, -12.5, 12.5, 16), 0u);
  EXPECT_EQ(packFixed(12.5, -12.5, 12.5, 16), 65535u);
  EXPECT_EQ(packFixed(1.0, -12.5, 12.5, 16), static_cast<std::uint32_t>(13.5 * 65535 / 25.0));
  EXPECT_EQ(packFixed(99.0, 0.0, 500.0, 12), 810u);  // 99 * 4095 / 500 = 810.8
  EXPECT_EQ(packFixed(1e9, -1, 1, 12), 4095u);  // clamped, never wrapped
  EXPECT_DOUBLE_EQ(unpackFixed(4095, -18, 18, 12), 18.0);
  EXPECT_DOUBLE_EQ(unpackFixed(0, -18, 18, 12), -18.0);
}

TEST(MitProtocol, CommandsRoundTripWithinOneStepOfTheirFields) {
  const MotorRanges r{12.5, 45, 90, 500, 5};
  const MitCommand c{0.7, -3.2, 120.0, 2.5, -41.0};
  can_frame f;
  EXPECT_EQ(packCommand(7, c, r, f), 0);
  EXPECT_EQ(f.can_id, 7u);
  EXPECT_EQ(f.can_dlc, 8);
  MitCommand back;
  ASSERT_TRUE(unpackCommand(f, r, back));
  EXPECT_NEAR(back.position, c.position, 25.0 / 65535);
  EXPECT_NEAR(back.velocity, c.velocity, 90.0 / 4095);
  EXPECT_NEAR(back.kp, c.kp, 500.0 / 4095);
  EXPECT_NEAR(back.kd, c.kd, 5.0 / 4095);
  EXPECT_NEAR(back.torque, c.torque, 180.0 / 4095);
  // The byte layout: position in bytes 0-1, kp's top nibble in byte 3, torque's low byte last.
  const std::uint32_t p = packFixed(0.7, -12.5, 12.5, 16), t = packFixed(-41, -90, 90, 12);
  EXPECT_EQ(f.data[0], p >> 8);
  EXPECT_EQ(f.data[1], p & 0xFF);
  EXPECT_EQ(f.data[7], t & 0xFF);
  EXPECT_EQ(f.data[6] & 0xF, t >> 8);
}

TEST(MitProtocol, OutOfRangeValuesAreClampedAndCounted) {
  const MotorRanges r{12.5, 45, 90, 500, 5};
  can_frame f;
  EXPECT_EQ(packCommand(1, MitCommand{20.0, 0.0, 600.0, 9.0, -400.0}, r, f), 4);
  MitCommand back;
  ASSERT_TRUE(unpackCommand(f, r, back));
  EXPECT_DOUBLE_EQ(back.position, 12.5);
  EXPECT_DOUBLE_EQ(back.kp, 500.0);
  EXPECT_DOUBLE_EQ(back.kd, 5.0);
  EXPECT_DOUBLE_EQ(back.torque, -90.0);
  EXPECT_EQ(packCommand(1, MitCommand{std::nan(""), 0, 0, 0, 0}, r, f), 1);  // NaN: 0, counted
  ASSERT_TRUE(unpackCommand(f, r, back));
  EXPECT_NEAR(back.position, 0.0, 25.0 / 65535);
}

TEST(MitProtocol, SpecialCommandsAndReplies) {
  can_frame f;
  packSpecial(3, MitSpecial::kEnable, f);
  EXPECT_EQ(f.can_id, 3u);
  for (int i = 0; i < 7; ++i) EXPECT_EQ(f.data[i], 0xFF);
  EXPECT_EQ(f.data[7], 0xFC);
  MitSpecial which;
  ASSERT_TRUE(unpackSpecial(f, which));
  EXPECT_EQ(which, MitSpecial::kEnable);
  MitCommand c;
  EXPECT_FALSE(unpackCommand(f, MotorRanges{}, c));  // a special command is not a motion one
  packSpecial(3, MitSpecial::kZero, f);
  ASSERT_TRUE(unpackSpecial(f, which));
  EXPECT_EQ(which, MitSpecial::kZero);

  const MotorRanges r{12.5, 45, 90, 500, 5};
  packReply(0, MitReply{9, -1.25, 7.5, 33.0}, r, f);
  EXPECT_EQ(f.can_id, 0u);
  EXPECT_EQ(f.can_dlc, 6);
  EXPECT_EQ(replyMotor(f, 0), 9);
  EXPECT_EQ(replyMotor(f, 1), -1);  // addressed to another host
  MitReply back;
  ASSERT_TRUE(unpackReply(f, 0, r, back));
  EXPECT_EQ(back.motor, 9);
  EXPECT_NEAR(back.position, -1.25, 25.0 / 65535);
  EXPECT_NEAR(back.velocity, 7.5, 90.0 / 4095);
  EXPECT_NEAR(back.torque, 33.0, 180.0 / 4095);
}

TEST(MitProtocol, ACommandNeverPacksToTheBytesOfASpecialOne) {
  // Every field at its top but the torque two steps below: FF FF FF FF FF FF FF FD, the bytes
  // of the disable command (FC..FE in the last byte: enable, disable, zero).
  const MotorRanges r{12.5, 45, 90, 500, 5};
  can_frame f;
  ASSERT_EQ(packFixed(89.93, -90, 90, 12), 0xFFDu);
  packCommand(1, MitCommand{12.5, 45, 500, 5, 89.93}, r, f);
  MitSpecial which;
  EXPECT_FALSE(unpackSpecial(f, which));
  EXPECT_EQ(f.data[7], 0xFB);
  MitCommand back;
  ASSERT_TRUE(unpackCommand(f, r, back));
  EXPECT_NEAR(back.torque, 90.0, 5 * 180.0 / 4095);
}

TEST(ImuProtocol, NoSampleWithoutAFreshOrientation) {
  ImuSample s;
  s.counter = 7;
  can_frame frames[3];
  packImu(0x100, s, frames);
  ImuAssembler assembler(0x100);
  bool completed = false;
  assembler.take(frames[1], completed);
  assembler.take(frames[2], completed);
  EXPECT_FALSE(completed);  // no orientation yet
  assembler.take(frames[0], completed);
  EXPECT_TRUE(completed);
  // The next sample's rates without its orientation frame: not a sample.
  s.counter = 8;
  packImu(0x100, s, frames);
  assembler.take(frames[1], completed);
  assembler.take(frames[2], completed);
  EXPECT_FALSE(completed);
  EXPECT_EQ(assembler.samples(), 1u);
}

TEST(ImuProtocol, SamplesRoundTripWithinTheirResolution) {
  ImuSample s;
  const double q[4] = {0.1, -0.2, 0.3, 0.927};  // x y z w, normalised below
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (int i = 0; i < 4; ++i) s.orientation[i] = q[i] / n;
  s.angular_velocity[0] = 0.5, s.angular_velocity[1] = -2.0, s.angular_velocity[2] = 0.01;
  s.linear_acceleration[0] = 0.3, s.linear_acceleration[1] = -0.1, s.linear_acceleration[2] = 9.81;
  s.counter = 4321;
  can_frame frames[3];
  packImu(0x100, s, frames);
  ImuAssembler assembler(0x100);
  bool completed = false;
  // Any order within a sample: the acceleration first, the orientation last.
  EXPECT_TRUE(assembler.take(frames[2], completed));
  EXPECT_FALSE(completed);
  EXPECT_TRUE(assembler.take(frames[0], completed));
  EXPECT_TRUE(assembler.take(frames[1], completed));
  EXPECT_TRUE(completed);
  const ImuSample& b = assembler.latest();
  EXPECT_EQ(b.counter, 4321);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(b.orientation[i], s.orientation[i], 1e-4);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(b.angular_velocity[i], s.angular_velocity[i], kGyroFullScale / 32767);
    EXPECT_NEAR(b.linear_acceleration[i], s.linear_acceleration[i], kAccelFullScale / 32767);
  }
  // A gyro frame and an acceleration frame of different samples do not make one.
  s.counter = 1;
  packImu(0x100, s, frames);
  can_frame other[3];
  s.counter = 2;
  packImu(0x100, s, other);
  assembler.take(frames[1], completed);
  assembler.take(other[2], completed);
  EXPECT_FALSE(completed);
  can_frame foreign = frames[0];
  foreign.can_id = 0x123;
  EXPECT_FALSE(assembler.take(foreign, completed));
  EXPECT_EQ(assembler.samples(), 1u);
}

TEST(CandumpLog, LinesAreCandumpsOwn) {
  can_frame f{};
  f.can_id = 0x1;
  f.can_dlc = 8;
  for (int i = 0; i < 7; ++i) f.data[i] = 0xFF;
  f.data[7] = 0xFC;
  const timespec t{1700000000, 123456789};
  EXPECT_EQ(CandumpLog::format(t, "can0", f), "(1700000000.123456) can0 001#FFFFFFFFFFFFFFFC");
  f.can_id = 0x12345678 | CAN_EFF_FLAG;
  f.can_dlc = 2;
  EXPECT_EQ(CandumpLog::format(t, "can1", f), "(1700000000.123456) can1 12345678#FFFF");
}

}  // namespace
}  // namespace ballast::socketcan
