// os::Workers, the one worker pool: every index run once, the shares covering the range in
// aligned contiguous pieces, errors rethrown in a fixed order, and a pool that serves many runs
// (refsim's steps) and then sleeps without losing a wake-up.
#include <granstack/os/workers.hpp>

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace granstack::os {
namespace {

TEST(Workers, EveryThreadRunsOnceAndTheCallerIsThreadZero) {
  Workers w(4);
  std::vector<std::atomic<int>> ran(4);
  std::thread::id zero;
  w.run([&](int t) {
    ++ran[static_cast<std::size_t>(t)];
    if (t == 0) zero = std::this_thread::get_id();
  });
  for (const auto& r : ran) EXPECT_EQ(r.load(), 1);
  EXPECT_EQ(zero, std::this_thread::get_id());
}

TEST(Workers, SharesCoverTheRangeInAlignedContiguousPieces) {
  for (const int threads : {1, 2, 3, 7}) {
    Workers w(threads);
    for (const std::size_t count : {0u, 1u, 5u, 17u, 1000u}) {
      for (const std::size_t align : {1u, 8u}) {
        std::vector<std::atomic<int>> hits(count);
        w.for_shares(count, [&](std::size_t begin, std::size_t end) {
          EXPECT_LE(begin, end);
          if (end < count) {
            EXPECT_EQ(end % align, 0u) << threads << " " << count << " " << align;
          }
          for (std::size_t i = begin; i < end; ++i) ++hits[i];
        }, align);
        for (std::size_t i = 0; i < count; ++i) EXPECT_EQ(hits[i].load(), 1) << i;
      }
    }
  }
}

TEST(Workers, ForEachRunsEveryIndexOnceAndRethrowsTheFirstErrorByIndex) {
  Workers w(3);
  std::vector<std::atomic<int>> hits(100);
  try {
    w.for_each(100, [&](std::size_t i) {
      ++hits[i];
      if (i == 70 || i == 30) throw std::runtime_error("item " + std::to_string(i));
    });
    FAIL() << "no error rethrown";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "item 30");
  }
  for (const auto& h : hits) EXPECT_EQ(h.load(), 1);  // an error stops no other item
  EXPECT_THROW(for_each(4, 2, [](std::size_t i) { if (i == 3) throw std::logic_error("x"); }), std::logic_error);
}

TEST(Workers, AnErrorOnAHelperIsRethrownAfterEveryThreadEnded) {
  Workers w(3);
  std::atomic<int> ended{0};
  EXPECT_THROW(w.run([&](int t) {
                 std::this_thread::sleep_for(std::chrono::milliseconds(t == 0 ? 20 : 1));
                 ++ended;
                 if (t == 2) throw std::invalid_argument("helper");
               }),
               std::invalid_argument);
  EXPECT_EQ(ended.load(), 3);
  // The pool still serves.
  std::atomic<int> again{0};
  w.run([&](int) { ++again; });
  EXPECT_EQ(again.load(), 3);
}

// Many short runs (a step's), then a pause long enough for the helpers to sleep, then more: no
// run is lost or doubled.
TEST(Workers, ManyShortRunsAndRunsAfterTheHelpersSleptAllComplete) {
  Workers w(3);
  std::atomic<long> sum{0};
  for (int k = 0; k < 5000; ++k) w.run([&](int t) { sum += t + 1; });
  EXPECT_EQ(sum.load(), 5000L * 6);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  for (int k = 0; k < 10; ++k) {
    w.run([&](int t) { sum += t + 1; });
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
  }
  EXPECT_EQ(sum.load(), 5010L * 6);
}

}  // namespace
}  // namespace granstack::os
