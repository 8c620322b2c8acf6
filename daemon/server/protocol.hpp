// The ballastd protocol, shared by the daemon (daemon/server) and its clients (cli/): header
// only, no daemon internals.
//
// JSON lines on a Unix stream socket. A request is one object on one line:
//     {"id": 7, "cmd": "walk", "vx": 0.5, "ttl": 2, "lease": "9f2c..."}
// and gets one reply line:
//     {"id": 7, "ok": true, ...}
//     {"id": 7, "ok": false, "error": {"code": "lease_held", "message": "..."}}
// `id` (a number or a string) is echoed; `lease` carries the command lease token; `client`
// names the client in status and lease messages. `watch` then streams
//     {"event": "status", "status": {...}}
// lines at the requested rate until `unwatch` or the connection closes.
//
// Every command and its fields are in kCommands below: the daemon validates requests against
// this table (unknown command or field, wrong type, out of range, missing field), and the CLI
// uses the same names. Bounds here are the protocol's; the profile's safety limits are checked
// again by the daemon (out_of_range).
#pragma once

#include <cstddef>
#include <cstdlib>
#include <string>

#include <unistd.h>

namespace ballast::protocol {

inline constexpr int kVersion = 1;

// Error codes: the "code" of an error reply.
inline constexpr const char* kBadJson = "bad_json";    // not a JSON object
inline constexpr const char* kTooLarge = "too_large";  // line over server.max_message_bytes
inline constexpr const char* kUnknownCommand = "unknown_command";
inline constexpr const char* kUnknownField = "unknown_field";
inline constexpr const char* kBadType = "bad_type";
inline constexpr const char* kOutOfRange = "out_of_range";
inline constexpr const char* kMissingField = "missing_field";
inline constexpr const char* kNoLease = "no_lease";         // motion command without the lease
inline constexpr const char* kLeaseHeld = "lease_held";     // another client holds it
inline constexpr const char* kRefused = "refused";          // not in this mode (message says why)
inline constexpr const char* kUnavailable = "unavailable";  // no such capability (planner, pushes)
inline constexpr const char* kNotFound = "not_found";       // profile, map or file
inline constexpr const char* kInvalidProfile = "invalid_profile";
inline constexpr const char* kIoError = "io_error";
inline constexpr const char* kBackendError = "backend_error";
inline constexpr const char* kBusy = "busy";        // try again shortly
inline constexpr const char* kTimeout = "timeout";  // the control loop did not answer
inline constexpr const char* kPermissionDenied = "permission_denied";  // uid not allowed
inline constexpr const char* kTooManyClients = "too_many_clients";
inline constexpr const char* kShuttingDown = "shutting_down";

/// kPath: a string holding an absolute path (the daemon's working directory is not the
/// client's, so a relative one would name another file).
enum class FieldType { kNumber, kInteger, kString, kPath, kBool, kVector3 };

struct Field {
  const char* name;
  FieldType type;
  double min, max;  ///< numbers, integers, each element of a vector
  bool required;
  const char* doc;
};

struct Command {
  const char* name;
  bool needs_lease;  ///< moves the robot or changes how it moves
  const Field* fields;
  std::size_t num_fields;
  const char* doc;
};

/// Fields every request may carry.
inline constexpr const char* kCommonFields[] = {"id", "cmd", "lease", "client"};

inline constexpr double kPi = 3.14159265358979323846;

inline constexpr Field kNoFields[] = {{"", FieldType::kBool, 0, 0, false, ""}};
inline constexpr Field kStatusFields[] = {
    {"joints", FieldType::kBool, 0, 0, false, "also report joint positions and torques"}};
inline constexpr Field kWatchFields[] = {
    {"rate", FieldType::kNumber, 0.1, 1000, false, "status lines per second (default 10)"},
    {"joints", FieldType::kBool, 0, 0, false, "also report joint positions and torques"}};
inline constexpr Field kWalkFields[] = {
    {"vx", FieldType::kNumber, -5, 5, false, "forward velocity, m/s"},
    {"vy", FieldType::kNumber, -5, 5, false, "sideways velocity (left), m/s"},
    {"yaw_rate", FieldType::kNumber, -10, 10, false, "turning rate (counter-clockwise), rad/s"},
    {"ttl", FieldType::kNumber, 0.001, 86400, false,
     "controller seconds the velocity holds (default: the profile's command ttl)"}};
inline constexpr Field kPoseFields[] = {
    {"height", FieldType::kNumber, 0, 5, false, "base height above the feet, m (default nominal)"},
    {"roll", FieldType::kNumber, -kPi, kPi, false, "rad"},
    {"pitch", FieldType::kNumber, -kPi, kPi, false, "rad"},
    {"yaw", FieldType::kNumber, -kPi, kPi, false, "rad"}};
inline constexpr Field kPushFields[] = {
    {"force", FieldType::kVector3, -1e4, 1e4, true, "[fx, fy, fz], N, world frame"},
    {"duration", FieldType::kNumber, 0.001, 60, true, "controller seconds"},
    {"body", FieldType::kString, 0, 0, false, "URDF link (default: the base)"}};
inline constexpr Field kAdvanceFields[] = {
    {"until", FieldType::kNumber, 0, 1e9, true, "controller time to run to, s"}};
inline constexpr Field kNameField[] = {
    {"name", FieldType::kString, 0, 0, true, "profile name or path"}};
inline constexpr Field kOptionalNameField[] = {
    {"name", FieldType::kString, 0, 0, false, "profile name or path (default: the running one)"}};
inline constexpr Field kPathField[] = {
    {"path", FieldType::kPath, 0, 0, true, "absolute path on the daemon's machine"}};

inline constexpr Command kCommands[] = {
    {"version", false, kNoFields, 0, "daemon and protocol version"},
    {"status", false, kStatusFields, 1, "the robot's state: one status object"},
    {"watch", false, kWatchFields, 2, "stream status lines at a rate ({\"event\":\"status\",...})"},
    {"unwatch", false, kNoFields, 0, "stop the stream"},
    {"stand", true, kNoFields, 0, "stand up (from passive), or stop walking and stand"},
    {"walk", true, kWalkFields, 4, "walk at a velocity for ttl controller seconds (needs the planner)"},
    {"pose", true, kPoseFields, 4, "standing base height and orientation (unset: nominal)"},
    {"stop", true, kNoFields, 0, "zero velocity, keep standing"},
    {"estop", false, kNoFields, 0, "damp every joint and latch until reset (anyone may)"},
    {"reset", true, kNoFields, 0, "clear faults and the estop latch (damp -> passive)"},
    {"passive", true, kNoFields, 0, "zero torque: the robot falls unless held"},
    {"push", true, kPushFields, 3, "push a body with an external force (simulation only)"},
    {"advance", true, kAdvanceFields, 1,
     "ballastd --hold: run the simulation to a controller time (replies at once)"},
    {"profile_list", false, kNoFields, 0, "profiles the daemon can switch to"},
    {"profile_show", false, kOptionalNameField, 1,
     "a profile, merged, with where each value comes from"},
    {"profile_use", true, kNameField, 1, "switch to a profile (validated first; gains blend)"},
    {"map_load", true, kPathField, 1, "load a terrain map (.bt, .ot): the live map starts from it"},
    {"map_info", false, kNoFields, 0, "the terrain map in use: the file loaded, the live map"},
    {"map_clear", true, kNoFields, 0, "forget the terrain: the live map starts empty (lidar only)"},
    {"map_save", false, kPathField, 1, "write the live map as an OctoMap file (.bt)"},
    {"record_start", false, kPathField, 1, "record telemetry at the control rate (FILE.blog binary, else text)"},
    {"record_stop", false, kNoFields, 0, "stop recording"},
    {"lease_acquire", false, kNoFields, 0, "take the free command lease (or renew yours)"},
    {"lease_take", false, kNoFields, 0, "take the command lease from whoever holds it"},
    {"lease_return", false, kNoFields, 0, "give the command lease back"},
};

inline const Command* findCommand(const std::string& name) {
  for (const Command& c : kCommands)
    if (name == c.name) return &c;
  return nullptr;
}

/// A command's one-line doc ("" for no such command): the CLI's help takes it from here.
inline const char* commandDoc(const std::string& name) {
  const Command* c = findCommand(name);
  return c ? c->doc : "";
}

/// A field's doc ("" if none).
inline const char* fieldDoc(const std::string& command, const std::string& field) {
  if (const Command* c = findCommand(command))
    for (std::size_t i = 0; i < c->num_fields; ++i)
      if (field == c->fields[i].name) return c->fields[i].doc;
  return "";
}

/// Every command on a line, "name field [optional]", a '*' when it needs the command lease, its
/// doc: the list in ballastd(8) (a test holds the man page to it).
inline std::string commandSynopsis() {
  std::string out;
  for (const Command& c : kCommands) {
    std::string use = c.name;
    for (std::size_t i = 0; i < c.num_fields; ++i)
      use += c.fields[i].required ? std::string(" ") + c.fields[i].name
                                  : std::string(" [") + c.fields[i].name + "]";
    if (use.size() < 35) use.resize(35, ' ');
    out += use + (c.needs_lease ? "* " : "  ") + c.doc + "\n";
  }
  return out;
}

inline const char* fieldTypeName(FieldType t) {
  switch (t) {
    case FieldType::kNumber:
      return "a number";
    case FieldType::kInteger:
      return "an integer";
    case FieldType::kString:
      return "a string";
    case FieldType::kPath:
      return "an absolute path";
    case FieldType::kBool:
      return "true or false";
    case FieldType::kVector3:
      return "a list of 3 numbers";
  }
  return "?";
}

/// The default socket: $XDG_RUNTIME_DIR/ballast/ballastd.sock, else
/// /tmp/ballast-<uid>/ballastd.sock.
inline std::string defaultSocketPath() {
  const char* runtime = std::getenv("XDG_RUNTIME_DIR");
  if (runtime && *runtime) return std::string(runtime) + "/ballast/ballastd.sock";
  return "/tmp/ballast-" + std::to_string(getuid()) + "/ballastd.sock";
}

/// Mode names as status reports them.
inline constexpr const char* kModes[] = {"passive", "stand-up", "stand", "walk", "damp", "recover"};

}  // namespace ballast::protocol
