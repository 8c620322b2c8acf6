// The Simbody simulation backend: plugins/backend_abi.hpp implemented on SimbodyWorld.
// Built as build/lib/ballast/libballast_backend_simbody.so (entry symbol ballast_backend_entry);
// ballastd loads it with backend::Plugin::load("simbody").
//
// Using it (the daemon does exactly this; tests and benchmarks too):
//
//   auto plugin = ballast::backend::Plugin::load("simbody");
//   ballast::backend::BackendPtr sim = plugin->create();
//   const char* contacts[] = {"left_toe", "left_heel", "right_toe", "right_heel"};
//   ballast::backend::Config config;
//   config.section_yaml = "friction: 0.9\nmotor_latency_ticks: 1\n";  // see sim_settings.hpp
//   config.section_origin = "profiles/sim-flat.yaml:40";
//   config.urdf_path = "urdf/humanoid.urdf";
//   config.terrain_map = "";            // flat floor; or an OctoMap .bt/.ot
//   config.contact_frames = contacts;
//   config.num_contacts = 4;
//   config.period = 0.001;
//   config.lockstep = true;             // advance() = one period of simulation, no sleeping
//   config.seed = 42;
//   ballast::backend::Error error;
//   if (!sim->configure(config, error) || !sim->start(error)) die(error.message);
//   for (;;) {                          // one control tick
//     sim->read(sensors);               // kOk, or kStale if nothing new since the last read
//     ... controller ...
//     sim->write(commands);             // per joint tau_ff, q_des, dq_des, kp, kd
//     sim->advance(timing);             // kFault (see lastError()); real time: how late, skipped
//   }
//
// Orders: joints are the URDF's movable joints in file order (capabilities().joint_names;
// Commands and Sensors use it); contacts (Truth::contact_force, Truth::contact) follow
// Config::contact_frames. Truth is filled (Sensors::has_truth) for diagnostics and scoring;
// Truth::contact[i] means contact point i's spheres carry load, Truth::non_foot_contact that any
// other body touches the terrain.
//
// start() puts the robot at rest in its initial posture (sim_settings.hpp: initial_*; by
// default standing with its soles on the terrain at the origin, facing +x) with the motors off:
// the first read() gives the posture to hold. Every call comes from one thread (the control
// loop's); a Backend instance is not shared.
//
// Per tick: write() validates and queues the commands; advance() applies the commands due
// (written motor_latency_ticks ticks ago; motors keep the last command if none is due, and are
// off until the first arrives), integrates one period, advances the lidar sweep and samples the
// sensors once. read() copies that sample. In real time (Config::lockstep false) advance() then
// sleeps to an absolute deadline (plugins/common/tick_pacer.hpp: the first advance() + k periods,
// clock_nanosleep on CLOCK_MONOTONIC) and reports the tick's lateness; after a stall the
// schedule skips the periods gone and the next advance() simulates them with the motors holding
// their last command, so simulated time stays wall time, as the world does for a real robot.
// The simulation's own computing beyond half a period pauses the schedule instead (the world
// waits; simulated time falls behind the wall for a moment): a slow integrator step is the
// simulator's, not the controller's, and must not look like a stalled host.
// host_* keys inject host delays (a stall, jitter) before the pacing, to test the daemon's
// deadline policy. The simulation itself runs at about 7-10x real time (test/bench/sim), so
// the controller has most of each period.
// Bad commands (wrong joint count, NaN/inf, negative gains) return kFault and are ignored (the
// motors keep the previous ones). A failed or diverged simulation returns kFault from then on.
// read() and write() never allocate; advance() allocates inside Simbody's integrator.
#pragma once

#include <cstdint>
#include <ctime>
#include <memory>
#include <string>
#include <vector>

#include "backend_abi.hpp"
#include "simulation_backend.hpp"  // plugins/common
#include "sim_settings.hpp"
#include "simbody_world.hpp"

namespace ballast::simbody {

class SimbodyBackend final : public plugin::SimulationBackend<SimbodyBackend, SimbodyWorld> {
 public:
  SimbodyBackend() : SimulationBackend("simbody") {}
  // Not part of the ABI: for tests and benchmarks that link the backend directly.
  const SimSettings& settings() const { return settings_; }

 private:
  friend class plugin::SimulationBackend<SimbodyBackend, SimbodyWorld>;  // its per-tick hooks
  void makeWorld(const backend::Config& config);
  std::string configuredMessage() const;
  void sampleSensors();
  void scanLidar();

  SimSettings settings_;
};

}  // namespace ballast::simbody
