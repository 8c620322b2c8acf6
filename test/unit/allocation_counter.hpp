// A counting malloc (and free) for the "the 1 kHz path allocates nothing" tests. glibc lets a program
// interpose malloc; operator new and Eigen both allocate through it. Only the thread that sets
// `counting` is watched (a planner or writer thread beside it may allocate freely).
// It defines malloc: in a test executable with several source files that count, the others
// define BALLAST_ALLOCATION_COUNTER_ELSEWHERE before including it.
#pragma once

#include <atomic>
#include <cstdlib>

namespace ballast::test::allocation {
inline thread_local bool counting = false;
inline std::atomic<long> count{0}, frees{0};
}  // namespace ballast::test::allocation

#ifndef BALLAST_ALLOCATION_COUNTER_ELSEWHERE
extern "C" void* __libc_malloc(std::size_t);
extern "C" void* malloc(std::size_t n) {
  if (ballast::test::allocation::counting) ballast::test::allocation::count.fetch_add(1);
  return __libc_malloc(n);
}
extern "C" void __libc_free(void*);
extern "C" void free(void* p) {
  if (p && ballast::test::allocation::counting) ballast::test::allocation::frees.fetch_add(1);
  __libc_free(p);
}
#endif

namespace ballast::test {

/// Allocations f() makes on this thread.
template <typename F>
long allocationsIn(F&& f) {
  allocation::count = 0;
  allocation::counting = true;
  f();
  allocation::counting = false;
  return allocation::count.load();
}

/// Blocks f() frees on this thread.
template <typename F>
long freesIn(F&& f) {
  allocation::frees = 0;
  const bool was = allocation::counting;
  allocation::counting = true;
  f();
  allocation::counting = was;
  return allocation::frees.load();
}

}  // namespace ballast::test
