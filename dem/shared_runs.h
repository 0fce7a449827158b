#pragma once
// Work shared among threads whose speed changes from moment to moment: on a virtual machine
// one core may run at two thirds of the other's speed for seconds, and a fixed split then makes
// the fast thread wait at every join. Each thread owns a run of consecutive items and takes
// them from its front; a thread that has finished its own run takes items from the back of the
// others'. Without such delays every thread does exactly its own run (the static split, with
// its data in the thread's cache); with them the late run's far end moves to the idle thread.
//
// Which thread does an item never changes a result: the callers' items are independent, and
// what they combine across threads (sums of counts, a maximum with a fixed tie-break) does not
// depend on the order.
#include <atomic>
#include <cstdint>
#include <memory>

namespace pilelab::dem {

class SharedRuns {
 public:
  SharedRuns() = default;
  // The runs live only within one parallel region: a copy starts empty.
  SharedRuns(const SharedRuns&) {}
  SharedRuns& operator=(const SharedRuns&) { return *this; }

  /// Thread t's run becomes the items [first[t], first[t + 1]) for t < threads. Call outside
  /// the parallel region that takes them; a thread of that region beyond `threads` takes only
  /// others' items, and a run whose thread is missing is taken by the others.
  void assign(const std::size_t* first, int threads) {
    if (threads > capacity_) {
      runs_ = std::make_unique<Run[]>(static_cast<std::size_t>(threads));
      capacity_ = threads;
    }
    count_ = threads;
    for (int t = 0; t < threads; ++t)
      runs_[t].ends.store(pack(first[t], first[t + 1]), std::memory_order_relaxed);
  }

  /// The next item for thread `thread` into `item`: the front of its own run, or else the back
  /// of another's (the next thread's first); false once every run is empty.
  bool take(int thread, std::size_t& item) {
    if (thread < count_ && take_front(runs_[thread], item)) return true;
    for (int k = 1; k < count_ + (thread >= count_); ++k)
      if (take_back(runs_[(thread + k) % count_], item)) return true;
    return false;
  }

 private:
  // A run's front (next item) and back (one past its last) in one word, so that its owner and
  // a thief claim items with one compare-and-swap and never the same one.
  struct alignas(64) Run {
    std::atomic<std::uint64_t> ends{0};
  };
  static std::uint64_t pack(std::size_t front, std::size_t back) { return std::uint64_t(front) << 32 | std::uint64_t(back); }
  static bool take_front(Run& run, std::size_t& item) {
    std::uint64_t ends = run.ends.load(std::memory_order_relaxed);
    for (;;) {
      const std::uint64_t front = ends >> 32, back = ends & 0xffffffffu;
      if (front >= back) return false;
      if (run.ends.compare_exchange_weak(ends, pack(front + 1, back), std::memory_order_relaxed)) {
        item = front;
        return true;
      }
    }
  }
  static bool take_back(Run& run, std::size_t& item) {
    std::uint64_t ends = run.ends.load(std::memory_order_relaxed);
    for (;;) {
      const std::uint64_t front = ends >> 32, back = ends & 0xffffffffu;
      if (front >= back) return false;
      if (run.ends.compare_exchange_weak(ends, pack(front, back - 1), std::memory_order_relaxed)) {
        item = back - 1;
        return true;
      }
    }
  }

  std::unique_ptr<Run[]> runs_;
  int capacity_ = 0, count_ = 0;
};

}  // namespace pilelab::dem
