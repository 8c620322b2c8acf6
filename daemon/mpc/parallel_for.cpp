#include "mpc/parallel_for.hpp"

#include <pthread.h>

#include <string>

namespace ballast::mpc {

ParallelFor::ParallelFor(int threads) {
  for (int t = 1; t < threads; ++t) workers_.emplace_back([this, t] { workerLoop(t); });
}

ParallelFor::~ParallelFor() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (auto& w : workers_) w.join();
}

void ParallelFor::work(const Job& job, int thread) {
  const std::uint64_t tag = static_cast<std::uint64_t>(job.run) << 32;
  std::uint64_t v = next_.load(std::memory_order_acquire);
  for (;;) {
    // Claim the next index of this run, or stop: the run is over or its indices are all taken.
    if ((v & ~0xffffffffull) != tag || static_cast<int>(v & 0xffffffffu) >= job.n) return;
    if (!next_.compare_exchange_weak(v, v + 1, std::memory_order_acq_rel)) continue;
    job.call(job.body, static_cast<int>(v & 0xffffffffu), thread);
    done_.fetch_add(1, std::memory_order_release);
    v = next_.load(std::memory_order_acquire);
  }
}

void ParallelFor::runErased(int n, void* body, Trampoline call) {
  Job job;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    job = Job{job_.run + 1, n, body, call};
    job_ = job;
    done_.store(0, std::memory_order_relaxed);
    next_.store(static_cast<std::uint64_t>(job.run) << 32, std::memory_order_release);
  }
  wake_.notify_all();
  work(job, 0);
  // What is left is at most one index per worker, already running: wait for it by spinning.
  while (done_.load(std::memory_order_acquire) < n) std::this_thread::yield();
}

void ParallelFor::workerLoop(int thread) {
  pthread_setname_np(pthread_self(), ("ballast-mpc-" + std::to_string(thread)).c_str());
  std::uint32_t seen = 0;
  for (;;) {
    Job job;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || job_.run != seen; });
      if (stop_) return;
      job = job_;
      seen = job.run;
    }
    work(job, thread);
  }
}

}  // namespace ballast::mpc
