// A fixed team of threads that runs one loop body over an index range, each index once,
// handed out dynamically. The calling thread works too, so `threads` = cores used. Used by the
// SQP to linearise and project the nodes on both cores.
#pragma once

#include <atomic>
#include <condition_variable>
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
  void runErased(int n, void* body, Trampoline call);
  void work(int thread);
  void workerLoop(int thread);

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  unsigned long generation_ = 0;
  int busy_ = 0;
  bool stop_ = false;
  std::atomic<int> next_{0};
  int n_ = 0;
  void* body_ = nullptr;
  Trampoline call_ = nullptr;
};

}  // namespace ballast::mpc
