// The planner's seat beside the control loop: its own thread, fed the latest estimated state
// and base command at planner.rate (controller time), answering with a PlannerOutput the loop
// picks up without waiting.
//
//   loop (1 kHz)  --post(PlannerInput) every 1/rate s-->  planner thread: plan()
//   loop          <--latest(PlannerOutput)-------------   (triple buffers, a semaphore wake-up)
//
// Real time: the loop never waits; the planner catches up with the newest input. Lockstep
// (synchronous): the loop waits for the answer to what it posted, so a run is deterministic
// and the planner keeps its rate in simulation time however long a solve takes in wall time.
// Until daemon/mpc exists no Planner is attached, the slot is empty and `walk` is refused.
#pragma once

#include <semaphore.h>

#include <atomic>
#include <thread>

#include "control/triple_buffer.hpp"
#include "control/types.hpp"

namespace ballast::control {

/// What the kino-dynamic MPC implements. plan() runs on the planner thread only.
class Planner {
 public:
  virtual ~Planner() = default;
  virtual void plan(const PlannerInput& input, PlannerOutput& output) = 0;
};

class PlannerSlot {
 public:
  /// Controller times this close count as equal (they are sums of periods, with rounding).
  static constexpr double kTimeTolerance = 1e-6;
  PlannerSlot() {
    sem_init(&wake_, 0, 0);
    sem_init(&answer_, 0, 0);
  }
  ~PlannerSlot();
  PlannerSlot(const PlannerSlot&) = delete;
  PlannerSlot& operator=(const PlannerSlot&) = delete;

  /// Attaches a planner and starts its thread (before the loop runs).
  void start(Planner* planner, double rate, bool synchronous);
  void stop();
  bool available() const { return planner_ != nullptr; }

  // Loop side.
  /// True when a new input is due at controller time t.
  bool due(double t) const { return available() && t + kTimeTolerance >= next_due_; }
  /// Posts an input (stamps its sequence) and, if synchronous, waits for the answer (at most
  /// timeout_s of wall time; false if it did not come).
  bool post(PlannerInput& input, double timeout_s = 2.0);
  /// The newest output, nullptr before the first one.
  const PlannerOutput* latest();

 private:
  void run();

  Planner* planner_ = nullptr;
  double period_ = 0.01;
  bool synchronous_ = false;
  double next_due_ = 0.0;
  std::uint64_t sequence_ = 0;
  bool have_output_ = false;
  TripleBuffer<PlannerInput> input_;
  TripleBuffer<PlannerOutput> output_;
  std::atomic<std::uint64_t> answered_{0};
  std::atomic<bool> stop_{false};
  sem_t wake_;
  sem_t answer_;  ///< posted with every answer (synchronous waits)
  std::thread thread_;
};

}  // namespace ballast::control
