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

void ParallelFor::work(int thread) {
  for (int i = next_.fetch_add(1); i < n_; i = next_.fetch_add(1)) call_(body_, i, thread);
}

void ParallelFor::runErased(int n, void* body, Trampoline call) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    n_ = n;
    body_ = body;
    call_ = call;
    next_ = 0;
    busy_ = static_cast<int>(workers_.size());
    ++generation_;
  }
  wake_.notify_all();
  work(0);
  std::unique_lock<std::mutex> lock(mutex_);
  done_.wait(lock, [this] { return busy_ == 0; });
}

void ParallelFor::workerLoop(int thread) {
  pthread_setname_np(pthread_self(), ("ballast-mpc-" + std::to_string(thread)).c_str());
  unsigned long seen = 0;
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
    }
    work(thread);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      --busy_;
    }
    done_.notify_one();
  }
}

}  // namespace ballast::mpc
