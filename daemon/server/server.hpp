// The IO side of ballastd: the Unix socket, its clients, the command lease, signals.
//
// One thread (ballastd's main thread) runs Server::run(): a poll() loop over the listening
// socket, the clients, a signalfd (SIGTERM/SIGINT: stop; SIGHUP: reload the profile) and the
// control loop's eventfd (replies and log events waiting). Requests are validated against the
// protocol table (protocol.hpp: verb -> fields) and dispatched through the server's table of
// handlers (verb -> handler, verbs.cpp; a test holds the two tables to each other). Commands for
// the robot go to the loop through its command ring and are answered when the loop has handled
// them (or with `timeout` after the profile's reply timeout). Nothing here can hold the loop up:
// the loop only ever pushes into rings and publishes its status through a seqlock.
//
// By concern: transport.cpp (socket, clients, lines, signals), leases.cpp, verbs.cpp (the
// handlers' table and the robot's commands), map_verbs.cpp (the terrain map; a map load reads
// on a thread of its own), watch.cpp (status), profile_switch.cpp.
//
// Security: the socket file is created mode 0660 in a directory ballastd creates 0750 if
// missing; each connecting peer's uid (SO_PEERCRED) must be ballastd's own or listed in
// server.allowed_uids. Motion commands need the command lease (one holder at a time, a random
// token); `estop` never does.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "control/control_loop.hpp"
#include "control/mpc_planner.hpp"
#include "control/telemetry.hpp"
#include "profile/profile.hpp"
#include "profile/settings.hpp"
#include "server/protocol.hpp"
#include "server/server_config.hpp"
#include "server/status_json.hpp"
#include "server/terrain_map.hpp"

namespace ballast::server {

/// The server's settings from a profile's; socket_override (from --socket) wins if not empty,
/// then the profile's socket, then the default path.
ServerConfig serverConfig(const profile::Settings& settings, const std::string& socket_override);
inline ServerConfig serverConfig(const profile::Profile& profile, const std::string& socket_override) {
  return serverConfig(profile::readSettings(profile), socket_override);
}

/// What the server reaches into. Owned by ballastd's main().
struct DaemonContext {
  const model::Model* model = nullptr;
  control::ControlLoop* loop = nullptr;
  control::MpcPlanner* planner = nullptr;  ///< gets a profile switch's settings, and terrain maps
  control::TelemetryWriter* writer = nullptr;
  std::unique_ptr<profile::Profile> profile;  ///< the running profile
  control::SettingsPtr settings;              ///< the loop's
  control::SettingsKeeper keeper;             ///< every settings the loop may hold
  std::vector<std::string> profile_dirs;
  std::string backend_name;
  bool simulation = false;
  TerrainMap map;  ///< the file map last loaded (`map load`, terrain.map), if any
  /// The live map the planner plans on: seeded from `map`, fed the lidar's scans (set before
  /// the server runs).
  control::TerrainMapper* mapper = nullptr;
};

class Server {
 public:
  Server(DaemonContext& context, ServerConfig config);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  /// Creates the socket (and its directory). Throws std::runtime_error saying what is wrong:
  /// another ballastd answers on the path, the directory cannot be made, bind fails.
  void open();
  /// Serves until SIGTERM/SIGINT (signals must be blocked in every thread beforehand).
  void run();
  /// Closes every connection and removes the socket file.
  void close();

  const ServerConfig& config() const { return config_; }

  /// The verbs the server has a handler for (a test holds them to protocol::kCommands).
  static std::vector<std::string> handledVerbs();

 private:
  struct Client {
    int fd = -1;
    uid_t uid = 0;
    pid_t pid = 0;
    std::string name;  // from the "client" field
    std::string in, out;
    bool discarding = false;  // skipping the rest of an overlong line
    double watch_rate = 0.0;
    bool watch_joints = false;
    std::chrono::steady_clock::time_point next_watch;
  };
  /// A request that passed the protocol table: its command, id and fields.
  struct Request {
    const protocol::Command& command;
    nlohmann::json id;
    const nlohmann::json& fields;

    double number(const char* field, double fallback) const {
      return fields.contains(field) ? fields[field].get<double>() : fallback;
    }
    bool flag(const char* field) const { return fields.value(field, false); }
    std::string text(const char* field) const { return fields.value(field, std::string()); }
  };
  /// A command sent to the loop, waiting for its reply.
  struct Pending {
    int client = -1;
    nlohmann::json id;
    std::string cmd;
    std::chrono::steady_clock::time_point deadline;
    bool answered = false;
    std::unique_ptr<profile::Profile> profile;  // profile_use: the profile being switched to
    control::SettingsPtr settings;              // ... and its settings
    std::uint64_t generation = 0;               // ... the loop's settings generation once taken
    ServerConfig config;                        // ... and its server section
    std::unique_ptr<TerrainMap> map;  // ... and its terrain map, when it names another one
  };
  /// A `map load` under way on its own thread (map_verbs.cpp).
  struct MapLoad {
    int client = -1;  // -1 once the client is gone
    nlohmann::json id;
    std::string path;
    TerrainMap map;              // the thread's until it signals
    const char* code = nullptr;  // the refusal's error code, or nullptr
    std::string error;
    std::thread thread;
  };
  struct Lease {
    std::string token;
    uid_t uid = 0;
    pid_t pid = 0;
    std::string client;
    std::chrono::steady_clock::time_point since, last_used;
  };
  /// A verb of protocol::kCommands and its handler (verbs.cpp).
  struct Verb {
    const char* name;
    void (Server::*handle)(Client&, const Request&);
  };
  static const std::vector<Verb>& verbs();

  // transport.cpp: the socket, its clients, their lines, signals
  void accept();
  void readFrom(Client& c);
  void handleLine(Client& c, const std::string& line);
  void onSignal();
  void reply(int client, const nlohmann::json& id, nlohmann::json body);
  void fail(int client, const nlohmann::json& id, const char* code, const std::string& message);
  void send(Client& c, const std::string& text);
  void flush(Client& c);
  void drop(int fd);

  // leases.cpp
  bool checkLease(Client& c, const nlohmann::json& id, const std::string& token);
  nlohmann::json leaseJson() const;
  bool leaseExpired() const;
  void leaseAcquire(Client& c, const Request& r);
  void leaseTake(Client& c, const Request& r);
  void leaseReturn(Client& c, const Request& r);
  void grantLease(Client& c, const Request& r, bool take);

  // verbs.cpp: the robot's commands (through the loop's ring), telemetry
  void version(Client& c, const Request& r);
  void stand(Client& c, const Request& r);
  void walk(Client& c, const Request& r);
  void pose(Client& c, const Request& r);
  void stop(Client& c, const Request& r);
  void estop(Client& c, const Request& r);
  void reset(Client& c, const Request& r);
  void passive(Client& c, const Request& r);
  void push(Client& c, const Request& r);
  void advance(Client& c, const Request& r);
  // map_verbs.cpp: the terrain map
  void mapLoad(Client& c, const Request& r);
  void mapInfo(Client& c, const Request& r);
  void mapClear(Client& c, const Request& r);
  void mapSave(Client& c, const Request& r);
  /// {"map": the file map's info or null, "live": the live map's, "loading": the file a map
  /// load is reading, if any}.
  nlohmann::json mapReply();
  /// The map load's thread is done (its eventfd is readable): the map in use, and the reply.
  void finishMapLoad();
  /// Shutting down: waits for a map load's thread (its reply goes nowhere).
  void waitForMapLoad();
  void recordStart(Client& c, const Request& r);
  void recordStop(Client& c, const Request& r);
  /// Sends `command` to the loop; the reply goes to the client when the loop answers.
  void submit(Client& c, const Request& r, control::OperatorCommand command);
  /// Queues a command in the loop's ring and notes it pending (false: the ring is full).
  Pending* enqueue(control::OperatorCommand& command);
  void onLoopReplies();
  /// Writes the loop's events (log lines) that wait in its ring to the log.
  void logLoopEvents();
  void expirePending();

  // watch.cpp: status now and as a stream
  void statusVerb(Client& c, const Request& r);
  void watch(Client& c, const Request& r);
  void unwatch(Client& c, const Request& r);
  nlohmann::json status(bool joints);
  void sendWatches();

  // profile_switch.cpp
  void profileList(Client& c, const Request& r);
  void profileShow(Client& c, const Request& r);
  void profileUse(Client& c, const Request& r);
  /// Validates a profile and hands its settings to the loop. c: the client that asked (nullptr
  /// for SIGHUP's reload).
  void switchProfile(Client* c, const nlohmann::json& id, const std::string& name);
  /// A profile switch the loop took (applied) or refused.
  void finishSwitch(Pending& p, bool applied, const char* message);
  std::vector<std::string> profileDirs() const;

  DaemonContext& ctx_;
  ServerConfig config_;
  int listen_fd_ = -1, signal_fd_ = -1;
  bool stop_ = false;
  std::map<int, Client> clients_;
  std::map<std::uint64_t, Pending> pending_;
  std::uint64_t sequence_ = 0;
  std::unique_ptr<Lease> lease_;
  std::unique_ptr<MapLoad> map_load_;
  int map_load_fd_ = -1;  // eventfd: the map load's thread is done
  StatusExtras extras_;
};

}  // namespace ballast::server
