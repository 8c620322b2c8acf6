// The CLI's verbs and the protocol commands they send. Their help is the protocol table's doc
// (daemon/server/protocol.hpp), so `ballast --help`, ballastd(8) and the daemon say one thing.
#pragma once

#include "server/protocol.hpp"

namespace ballast::cli {

struct Verb {
  const char* words;    ///< as typed after `ballast`
  const char* command;  ///< the protocol command it sends
};

inline constexpr Verb kVerbs[] = {
    {"status", "status"},          {"status --watch", "watch"},
    {"stand", "stand"},            {"walk", "walk"},
    {"pose", "pose"},              {"stop", "stop"},
    {"estop", "estop"},            {"reset", "reset"},
    {"passive", "passive"},        {"push", "push"},
    {"profile list", "profile_list"}, {"profile show", "profile_show"},
    {"profile use", "profile_use"}, {"map load", "map_load"},
    {"map info", "map_info"},      {"map clear", "map_clear"},
    {"map save", "map_save"},      {"record start", "record_start"},
    {"record stop", "record_stop"}, {"lease acquire", "lease_acquire"},
    {"lease take", "lease_take"},  {"lease return", "lease_return"},
    {"advance", "advance"},
};

/// Commands no verb sends: the CLI prints its own version; leaving ends a watch.
inline constexpr const char* kNotSent[] = {"version", "unwatch"};

/// The help of a command's verb.
inline const char* help(const char* command) { return protocol::commandDoc(command); }

}  // namespace ballast::cli
