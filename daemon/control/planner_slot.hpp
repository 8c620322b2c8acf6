// The planner's seat beside the control loop: its own thread, fed the latest estimated state
// and base command at planner.rate (controller time), answering with a PlannerOutput the loop
// picks up.
//
//   loop (1 kHz)  --post(PlannerInput) every 1/rate s-->  planner thread: plan()
//   loop          <--latest(t): PlannerOutput---------   (triple buffers, a semaphore wake-up)
//
// Real time: the loop never waits; it takes the newest answer when it arrives, however long
// the solve took. Lockstep (pipelined, deterministic): an input posted at controller time t_k is
// answered while the loop goes on ticking (the simulation on one core, the planner on the
// other), and its answer is taken at t_k + latency exactly (planner.latency: the delay a real
// solve has), waiting for it then if it is not there yet. Whatever the wall-clock speed of
// either thread, the loop sees the same plans at the same ticks, so a lockstep run with one seed
// is bit-for-bit repeatable. latency <= 1/rate: at most one input is in flight. Between an
// answer and the next input, whose time lockstep knows (1/rate later), the planner prepares
// for it (Planner::prepare): the ticks the loop runs meanwhile are the planner's idle time.
#pragma once

#include <semaphore.h>
#include <time.h>

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
  /// After an answer, while the thread waits: work ahead for an input expected at controller
  /// time t (it must not change that plan, only make it sooner). None by default.
  virtual void prepare(double /*t*/) {}
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

  /// Attaches a planner and starts its thread (before the loop runs). lockstep: answers are
  /// taken `latency` s of controller time after their input (see the header comment).
  /// priority > 0: the thread runs SCHED_FIFO at that priority (below the loop's), and so do
  /// the threads it starts (the MPC's workers): in real time a busy machine must not starve the
  /// plans (safety.max_plan_age). Where the system refuses, it runs at normal priority.
  void start(Planner* planner, double rate, bool lockstep, double latency, int priority = 0);
  void stop();
  /// Stops the thread and empties the seat (a planner may be started again).
  void detach();
  bool available() const { return planner_ != nullptr; }

  // Loop side.
  /// True when a new input is due at controller time t.
  bool due(double t) const { return available() && t + kTimeTolerance >= next_due_; }
  /// Lockstep: how long the loop waits for an answer before it says the planner is stuck, s of
  /// wall time. Generous, as simulated time waits for it: a solve is milliseconds, but a loaded
  /// host (2 cores shared by a build and a map read) has starved the planner thread for 2 s.
  static constexpr double kLockstepTimeout = 10.0;
  /// Posts an input (stamps its sequence). Real time: never waits. Lockstep: takes an answer
  /// still in flight first (false if it did not come within timeout_s of wall time).
  bool post(PlannerInput& input, double timeout_s = kLockstepTimeout);
  /// The output the loop uses at controller time t, nullptr before the first one: real time,
  /// the newest; lockstep, the answer to the input in flight once t reaches its time (waiting
  /// for it at most timeout_s of wall time: timed_out says it did not come).
  const PlannerOutput* latest(double t, bool& timed_out, double timeout_s = kLockstepTimeout);

  /// Where the planner thread is, for a fault's message (real time: a plan that does not come is
  /// a solve that computes too long, or a thread that does not run). Any thread; system calls,
  /// so not for every tick.
  struct Progress {
    bool solving = false;  ///< in plan() now
    double wall = 0.0;     ///< s since that solve began
    double cpu = 0.0;      ///< s of it the planner thread ran (its workers not counted)
  };
  Progress progress() const;

  /// Testing, real time (before start): the thread sleeps `duration` s in its first solve of an
  /// input from controller time `at` on, before the planner's own work (0: never).
  void injectStall(double at, double duration) {
    stall_at_ = at;
    stall_ = duration;
  }

 private:
  void run();

  Planner* planner_ = nullptr;
  double period_ = 0.01;
  bool lockstep_ = false;
  double latency_ = 0.0;
  int priority_ = 0;
  double stall_at_ = 0.0, stall_ = 0.0;  // injectStall; stall_ 0 once injected
  std::uint64_t in_flight_ = 0;  // lockstep: the sequence whose answer is awaited (0: none)
  double use_at_ = 0.0;          // ... and the controller time it is taken at
  double next_due_ = 0.0;
  std::uint64_t sequence_ = 0;
  bool have_output_ = false;
  TripleBuffer<PlannerInput> input_;
  TripleBuffer<PlannerOutput> output_;
  std::atomic<std::uint64_t> answered_{0};
  // The solve in progress (progress()): its start on the monotonic clock (0: none) and on the
  // planner thread's CPU clock.
  std::atomic<std::uint64_t> solve_began_ns_{0};
  std::atomic<std::uint64_t> solve_began_cpu_ns_{0};
  std::atomic<bool> have_cpu_clock_{false};
  clockid_t cpu_clock_{};
  std::atomic<bool> stop_{false};
  sem_t wake_;
  sem_t answer_;  ///< posted with every answer (lockstep waits)
  std::thread thread_;
};

}  // namespace ballast::control
