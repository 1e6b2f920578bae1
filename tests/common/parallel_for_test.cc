// ParallelFor (common/parallel_for.h): job-order merge whatever the number of threads, the failure of the smallest
// job index forwarded, cancellation from a caller's token and from the process token (RequestStop).
#include "uascma/common/parallel_for.h"

#include <atomic>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "uascma/common/progress.h"

namespace uascma {
namespace {

// Work whose cost falls with the index (early jobs are the slow ones), so that with several threads later jobs
// finish first and an unordered merge would see them first. Returns a value of the index alone.
double UnevenJob(std::int64_t index, std::int64_t count) {
  double x = 1.0 / static_cast<double>(index + 1);
  const std::int64_t rounds = 2000 * (count - index);
  for (std::int64_t r = 0; r < rounds; ++r) x = x * 0.999999 + 1e-9 * static_cast<double>(r % 7);
  return x;
}

// A fold that depends on the order of its terms (floating-point sums are not associative).
double OrderedFold(int jobs, std::vector<std::int64_t>* order) {
  constexpr std::int64_t kCount = 64;
  ParallelOptions options;
  options.jobs = jobs;
  options.cancel = nullptr;
  double sum = 0.0;
  const std::int64_t merged = ParallelFor(
      kCount, options, [](std::int64_t i) { return UnevenJob(i, kCount); },
      [&](std::int64_t i, double value) {
        if (order != nullptr) order->push_back(i);
        sum = sum * 1.0000001 + value;
      });
  EXPECT_EQ(merged, kCount);
  return sum;
}

TEST(ParallelForTest, MergesInJobOrderForAnyNumberOfThreads) {
  for (int jobs : {1, 2, 3, 8}) {
    std::vector<std::int64_t> order;
    OrderedFold(jobs, &order);
    ASSERT_EQ(order.size(), 64u) << jobs << " threads";
    for (std::size_t i = 0; i < order.size(); ++i)
      EXPECT_EQ(order[i], static_cast<std::int64_t>(i)) << jobs << " threads";
  }
}

TEST(ParallelForTest, OneAndManyThreadsGiveTheSameBits) {
  const double one = OrderedFold(1, nullptr);
  for (int jobs : {2, 4, 16}) {
    const double many = OrderedFold(jobs, nullptr);
    EXPECT_EQ(std::memcmp(&one, &many, sizeof one), 0) << jobs << " threads: " << one << " vs " << many;
  }
}

TEST(ParallelForTest, MapReturnsResultsInJobOrder) {
  ParallelOptions options;
  options.jobs = 4;
  options.cancel = nullptr;
  const std::vector<std::int64_t> squares = ParallelMap(50, options, [](std::int64_t i) { return i * i; });
  ASSERT_EQ(squares.size(), 50u);
  for (std::int64_t i = 0; i < 50; ++i) EXPECT_EQ(squares[static_cast<std::size_t>(i)], i * i);
}

TEST(ParallelForTest, NoJobsMeansNoCalls) {
  int calls = 0;
  EXPECT_EQ(ParallelFor(
                0, ParallelOptions{}, [&](std::int64_t) { return ++calls; }, [](std::int64_t, int) {}),
            0);
  EXPECT_EQ(calls, 0);
}

TEST(ParallelForTest, ForwardsTheFailureOfTheSmallestIndexAfterMergingTheJobsBeforeIt) {
  for (int jobs : {1, 2, 5}) {
    ParallelOptions options;
    options.jobs = jobs;
    options.cancel = nullptr;
    std::vector<std::int64_t> merged;
    try {
      ParallelFor(
          40, options,
          [](std::int64_t i) -> int {
            if (i == 7 || i == 13) throw std::runtime_error("job " + std::to_string(i));
            return static_cast<int>(i);
          },
          [&](std::int64_t i, int) { merged.push_back(i); });
      ADD_FAILURE() << "no exception with " << jobs << " threads";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "job 7") << jobs << " threads";
    }
    ASSERT_EQ(merged.size(), 7u) << jobs << " threads";
    for (std::size_t i = 0; i < merged.size(); ++i) EXPECT_EQ(merged[i], static_cast<std::int64_t>(i));
  }
}

// Job 20 fails first in time; job 5, already under way, fails only after it (it waits for the stop that job 20's
// failure raises). The error forwarded is job 5's: the one a single thread would have met first.
TEST(ParallelForTest, ASmallerIndexFailingLaterInTimeIsTheOneForwarded) {
  for (int jobs : {2, 4}) {
    ParallelOptions options;
    options.jobs = jobs;
    options.cancel = nullptr;
    std::atomic<int> started_after_stop{0};
    try {
      ParallelFor(
          1000, options,
          [&](std::int64_t i, const CancellationToken& stop) -> int {
            if (stop.IsCancelled()) ++started_after_stop;
            if (i == 5) {
              while (!stop.IsCancelled()) std::this_thread::yield();
              throw std::runtime_error("job 5");
            }
            if (i == 20) throw std::runtime_error("job 20");
            return 0;
          },
          [](std::int64_t, int) {});
      ADD_FAILURE() << "no exception";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "job 5") << jobs << " threads";
    }
    // Job 5 waits for the stop by design; besides it, a thread that had taken its index before the stop may
    // still start that job: no more than one per thread.
    EXPECT_LE(started_after_stop.load(), jobs);
  }
}

TEST(ParallelForTest, AFailingMergeIsForwardedToo) {
  ParallelOptions options;
  options.jobs = 3;
  options.cancel = nullptr;
  int merges = 0;
  EXPECT_THROW(ParallelFor(
                   30, options, [](std::int64_t i) { return i; },
                   [&](std::int64_t i, std::int64_t) {
                     if (i == 11) throw std::logic_error("merge 11");
                     ++merges;
                   }),
               std::logic_error);
  EXPECT_EQ(merges, 11);
}

TEST(ParallelForTest, ACancelledTokenStartsNoFurtherJobAndMergesAPrefix) {
  for (int jobs : {1, 3}) {
    CancellationToken token;
    ParallelOptions options;
    options.jobs = jobs;
    options.cancel = &token;
    std::atomic<std::int64_t> highest_started{-1};
    std::vector<std::int64_t> merged;
    const std::int64_t done = ParallelFor(
        1000, options,
        [&](std::int64_t i) {
          std::int64_t seen = highest_started.load();
          while (i > seen && !highest_started.compare_exchange_weak(seen, i)) {
          }
          if (i == 10) token.Cancel();
          return i;
        },
        [&](std::int64_t i, std::int64_t) { merged.push_back(i); });
    // Indices are handed out in order and none after the cancel is seen: at most one further job per thread.
    EXPECT_GE(done, 11) << jobs << " threads";
    EXPECT_LE(done, 10 + jobs) << jobs << " threads";
    EXPECT_EQ(highest_started.load(), done - 1);
    ASSERT_EQ(static_cast<std::int64_t>(merged.size()), done);
    for (std::size_t i = 0; i < merged.size(); ++i) EXPECT_EQ(merged[i], static_cast<std::int64_t>(i));
    if (jobs == 1) {
      EXPECT_EQ(done, 11);
    }
  }
}

TEST(ParallelForTest, TheProcessStopCancelsByDefaultAndMapSaysSo) {
  ClearStopRequest();
  ParallelOptions options;
  options.jobs = 2;
  EXPECT_THROW(ParallelMap(500, options,
                           [](std::int64_t i) {
                             if (i == 3) RequestStop();  // as the CLI's SIGINT handler does
                             return i;
                           }),
               Cancelled);
  EXPECT_TRUE(CancellationToken::Process().IsCancelled());
  ClearStopRequest();
  EXPECT_EQ(ParallelMap(20, options, [](std::int64_t i) { return i; }).size(), 20u);
}

TEST(ParallelForTest, AChildTokenFollowsItsParent) {
  CancellationToken parent;
  CancellationToken child(&parent);
  EXPECT_FALSE(child.IsCancelled());
  parent.Cancel();
  EXPECT_TRUE(child.IsCancelled());
  parent.Reset();
  child.Cancel();
  EXPECT_TRUE(child.IsCancelled());
  EXPECT_FALSE(parent.IsCancelled());
}

TEST(ParallelForTest, UnorderedMergesEveryJobOnce) {
  ParallelOptions options;
  options.jobs = 4;
  options.ordered = false;
  options.cancel = nullptr;
  std::vector<int> seen(100, 0);
  EXPECT_EQ(ParallelFor(
                100, options, [](std::int64_t i) { return UnevenJob(i, 100); },
                [&](std::int64_t i, double) { ++seen[static_cast<std::size_t>(i)]; }),
            100);
  for (int count : seen) EXPECT_EQ(count, 1);
}

}  // namespace
}  // namespace uascma
