// The supervisor's hang rule, on time the test drives: a worker is hung after more than --case-timeout-s
// without a line, however long it has run in all, and every line starts the silence again. (The CLI test
// AHangIsKilledAfterTheCaseTimeoutAndCostsOneCase holds the wiring: a worker that never answers is killed and
// costs one case.)
#include "bench/cli/silence_watch.h"

#include <gtest/gtest.h>

using omnishadow::bench::SilenceWatch;

TEST(SilenceWatch, HungOnlyAfterMoreThanTheTimeoutOfSilence) {
  SilenceWatch w(10.0, 100.0);  // started at 100 s on the caller's clock
  EXPECT_FALSE(w.hung(100.0));
  EXPECT_FALSE(w.hung(109.999));
  EXPECT_FALSE(w.hung(110.0)) << "exactly the timeout is still patience";
  EXPECT_TRUE(w.hung(110.001));
  EXPECT_DOUBLE_EQ(w.silent_s(112.5), 12.5);
}

// A worker that speaks every 9 s for 10 minutes is never hung (its case is long, not stuck); once it stops
// speaking it is hung 10 s after its last line, not after its start.
TEST(SilenceWatch, EveryLineStartsTheSilenceAgain) {
  SilenceWatch w(10.0, 0.0);
  double t = 0.0;
  for (; t < 600.0; t += 9.0) {
    EXPECT_FALSE(w.hung(t + 8.999)) << "at " << t;
    w.heard(t + 9.0);
  }
  EXPECT_FALSE(w.hung(t + 10.0));
  EXPECT_TRUE(w.hung(t + 10.01));
}
