// Progress reporting and the stop request (common/progress.h): the plain line a log reads, durations for
// people, the counts the Python module polls, and the process-wide stop flag.
#include "uascma/common/progress.h"

#include <gtest/gtest.h>

namespace uascma {
namespace {

TEST(ProgressTest, DurationsReadAsPeopleSayThem) {
  EXPECT_EQ(FormatDuration(0.4), "0 s");
  EXPECT_EQ(FormatDuration(42.0), "42 s");
  EXPECT_EQ(FormatDuration(153.0), "2 min 33 s");
  EXPECT_EQ(FormatDuration(3900.0), "1 h 05 min");
  EXPECT_EQ(FormatDuration(-1.0), "?");
}

TEST(ProgressTest, LineGivesCountsPercentRateAndEta) {
  // 1200 of 4000 in 65 s: 18.46/s (printed without decimals from 10/s), ETA 2800 / 18.46 = 151.7 s → 2 min 32 s.
  EXPECT_EQ(FormatProgressLine("campaign x, flights", 1200, 4000, 65.0),
            "campaign x, flights: 1200/4000 (30.0 %), 18/s, 1 min 05 s elapsed, ETA 2 min 32 s");
  // Slow work keeps two decimals of the rate; nothing done yet has no ETA; all done says so.
  EXPECT_EQ(FormatProgressLine("a", 3, 100, 12.0), "a: 3/100 (3.0 %), 0.25/s, 12 s elapsed, ETA 6 min 28 s");
  EXPECT_EQ(FormatProgressLine("a", 0, 100, 5.0), "a: 0/100 (0.0 %), 0.00/s, 5 s elapsed, ETA unknown");
  EXPECT_EQ(FormatProgressLine("a", 100, 100, 5.0), "a: 100/100 (100.0 %), 20/s, 5 s elapsed, done");
}

TEST(ProgressTest, CurrentProgressIsTheNewestLiveBarThenTheLastEnded) {
  SetProgressOnStderr(false);  // nothing on the test's stderr
  ForgetEndedProgress();
  EXPECT_FALSE(CurrentProgress().has_value());
  {
    ProgressBar outer(10, "outer");
    outer.Advance(3);
    {
      ProgressBar inner(4, "inner");
      inner.Advance();
      ASSERT_TRUE(CurrentProgress().has_value());
      EXPECT_EQ(CurrentProgress()->label, "inner");
      EXPECT_EQ(CurrentProgress()->done, 1);
    }
    EXPECT_EQ(CurrentProgress()->label, "outer");
    EXPECT_EQ(CurrentProgress()->done, 3);
    EXPECT_EQ(CurrentProgress()->total, 10);
    outer.Advance(7);
  }
  // Ended: its final counts stay until forgotten (a poller that looks after the work still sees the end).
  ASSERT_TRUE(CurrentProgress().has_value());
  EXPECT_EQ(CurrentProgress()->label, "outer");
  EXPECT_EQ(CurrentProgress()->done, 10);
  ForgetEndedProgress();
  EXPECT_FALSE(CurrentProgress().has_value());
  SetProgressOnStderr(true);
}

TEST(ProgressTest, StopRequestIsSetAndCleared) {
  ClearStopRequest();
  EXPECT_FALSE(StopRequested());
  RequestStop();
  EXPECT_TRUE(StopRequested());
  ClearStopRequest();
  EXPECT_FALSE(StopRequested());
}

}  // namespace
}  // namespace uascma
