// The MuJoCo simulation backend: plugins/backend_abi.hpp implemented on MujocoWorld (MuJoCo
// 2.2.2, Debian's libmujoco-dev). Built as build/lib/ballast/libballast_backend_mujoco.so (entry
// symbol ballast_backend_entry); ballastd loads it with backend::Plugin::load("mujoco") when a
// profile says `backend: {name: mujoco}` (profiles/sim-flat-mujoco.yaml).
//
// It behaves as the simbody backend does (plugins/simbody/simbody_backend.hpp), with a second
// contact model: a controller that walks on both is not tuned to one simulator. Same ABI use,
// same orders, same per-tick behaviour, same profile keys where they mean the same thing
// (mujoco_settings.hpp), the same sensor model, lidar sweep and terrain columns
// (plugins/common), the same initial posture:
//
//   config.section_yaml = "friction: 0.9\nmotor_latency_ticks: 1\n";  // see mujoco_settings.hpp
//   ... exactly as for simbody (Config, read / write / advance per tick) ...
//
// Orders: joints are the URDF's movable joints in file order (capabilities().joint_names;
// Commands and Sensors use it); contacts (Truth::contact_force, Truth::contact) follow
// Config::contact_frames. Truth::contact[i] means contact point i's spheres carried load in the
// last MuJoCo step, Truth::non_foot_contact that any other body touched the terrain.
//
// start() puts the robot at rest in its initial posture (mujoco_settings.hpp: initial_*; by
// default standing with its soles on the terrain at the origin, facing +x) with the motors off:
// the first read() gives the posture to hold. Every call comes from one thread (the control
// loop's); a Backend instance is not shared.
//
// Per tick: write() validates and queues the commands; advance() applies the commands due
// (written motor_latency_ticks ticks ago; motors keep the last command if none is due, and are
// off until the first arrives), steps MuJoCo one period (`substeps` steps, the motor model in
// each), advances the lidar sweep (mj_ray on the terrain) and samples the sensors once. read()
// copies that sample. In real time (Config::lockstep false) advance() then sleeps to an absolute
// deadline (plugins/common/tick_pacer.hpp) and reports the tick's lateness; after a stall the
// schedule skips the periods gone and the next advance() simulates them with the motors holding
// their last command, so simulated time stays wall time. The simulation's own computing beyond
// half a period pauses the schedule instead (the world waits; simulated time falls behind the
// wall for a moment), as in the Simbody backend. host_* keys inject host delays (a
// stall, jitter) before the pacing. Lockstep runs repeat bit for bit for a seed (MuJoCo steps
// on one thread; every random draw is seeded).
// Bad commands (wrong joint count, NaN/inf, negative gains) return kFault and are ignored (the
// motors keep the previous ones). A failed or diverged simulation returns kFault from then on.
// read(), write() and advance() do not allocate (MuJoCo works in its preallocated mjData).
#pragma once

#include <cstdint>
#include <ctime>
#include <memory>
#include <vector>

#include "backend_abi.hpp"
#include "host_delays.hpp"    // plugins/common
#include "rolling_lidar.hpp"  // plugins/common
#include "sensor_model.hpp"   // plugins/common
#include "mujoco_settings.hpp"
#include "mujoco_world.hpp"
#include "tick_pacer.hpp"     // plugins/common

namespace ballast::mujoco {

class MujocoBackend final : public backend::Backend {
 public:
  bool configure(const backend::Config& config, backend::Error& error) override;
  const backend::Capabilities& capabilities() const override { return caps_; }
  bool start(backend::Error& error) override;
  backend::Status read(backend::Sensors& sensors) override;
  backend::Status write(const backend::Commands& commands) override;
  backend::Status advance(backend::TickTiming& timing) override;
  using backend::Backend::advance;
  const backend::Error& lastError() const override { return lastError_; }
  void stop() override;
  bool push(const backend::Push& push, backend::Error& error) override;
  bool lidarScan(backend::PointCloudView& scan) override;

  // Not part of the ABI: for tests and benchmarks that link the backend directly.
  MujocoWorld& world() { return *world_; }
  const MujocoSettings& settings() const { return settings_; }
  std::uint64_t lateTicks() const { return pacer_.lateTicks(); }
  std::uint64_t ticks() const { return tick_; }

 private:
  backend::Status fault(const char* message);
  void sampleSensors();
  void scanLidar();

  backend::Capabilities caps_;
  backend::Error lastError_;
  MujocoSettings settings_;
  std::unique_ptr<MujocoWorld> world_;
  plugin::SensorModel sensors_;
  plugin::RollingLidar lidar_;
  bool lidarEnabled_ = false;
  double period_ = 0.001;
  bool lockstep_ = true;
  bool started_ = false, faulted_ = false;

  // Commands in flight: slot k % size holds what was written during tick k.
  struct QueuedCommands {
    std::int64_t tick = -1;
    backend::JointCommand joint[backend::kMaxJoints];
  };
  std::vector<QueuedCommands> queue_;

  std::uint64_t tick_ = 0;  ///< advances since start()
  backend::Sensors sample_;
  std::uint64_t lastReadSequence_ = 0;
  plugin::TickPacer pacer_;
  plugin::HostDelays host_;
};

}  // namespace ballast::mujoco
