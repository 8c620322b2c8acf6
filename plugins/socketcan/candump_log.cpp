#include "candump_log.hpp"

#include <cerrno>
#include <chrono>
#include <cstring>

namespace ballast::socketcan {

bool CandumpLog::open(const std::string& path, const std::vector<std::string>& busNames,
                      std::string& error) {
  close();
  file_ = std::fopen(path.c_str(), "w");
  if (!file_) {
    error = "log " + path + ": cannot write it: " + std::strerror(errno);
    return false;
  }
  buses_ = busNames;
  stop_ = false;
  writer_ = std::thread([this] { run(); });
  return true;
}

void CandumpLog::close() {
  if (!file_) return;
  stop_ = true;
  if (writer_.joinable()) writer_.join();
  std::fclose(file_);
  file_ = nullptr;
}

void CandumpLog::record(int bus, const can_frame& frame) {
  if (!file_) return;
  Entry e;
  clock_gettime(CLOCK_REALTIME, &e.stamp);
  e.bus = bus;
  e.frame = frame;
  if (!ring_.tryPush(e)) dropped_.fetch_add(1, std::memory_order_relaxed);
}

std::string CandumpLog::format(const timespec& stamp, const std::string& bus, const can_frame& f) {
  char line[96];
  int n = std::snprintf(line, sizeof line, "(%lld.%06ld) %s ", static_cast<long long>(stamp.tv_sec),
                        stamp.tv_nsec / 1000, bus.c_str());
  if (f.can_id & (CAN_EFF_FLAG | CAN_ERR_FLAG))
    n += std::snprintf(line + n, sizeof line - static_cast<std::size_t>(n), "%08X#",
                       f.can_id & (CAN_EFF_MASK | CAN_ERR_FLAG));
  else
    n += std::snprintf(line + n, sizeof line - static_cast<std::size_t>(n), "%03X#",
                       f.can_id & CAN_SFF_MASK);
  if (f.can_id & CAN_RTR_FLAG) {
    std::snprintf(line + n, sizeof line - static_cast<std::size_t>(n), "R");
  } else {
    for (int i = 0; i < f.can_dlc && i < 8; ++i)
      n += std::snprintf(line + n, sizeof line - static_cast<std::size_t>(n), "%02X", f.data[i]);
  }
  return line;
}

void CandumpLog::run() {
  Entry e;
  for (;;) {
    bool any = false;
    while (ring_.tryPop(e)) {
      any = true;
      const std::string& bus =
          e.bus >= 0 && e.bus < static_cast<int>(buses_.size()) ? buses_[e.bus] : std::string("can?");
      std::fprintf(file_, "%s\n", format(e.stamp, bus, e.frame).c_str());
    }
    if (any) std::fflush(file_);
    if (stop_ && ring_.size() == 0) return;
    if (!any) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}

}  // namespace ballast::socketcan
