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
#include <string>
#include <vector>

#include "backend_abi.hpp"
#include "simulation_backend.hpp"  // plugins/common
#include "mujoco_settings.hpp"
#include "mujoco_world.hpp"

namespace ballast::mujoco {

class MujocoBackend final : public plugin::SimulationBackend<MujocoBackend, MujocoWorld> {
 public:
  MujocoBackend() : SimulationBackend("mujoco") {}
  // Not part of the ABI: for tests and benchmarks that link the backend directly.
  const MujocoSettings& settings() const { return settings_; }

 private:
  friend class plugin::SimulationBackend<MujocoBackend, MujocoWorld>;  // its per-tick hooks
  void makeWorld(const backend::Config& config);
  std::string configuredMessage() const;
  void sampleSensors();
  void scanLidar();

  MujocoSettings settings_;
};

}  // namespace ballast::mujoco
