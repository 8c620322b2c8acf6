#include "control/planner_slot.hpp"

#include <chrono>

namespace ballast::control {

PlannerSlot::~PlannerSlot() {
  stop();
  sem_destroy(&wake_);
}

void PlannerSlot::start(Planner* planner, double rate, bool synchronous) {
  planner_ = planner;
  period_ = 1.0 / rate;
  synchronous_ = synchronous;
  if (planner_) thread_ = std::thread([this] { run(); });
}

void PlannerSlot::stop() {
  if (!thread_.joinable()) return;
  stop_ = true;
  sem_post(&wake_);
  thread_.join();
}

bool PlannerSlot::post(PlannerInput& input, double timeout_s) {
  input.sequence = ++sequence_;
  next_due_ = input.t + period_;
  input_.back() = input;
  input_.publish();
  sem_post(&wake_);
  if (!synchronous_) return true;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (answered_.load(std::memory_order_acquire) < input.sequence) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::yield();
  }
  return true;
}

const PlannerOutput* PlannerSlot::latest() {
  if (output_.take()) have_output_ = true;
  return have_output_ ? &output_.front() : nullptr;
}

void PlannerSlot::run() {
  for (;;) {
    sem_wait(&wake_);
    if (stop_) return;
    if (!input_.take()) continue;  // several posts, one wake-up already consumed them
    const PlannerInput& in = input_.front();
    PlannerOutput& out = output_.back();
    const auto t0 = std::chrono::steady_clock::now();
    planner_->plan(in, out);
    out.sequence = in.sequence;
    out.solve_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    output_.publish();
    answered_.store(in.sequence, std::memory_order_release);
  }
}

}  // namespace ballast::control
