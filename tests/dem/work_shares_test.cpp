// The threads' shares of a pass follow their rates: shares in proportion to the rates make the
// parts take equal times, a thread held up once loses little of its part, and none loses all.
#include "dem/work_shares.h"

#include <gtest/gtest.h>

#include <vector>

namespace pilelab::dem {
namespace {

// One pass of `total` units of cost: each thread's part by the shares, taking cost / rate plus a
// fixed overhead; returns each part's time, and records it.
std::vector<double> run_pass(WorkShares& shares, const std::vector<double>& rate, const std::vector<double>& overhead,
                             double total = 1000.0) {
  const int threads = static_cast<int>(rate.size());
  std::vector<double> seconds(threads);
  for (int t = 0; t < threads; ++t) {
    const double cost = total * (shares.begin(t + 1, threads) - shares.begin(t, threads));
    seconds[t] = cost / rate[t] + overhead[t];
    shares.record(t, threads, cost, seconds[t]);
  }
  shares.update();
  return seconds;
}

TEST(WorkShares, StartEqualAndCoverTheWhole) {
  WorkShares shares;
  shares.prepare(4);
  for (int t = 0; t <= 4; ++t) EXPECT_DOUBLE_EQ(shares.begin(t, 4), t / 4.0);
  EXPECT_DOUBLE_EQ(shares.begin(5, 4), 1.0);  // past the last thread: the end
  // A team of another size than prepared gets equal parts.
  for (int t = 0; t <= 3; ++t) EXPECT_DOUBLE_EQ(shares.begin(t, 3), t / 3.0);
}

TEST(WorkShares, SharesInProportionToRatesEqualTheTimes) {
  WorkShares shares;
  shares.prepare(3);
  const std::vector<double> rate = {1.0, 2.0, 3.0}, none = {0.0, 0.0, 0.0};
  run_pass(shares, rate, none);  // the first records are the rates themselves
  EXPECT_NEAR(shares.begin(1, 3), 1.0 / 6.0, 1e-12);
  EXPECT_NEAR(shares.begin(2, 3), 3.0 / 6.0, 1e-12);
  const std::vector<double> seconds = run_pass(shares, rate, none);
  EXPECT_NEAR(seconds[0], seconds[1], 1e-12 * seconds[0]);
  EXPECT_NEAR(seconds[1], seconds[2], 1e-12 * seconds[0]);
  EXPECT_DOUBLE_EQ(shares.begin(0, 3), 0.0);
  EXPECT_DOUBLE_EQ(shares.begin(3, 3), 1.0);
}

// A cost that does not grow with the part (the first thread's part borders the second's and
// waits for its data): the shares' fixed point still has equal times, which the steps approach.
TEST(WorkShares, AFixedOverheadStillConvergesToEqualTimes) {
  WorkShares shares;
  shares.prepare(2);
  const std::vector<double> rate = {1.0, 1.0}, overhead = {100.0, 0.0};
  std::vector<double> seconds;
  for (int step = 0; step < 400; ++step) seconds = run_pass(shares, rate, overhead);
  // Equal times: 1000 s0 + 100 = 1000 (1 - s0), so s0 = 0.45.
  EXPECT_NEAR(shares.begin(1, 2), 0.45, 1e-6);
  EXPECT_NEAR(seconds[0], seconds[1], 1e-5 * seconds[1]);
}

TEST(WorkShares, AThreadHeldUpOnceLosesLittle) {
  WorkShares shares;
  shares.prepare(2);
  const std::vector<double> even = {1.0, 1.0}, none = {0.0, 0.0};
  run_pass(shares, even, none);
  ASSERT_DOUBLE_EQ(shares.begin(1, 2), 0.5);
  run_pass(shares, even, {1e6, 0.0});  // the first thread was held up for a long while
  // Its rate is taken as at least half the smoothed one, which moves by `smoothing` of the way.
  const double kept = 1.0 - 0.5 * WorkShares::smoothing;
  EXPECT_NEAR(shares.begin(1, 2), kept / (kept + 1.0), 1e-12);
  for (int step = 0; step < 200; ++step) run_pass(shares, even, none);
  EXPECT_NEAR(shares.begin(1, 2), 0.5, 1e-9);  // and it wins its part back
}

TEST(WorkShares, NoThreadFallsBelowTheLeastShare) {
  WorkShares shares;
  shares.prepare(2);
  for (int step = 0; step < 100; ++step) run_pass(shares, {1.0, 1000.0}, {0.0, 0.0});
  EXPECT_NEAR(shares.begin(1, 2), 0.5 * WorkShares::least_share, 1e-12);
}

// A pass that ran on another team than prepared (a serial pair loop after a parallel move) did
// not take the shares' parts: its times must not move them.
TEST(WorkShares, AnotherTeamRecordsNothing) {
  WorkShares shares;
  shares.prepare(2);
  shares.record(0, 1, 1000.0, 1e6);  // the whole pass on one thread, slowly
  run_pass(shares, {1.0, 1.0}, {0.0, 0.0});
  EXPECT_NEAR(shares.begin(1, 2), 0.5, 1e-12);
}

TEST(WorkShares, ANewTeamSizeStartsEqual) {
  WorkShares shares;
  shares.prepare(2);
  run_pass(shares, {1.0, 3.0}, {0.0, 0.0});
  ASSERT_NEAR(shares.begin(1, 2), 0.25, 1e-12);
  shares.prepare(2);  // the same team keeps its shares
  EXPECT_NEAR(shares.begin(1, 2), 0.25, 1e-12);
  shares.prepare(3);
  for (int t = 0; t <= 3; ++t) EXPECT_DOUBLE_EQ(shares.begin(t, 3), t / 3.0);
}

}  // namespace
}  // namespace pilelab::dem
