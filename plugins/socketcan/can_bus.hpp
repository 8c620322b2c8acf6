// One CAN bus, non-blocking: a raw SocketCAN socket bound to an interface ("can0", "vcan0"), or
// an already open socket that carries struct can_frame with message boundaries kept ("fd:N",
// e.g. one end of a socketpair(AF_UNIX, SOCK_SEQPACKET): an emulated bus, for tests and tools;
// the bus works on a duplicate, the caller's descriptor stays the caller's).
// The same read/write/poll code serves both.
#pragma once

#include <linux/can.h>

#include <string>

namespace ballast::socketcan {

class CanBus {
 public:
  CanBus() = default;
  ~CanBus() { close(); }
  CanBus(const CanBus&) = delete;
  CanBus& operator=(const CanBus&) = delete;
  CanBus(CanBus&& other) noexcept;
  CanBus& operator=(CanBus&& other) noexcept;

  /// Opens `spec` ("can0" or "fd:N"); false with a message naming the bus and what failed.
  bool open(const std::string& spec, std::string& error);
  void close();

  /// False when the frame could not be queued (errno in lastError(): EAGAIN/ENOBUFS when the
  /// transmit queue is full).
  bool send(const can_frame& frame);
  /// False when no frame is waiting (or on an error: lastError() != 0).
  bool receive(can_frame& frame);

  int fd() const { return fd_; }
  const std::string& name() const { return name_; }
  /// An emulated bus (fd:N): whatever plays the motors can be stepped, so lockstep works.
  bool emulated() const { return emulated_; }
  int lastError() const { return errno_; }

 private:
  int fd_ = -1;
  std::string name_;
  bool emulated_ = false;
  int errno_ = 0;
};

}  // namespace ballast::socketcan
