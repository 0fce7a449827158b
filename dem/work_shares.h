#pragma once
// How a pass of the step shares its work among the threads.
//
// Each thread of a pass takes one contiguous part of the work (grains, or listed pairs, in their
// order), so that a grain's data stays in one core's cache from pass to pass. The parts are cut
// at shares of an expected cost (a grain, a pair), but the threads do not get through a unit of
// cost equally fast: the thread whose grains border the other thread's part reads data the other
// core wrote, the parts of a pile differ in what the cost model misses, and the cores of a
// virtual machine differ. Each thread's share therefore follows the rate at which it got through
// its part over the last steps (cost per second, smoothed), which is the share that makes the
// threads finish together. The results never depend on the shares, only the time does.
#include <vector>

namespace pilelab::dem {

class WorkShares {
 public:
  /// Before the pass (serial): the team it will run with. A team of another size than the
  /// last starts from equal shares.
  void prepare(int threads);
  /// Where thread t's part begins, as a fraction of the whole: 0 for t = 0, 1 for t >= threads.
  /// A team of another size than prepared gets equal parts.
  double begin(int thread, int threads) const;
  /// In the pass, by each thread of a team of `threads` for itself: its part had this expected
  /// cost and took this long. Several passes may record before an update (their costs and times
  /// add up). A team of another size than prepared records nothing: its parts were not the
  /// shares'.
  void record(int thread, int threads, double cost, double seconds);
  /// After the pass (serial): the recorded rates move the shares, and the records are cleared.
  void update();

  /// A share never falls below this fraction of an equal one (nor rises above 2 - it), however
  /// slowly its thread has run: it keeps enough work for its rate to stay measured.
  static constexpr double least_share = 0.5;
  /// How far one step's rate moves the smoothed rate: about the last 1 / smoothing steps count.
  static constexpr double smoothing = 0.125;

 private:
  struct alignas(64) Record {  // one cache line per thread: no thread writes another's line
    double cost = 0.0, seconds = 0.0;
  };
  std::vector<Record> records_;
  std::vector<double> rate_;   // cost per second of each thread, smoothed; 0 before any record
  std::vector<double> begin_;  // threads + 1 entries
};

}  // namespace pilelab::dem
