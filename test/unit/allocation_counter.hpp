// A counting malloc for the "the 1 kHz path allocates nothing" tests. glibc lets a program
// interpose malloc; operator new and Eigen both allocate through it. Only the thread that sets
// `counting` is watched (a planner or writer thread beside it may allocate freely).
// Include this header in exactly one source file of a test executable: it defines malloc.
#pragma once

#include <atomic>
#include <cstdlib>

namespace ballast::test::allocation {
inline thread_local bool counting = false;
inline std::atomic<long> count{0};
}  // namespace ballast::test::allocation

extern "C" void* __libc_malloc(std::size_t);
extern "C" void* malloc(std::size_t n) {
  if (ballast::test::allocation::counting) ballast::test::allocation::count.fetch_add(1);
  return __libc_malloc(n);
}

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

}  // namespace ballast::test
