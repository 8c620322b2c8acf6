#include "can_emulator.hpp"

#include <poll.h>
#include <sys/socket.h>

namespace ballast::socketcan {

int CanEmulator::addBus(int fd) {
  fds_.push_back(fd);
  return static_cast<int>(fds_.size()) - 1;
}

int CanEmulator::addMotor(int bus, int id, const MotorRanges& ranges) {
  Motor m;
  m.bus = bus;
  m.id = id;
  m.ranges = ranges;
  motors_.push_back(m);
  return static_cast<int>(motors_.size()) - 1;
}

void CanEmulator::reply(Motor& m) {
  if (m.silent) return;
  can_frame f;
  MitReply r;
  r.motor = m.id;
  r.position = m.position;
  r.velocity = m.velocity;
  r.torque = m.torque;
  r.length = m.fault != 0 ? 8 : 6;
  r.fault = m.fault;
  packReply(hostId_, r, m.ranges, f);
  send(fds_[static_cast<std::size_t>(m.bus)], &f, sizeof f, MSG_NOSIGNAL | MSG_DONTWAIT);
}

int CanEmulator::pump(int timeoutMs) {
  std::vector<pollfd> fds;
  for (int fd : fds_) fds.push_back(pollfd{fd, POLLIN, 0});
  if (poll(fds.data(), fds.size(), timeoutMs) <= 0) return 0;
  int handled = 0;
  can_frame f;
  for (std::size_t b = 0; b < fds_.size(); ++b) {
    while (recv(fds_[b], &f, sizeof f, MSG_DONTWAIT) == static_cast<ssize_t>(sizeof f)) {
      ++handled;
      Motor* target = nullptr;
      for (Motor& m : motors_)
        if (m.bus == static_cast<int>(b) && static_cast<canid_t>(m.id) == (f.can_id & CAN_SFF_MASK))
          target = &m;
      if (!target) {
        ++stray_;
        continue;
      }
      Motor& m = *target;
      if (m.silent) continue;
      MitSpecial special;
      if (unpackSpecial(f, special)) {
        if (special == MitSpecial::kEnable) m.enabled = true, ++m.enables;
        if (special == MitSpecial::kDisable) m.enabled = false, ++m.disables;
        if (special == MitSpecial::kZero) m.position = 0.0, ++m.zeroes;
        reply(m);
        continue;
      }
      if (unpackCommand(f, m.ranges, m.command)) {
        ++m.commands;
        // A motor out of motor mode ignores motion commands but still answers.
        if (m.enabled) m.commanded = true;
        else reply(m);
        continue;
      }
      ++stray_;
    }
  }
  return handled;
}

bool CanEmulator::allCommanded() const {
  for (const Motor& m : motors_)
    if (m.enabled && !m.silent && !m.commanded) return false;
  return true;
}

void CanEmulator::replyAll() {
  for (Motor& m : motors_)
    if (m.commanded) {
      m.commanded = false;
      reply(m);
    }
}

void CanEmulator::sendImu(const ImuSample& sample) {
  if (imuBus_ < 0) return;
  can_frame frames[3];
  packImu(imuBase_, sample, frames);
  for (const can_frame& f : frames)
    send(fds_[static_cast<std::size_t>(imuBus_)], &f, sizeof f, MSG_NOSIGNAL | MSG_DONTWAIT);
}

}  // namespace ballast::socketcan
