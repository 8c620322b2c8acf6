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
}  // namespace

void PlannerSlot::run() {
  pthread_setname_np(pthread_self(), "ballast-planner");
  if (priority_ > 0) {
    sched_param param{};
    param.sched_priority = priority_;
    pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);  // refused: normal priority
  }
  for (;;) {
    sem_wait(&wake_);
    if (stop_) return;
    if (!input_.take()) continue;  // several posts, one wake-up already consumed them
    const PlannerInput& in = input_.front();
    PlannerOutput& out = output_.back();
    const auto t0 = std::chrono::steady_clock::now();
    out.exception = false;
    try {
      planner_->plan(in, out);
    } catch (const std::exception& e) {
      failed(out, e.what());
    } catch (...) {
      failed(out, "an exception of unknown type");
    }
    out.sequence = in.sequence;
    out.solve_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    output_.publish();
    answered_.store(in.sequence, std::memory_order_release);
    sem_post(&answer_);
  }
}

}  // namespace ballast::control
