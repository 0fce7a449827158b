// The time a cache line takes to go from one core to another and back: two threads, each bound
// to its core, pass a counter between them through one atomic. On one chip of shared cache a
// round trip takes about a hundred nanoseconds; where the two cores share no cache (two chiplets
// or sockets) several times that. On a virtual machine the host decides, and may change its
// mind within minutes: dem_step_table.sh prints this figure beside every table, because the
// two-thread step, whose threads hand each other the grains at the edge of their parts, feels
// it and one thread does not.
//
//   core_round_trip [CORE_A CORE_B]   (default: the first two cores this process may use)
//
// Prints the median of five measurements of 200 000 round trips each, in nanoseconds.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <thread>
#include <vector>

#include <pthread.h>
#include <sched.h>

namespace {

bool bind_to_core(int core) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(core, &set);
  return pthread_setaffinity_np(pthread_self(), sizeof set, &set) == 0;
}

// Mean round trip over `rounds`, in ns: this thread serves odd counts, the other answers with
// the next even one.
double round_trip_ns(int core_a, int core_b, int rounds) {
  alignas(64) std::atomic<int> ball{0};
  std::thread partner([&] {
    bind_to_core(core_b);
    for (int k = 0; k < rounds; ++k) {
      while (ball.load(std::memory_order_acquire) != 2 * k + 1) {
      }
      ball.store(2 * k + 2, std::memory_order_release);
    }
  });
  bind_to_core(core_a);
  const auto start = std::chrono::steady_clock::now();
  for (int k = 0; k < rounds; ++k) {
    ball.store(2 * k + 1, std::memory_order_release);
    while (ball.load(std::memory_order_acquire) != 2 * k + 2) {
    }
  }
  const double elapsed = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start).count();
  partner.join();
  return elapsed / rounds;
}

}  // namespace

int main(int argc, char** argv) {
  int cores[2] = {-1, -1};
  if (argc == 3) {
    cores[0] = std::atoi(argv[1]);
    cores[1] = std::atoi(argv[2]);
  } else {
    cpu_set_t allowed;
    CPU_ZERO(&allowed);
    sched_getaffinity(0, sizeof allowed, &allowed);
    for (int c = 0, found = 0; c < CPU_SETSIZE && found < 2; ++c)
      if (CPU_ISSET(c, &allowed)) cores[found++] = c;
  }
  if (cores[0] < 0 || cores[1] < 0 || cores[0] == cores[1]) {
    std::fprintf(stderr, "core_round_trip: needs two distinct cores (usage: core_round_trip [CORE_A CORE_B])\n");
    return 1;
  }
  if (!bind_to_core(cores[1]) || !bind_to_core(cores[0])) {
    std::fprintf(stderr, "core_round_trip: cannot bind a thread to core %d or %d\n", cores[0], cores[1]);
    return 1;
  }
  std::vector<double> trips;
  for (int k = 0; k < 5; ++k) trips.push_back(round_trip_ns(cores[0], cores[1], 200000));
  std::sort(trips.begin(), trips.end());
  std::printf("%.0f\n", trips[2]);
  return 0;
}
