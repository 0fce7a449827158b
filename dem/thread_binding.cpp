#include "dem/thread_binding.h"

#include <cstdlib>
#include <initializer_list>

#ifdef __linux__
#include <pthread.h>
#include <sched.h>
#endif
#ifdef _OPENMP
#include <omp.h>
#endif

namespace pilelab::dem {

int bind_threads_to_cores() {
#if defined(__linux__) && defined(_OPENMP)
  for (const char* chosen : {"OMP_PROC_BIND", "OMP_PLACES", "GOMP_CPU_AFFINITY"})
    if (std::getenv(chosen)) return 0;
  const int threads = omp_get_max_threads();
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  if (threads < 2 || sched_getaffinity(0, sizeof allowed, &allowed) != 0) return 0;
  int cores[CPU_SETSIZE], count = 0;
  for (int c = 0; c < CPU_SETSIZE; ++c)
    if (CPU_ISSET(c, &allowed)) cores[count++] = c;
  if (threads > count) return 0;  // oversubscribed: binding would only stack threads
  int bound = 0;
#pragma omp parallel num_threads(threads) reduction(+ : bound)
  {
    cpu_set_t mine;
    CPU_ZERO(&mine);
    CPU_SET(cores[omp_get_thread_num()], &mine);
    bound += pthread_setaffinity_np(pthread_self(), sizeof mine, &mine) == 0 ? 1 : 0;
  }
  return bound;
#else
  return 0;
#endif
}

}  // namespace pilelab::dem
