// The IO side's hold on the ControlSettings it hands the control loop.
//
// Settings are values shared between threads as shared_ptr<const ControlSettings>. The command
// ring carries plain bytes, so a switch command carries a pointer to one of the keeper's handles
// (a shared_ptr the keeper owns); the loop copies it into its own shared_ptr and lets go of the
// one it ran before. Only the IO thread frees settings: the keeper keeps every handle until the
// loop has taken the command that carried it (LoopStatus::last_command) and nothing but the
// keeper holds the settings any more (use_count). So the loop never frees memory (its copy is
// never the last), and a reply the loop could not send (a full reply ring) leaks nothing.
#pragma once

#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

#include "control/settings.hpp"

namespace ballast::control {

class SettingsKeeper {
 public:
  /// Keeps `settings` for the command of this sequence (0: the loop's first settings); the
  /// returned handle goes in OperatorCommand::settings and lives until collect() frees it.
  const SettingsPtr* keep(SettingsPtr settings, std::uint64_t sequence) {
    entries_.push_back({std::make_unique<SettingsPtr>(std::move(settings)), sequence});
    return entries_.back().handle.get();
  }
  /// Lets go of a handle whose command never reached the loop (a full command ring).
  void drop(const SettingsPtr* handle) {
    entries_.erase(std::remove_if(entries_.begin(), entries_.end(),
                                  [&](const Entry& e) { return e.handle.get() == handle; }),
                   entries_.end());
  }
  /// Frees the settings nobody else holds, of commands the loop has taken (sequence <= taken).
  /// Returns how many. IO thread only.
  std::size_t collect(std::uint64_t taken) {
    const std::size_t before = entries_.size();
    entries_.erase(std::remove_if(entries_.begin(), entries_.end(),
                                  [&](const Entry& e) {
                                    return e.sequence <= taken && e.handle->use_count() == 1;
                                  }),
                   entries_.end());
    return before - entries_.size();
  }
  std::size_t held() const { return entries_.size(); }

 private:
  struct Entry {
    std::unique_ptr<SettingsPtr> handle;  // its address is what a command carries
    std::uint64_t sequence;
  };
  std::vector<Entry> entries_;
};

}  // namespace ballast::control
