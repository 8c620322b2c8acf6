// Every frame sent and received, as `candump -l` writes them, so can-utils replay and inspect
// them (`canplayer -I FILE`, `log2asc`):
//     (1700000000.123456) can0 001#FFFFFFFFFFFFFFFC
// The control thread only copies frames into a lock-free ring; a writer thread formats and
// writes them. A full ring drops frames and counts them (the loop never waits on the disk).
#pragma once

#include <linux/can.h>

#include <atomic>
#include <cstdio>
#include <ctime>
#include <string>
#include <thread>
#include <vector>

#include "spsc_ring.hpp"  // plugins/common

namespace ballast::socketcan {

class CandumpLog {
 public:
  CandumpLog() : ring_(8192) {}
  ~CandumpLog() { close(); }

  /// Opens (truncates) `path` and starts the writer; false with a message.
  bool open(const std::string& path, const std::vector<std::string>& busNames, std::string& error);
  void close();
  bool active() const { return file_ != nullptr; }

  /// Control thread: one frame on bus `bus` (an index into busNames). Never blocks.
  void record(int bus, const can_frame& frame);
  std::uint64_t dropped() const { return dropped_.load(std::memory_order_relaxed); }

  /// The candump line of a frame (without the newline).
  static std::string format(const timespec& stamp, const std::string& bus, const can_frame& frame);

 private:
  struct Entry {
    timespec stamp;
    int bus;
    can_frame frame;
  };
  void run();

  SpscRing<Entry> ring_;
  std::vector<std::string> buses_;
  std::FILE* file_ = nullptr;
  std::thread writer_;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> dropped_{0};
};

}  // namespace ballast::socketcan
