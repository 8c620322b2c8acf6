// A fixed team of threads that runs one loop body over an index range, each index once,
// handed out dynamically. The calling thread works too, so `threads` = cores used. Used by the
// SQP to linearise and project the nodes on both cores.
//
// run() returns when every index is done, not when every worker has woken: a worker that wakes
// after the caller has taken all the work finds its run over and takes nothing (an index is
// claimed together with its run's number), so a slow wake-up never delays the caller.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

namespace ballast::mpc {

class ParallelFor {
 public:
  explicit ParallelFor(int threads);
  ~ParallelFor();
  ParallelFor(const ParallelFor&) = delete;
  ParallelFor& operator=(const ParallelFor&) = delete;

  int threads() const { return static_cast<int>(workers_.size()) + 1; }

  /// Calls body(i, thread) for every i in [0, n); thread ∈ [0, threads()). Returns when done.
  template <typename Body>
  void run(int n, Body& body) {
    runErased(n, &body, [](void* b, int i, int t) { (*static_cast<Body*>(b))(i, t); });
  }

 private:
  using Trampoline = void (*)(void*, int, int);
  struct Job {
    std::uint32_t run = 0;  // the run's number
    int n = 0;
    void* body = nullptr;
    Trampoline call = nullptr;
  };
  void runErased(int n, void* body, Trampoline call);
  void work(const Job& job, int thread);
  void workerLoop(int thread);

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  Job job_;                               // the current run (under mutex_)
  std::atomic<std::uint64_t> next_{0};    // run number << 32 | next index
  std::atomic<int> done_{0};              // indices of the current run finished
};

}  // namespace ballast::mpc
