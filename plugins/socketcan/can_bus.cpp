#include "can_bus.hpp"

#include <fcntl.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace ballast::socketcan {

CanBus::CanBus(CanBus&& o) noexcept
    : fd_(o.fd_), name_(std::move(o.name_)), emulated_(o.emulated_), errno_(o.errno_) {
  o.fd_ = -1;
}

CanBus& CanBus::operator=(CanBus&& o) noexcept {
  if (this != &o) {
    close();
    fd_ = o.fd_;
    name_ = std::move(o.name_);
    emulated_ = o.emulated_;
    errno_ = o.errno_;
    o.fd_ = -1;
  }
  return *this;
}

void CanBus::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

bool CanBus::open(const std::string& spec, std::string& error) {
  close();
  name_ = spec;
  auto failed = [&](const std::string& what) {
    error = "bus " + spec + ": " + what + ": " + std::strerror(errno);
    close();
    return false;
  };
  if (spec.rfind("fd:", 0) == 0) {
    char* end = nullptr;
    const long fd = std::strtol(spec.c_str() + 3, &end, 10);
    if (end == spec.c_str() + 3 || *end != '\0' || fd < 0) {
      error = "bus " + spec + ": expected fd:N with N an open file descriptor";
      return false;
    }
    int type = 0;
    socklen_t length = sizeof type;
    if (getsockopt(static_cast<int>(fd), SOL_SOCKET, SO_TYPE, &type, &length) != 0)
      return failed("not an open socket");
    if (type != SOCK_SEQPACKET && type != SOCK_DGRAM) {
      error = "bus " + spec + ": the socket must keep message boundaries (SOCK_SEQPACKET or "
              "SOCK_DGRAM), one struct can_frame per message";
      return false;
    }
    // A copy of its own: the bus closes what it opened, never the caller's descriptor.
    fd_ = fcntl(static_cast<int>(fd), F_DUPFD_CLOEXEC, 0);
    if (fd_ < 0) return failed("cannot duplicate the descriptor");
    emulated_ = true;
  } else {
    if (spec.empty() || spec.size() >= IFNAMSIZ) {
      error = "bus '" + spec + "': not an interface name (at most " + std::to_string(IFNAMSIZ - 1) +
              " characters) nor fd:N";
      return false;
    }
    fd_ = socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
    if (fd_ < 0) {
      const std::string hint = errno == EAFNOSUPPORT
                                   ? " (this kernel has no SocketCAN: load the can and can_raw "
                                     "modules, or use an emulated bus fd:N)"
                                   : "";
      error = "bus " + spec + ": cannot open a CAN socket: " + std::strerror(errno) + hint;
      fd_ = -1;
      return false;
    }
    ifreq ifr{};
    std::strncpy(ifr.ifr_name, spec.c_str(), IFNAMSIZ - 1);
    if (ioctl(fd_, SIOCGIFINDEX, &ifr) != 0) return failed("no such CAN interface (ip link show)");
    sockaddr_can addr{};
    addr.can_family = AF_CAN;
    addr.can_ifindex = ifr.ifr_ifindex;
    if (bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0)
      return failed("cannot bind to the interface");
    const can_err_mask_t errors = CAN_ERR_TX_TIMEOUT | CAN_ERR_BUSOFF | CAN_ERR_CRTL | CAN_ERR_ACK;
    setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &errors, sizeof errors);
    emulated_ = false;
  }
  const int flags = fcntl(fd_, F_GETFL);
  if (flags < 0 || fcntl(fd_, F_SETFL, flags | O_NONBLOCK) != 0) return failed("cannot make it non-blocking");
  errno_ = 0;
  return true;
}

bool CanBus::send(const can_frame& frame) {
  const ssize_t n = ::send(fd_, &frame, sizeof frame, MSG_NOSIGNAL | MSG_DONTWAIT);
  if (n == static_cast<ssize_t>(sizeof frame)) return true;
  errno_ = n < 0 ? errno : EMSGSIZE;
  return false;
}

bool CanBus::receive(can_frame& frame) {
  const ssize_t n = ::recv(fd_, &frame, sizeof frame, MSG_DONTWAIT);
  if (n == static_cast<ssize_t>(sizeof frame)) return true;
  errno_ = n < 0 ? (errno == EAGAIN || errno == EWOULDBLOCK ? 0 : errno) : (n == 0 ? EPIPE : EMSGSIZE);
  return false;
}

}  // namespace ballast::socketcan
