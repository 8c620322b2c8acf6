// The structures between the loop and the other threads: values arrive whole, in order, and
// neither side ever waits for the other.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "control/seqlock.hpp"
#include "control/spsc_ring.hpp"
#include "control/triple_buffer.hpp"

namespace ballast::control {
namespace {

struct Block {
  long v[64];
};

TEST(SpscRing, DeliversEverythingInOrderAcrossThreads) {
  SpscRing<long> ring(128);
  EXPECT_EQ(ring.capacity(), 128u);
  constexpr long kCount = 1000000;
  std::thread producer([&] {
    for (long i = 0; i < kCount;)
      if (ring.tryPush(i)) ++i;
  });
  long expected = 0, v;
  while (expected < kCount) {
    if (ring.tryPop(v)) {
      ASSERT_EQ(v, expected++);
    }
  }
  producer.join();
  EXPECT_FALSE(ring.tryPop(v));
}

TEST(SpscRing, FullRingRefusesWithoutBlocking) {
  SpscRing<int> ring(4);
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(ring.tryPush(i));
  EXPECT_FALSE(ring.tryPush(99));
  int v;
  EXPECT_TRUE(ring.tryPop(v));
  EXPECT_EQ(v, 0);
  EXPECT_TRUE(ring.tryPush(4));
  EXPECT_EQ(ring.size(), 4u);
}

TEST(SeqLock, ReadersNeverSeeATornValue) {
  SeqLock<Block> lock;
  std::atomic<bool> done{false};
  std::atomic<long> reads{0};
  std::vector<std::thread> readers;
  for (int r = 0; r < 2; ++r)
    readers.emplace_back([&] {
      while (!done) {
        const Block b = lock.load();
        for (long x : b.v) ASSERT_EQ(x, b.v[0]);
        ++reads;
      }
    });
  // On two loaded cores the readers may not be scheduled before a fixed number of stores ends,
  // so the writer keeps going until they have overlapped it for a while.
  Block b;
  long i = 0;
  while (i < 200000 || reads.load() < 20000) {
    ++i;
    for (long& x : b.v) x = i;
    lock.store(b);
    if (i % 1024 == 0) std::this_thread::yield();
  }
  done = true;
  for (auto& t : readers) t.join();
  EXPECT_EQ(lock.load().v[63], i);
  EXPECT_EQ(lock.version(), static_cast<unsigned>(i));
  EXPECT_GE(reads.load(), 20000);
}

TEST(TripleBuffer, ReaderGetsTheNewestWholeValue) {
  TripleBuffer<Block> buffer;
  std::atomic<bool> done{false};
  long last = 0;
  std::thread reader([&] {
    while (!done) {
      if (!buffer.take()) continue;
      const Block& b = buffer.front();
      for (long x : b.v) ASSERT_EQ(x, b.v[0]);
      ASSERT_GE(b.v[0], last);  // never older than what it saw before
      last = b.v[0];
    }
  });
  for (long i = 1; i <= 200000; ++i) {
    for (long& x : buffer.back().v) x = i;
    buffer.publish();
  }
  done = true;
  reader.join();
  if (buffer.take()) last = buffer.front().v[0];
  EXPECT_EQ(last, 200000);
  EXPECT_FALSE(buffer.take());
}

}  // namespace
}  // namespace ballast::control
