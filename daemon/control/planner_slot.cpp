#include "control/planner_slot.hpp"

#include <pthread.h>

#include <cerrno>
#include <cstdio>
#include <exception>
#include <chrono>
#include <ctime>

namespace ballast::control {

PlannerSlot::~PlannerSlot() {
  stop();
  sem_destroy(&wake_);
  sem_destroy(&answer_);
}

void PlannerSlot::start(Planner* planner, double rate, bool lockstep, double latency,
                        int priority) {
  planner_ = planner;
  priority_ = priority;
  period_ = 1.0 / rate;
  lockstep_ = lockstep;
  latency_ = latency;
  if (planner_) thread_ = std::thread([this] { run(); });
}

void PlannerSlot::stop() {
  if (!thread_.joinable()) return;
  stop_ = true;
  sem_post(&wake_);
  thread_.join();
}

void PlannerSlot::detach() {
  stop();
  planner_ = nullptr;
  stop_ = false;
  in_flight_ = 0;
  have_output_ = false;
}

bool PlannerSlot::post(PlannerInput& input, double timeout_s) {
  // Lockstep: an answer still in flight is due by now (latency <= period): take it first.
  bool timed_out = false;
  if (lockstep_ && in_flight_ != 0) {
    use_at_ = input.t;
    latest(input.t, timed_out, timeout_s);
  }
  input.sequence = ++sequence_;
  next_due_ = input.t + period_;
  input_.back() = input;
  input_.publish();
  if (lockstep_) {
    in_flight_ = input.sequence;
    use_at_ = input.t + latency_;
  }
  sem_post(&wake_);
  return !timed_out;
}

const PlannerOutput* PlannerSlot::latest(double t, bool& timed_out, double timeout_s) {
  timed_out = false;
  if (!lockstep_) {
    if (output_.take()) have_output_ = true;
    return have_output_ ? &output_.front() : nullptr;
  }
  if (in_flight_ == 0 || t + kTimeTolerance < use_at_)
    return have_output_ ? &output_.front() : nullptr;
  // Its time has come: wait for the answer (sleeping: on two cores a spinning loop thread
  // would take a core from the planner's linearisation team).
  timespec deadline;
  clock_gettime(CLOCK_MONOTONIC, &deadline);
  const auto ns = static_cast<long long>(timeout_s * 1e9) + deadline.tv_nsec;
  deadline.tv_sec += static_cast<time_t>(ns / 1000000000LL);
  deadline.tv_nsec = static_cast<long>(ns % 1000000000LL);
  while (answered_.load(std::memory_order_acquire) < in_flight_)
    if (sem_clockwait(&answer_, CLOCK_MONOTONIC, &deadline) != 0 && errno == ETIMEDOUT &&
        answered_.load(std::memory_order_acquire) < in_flight_) {
      timed_out = true;
      return have_output_ ? &output_.front() : nullptr;
    }
  in_flight_ = 0;
  if (output_.take()) have_output_ = true;
  return have_output_ ? &output_.front() : nullptr;
}

namespace {
/// A planner that threw: no plan, and the loop treats it as a fault.
void failed(PlannerOutput& out, const char* what) {
  out.valid = false;
  out.exception = true;
  std::snprintf(out.message, sizeof(out.message), "exception: %s", what);
}

std::uint64_t clockNs(clockid_t clock) {
  timespec ts;
  if (clock_gettime(clock, &ts) != 0) return 0;
  return static_cast<std::uint64_t>(ts.tv_sec) * 1000000000ull + static_cast<std::uint64_t>(ts.tv_nsec);
}
}  // namespace

PlannerSlot::Progress PlannerSlot::progress() const {
  Progress p;
  const std::uint64_t began = solve_began_ns_.load(std::memory_order_acquire);
  if (began == 0 || !have_cpu_clock_.load(std::memory_order_acquire)) return p;
  const std::uint64_t cpu = clockNs(cpu_clock_), began_cpu = solve_began_cpu_ns_.load(std::memory_order_acquire);
  const std::uint64_t now = clockNs(CLOCK_MONOTONIC);
  // The same solve throughout (a newer one would have restamped the start)?
  if (solve_began_ns_.load(std::memory_order_acquire) != began) return p;
  p.solving = true;
  p.wall = now > began ? static_cast<double>(now - began) * 1e-9 : 0.0;
  p.cpu = cpu > began_cpu ? static_cast<double>(cpu - began_cpu) * 1e-9 : 0.0;
  return p;
}

void PlannerSlot::run() {
  pthread_setname_np(pthread_self(), "ballast-planner");
  if (priority_ > 0) {
    sched_param param{};
    param.sched_priority = priority_;
    pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);  // refused: normal priority
  }
  if (pthread_getcpuclockid(pthread_self(), &cpu_clock_) == 0)
    have_cpu_clock_.store(true, std::memory_order_release);
  for (;;) {
    sem_wait(&wake_);
    if (stop_) return;
    if (!input_.take()) continue;  // several posts, one wake-up already consumed them
    const PlannerInput& in = input_.front();
    PlannerOutput& out = output_.back();
    const auto t0 = std::chrono::steady_clock::now();
    out.exception = false;
    if (have_cpu_clock_.load(std::memory_order_relaxed))
      solve_began_cpu_ns_.store(clockNs(cpu_clock_), std::memory_order_relaxed);
    solve_began_ns_.store(clockNs(CLOCK_MONOTONIC), std::memory_order_release);
    if (stall_ > 0.0 && in.t >= stall_at_) {
      std::this_thread::sleep_for(std::chrono::duration<double>(stall_));
      stall_ = 0.0;
    }
    try {
      planner_->plan(in, out);
    } catch (const std::exception& e) {
      failed(out, e.what());
    } catch (...) {
      failed(out, "an exception of unknown type");
    }
    solve_began_ns_.store(0, std::memory_order_release);
    out.sequence = in.sequence;
    out.solve_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    output_.publish();
    answered_.store(in.sequence, std::memory_order_release);
    sem_post(&answer_);
    // Real time, the next input's time is not known ahead (and its plan starts a measured
    // solve time after it): nothing to prepare for.
    if (!lockstep_) continue;
    try {
      planner_->prepare(in.t + period_);
    } catch (...) {
      // Only the next plan's speed is lost: it computes what the preparation would have.
    }
  }
}

}  // namespace ballast::control
