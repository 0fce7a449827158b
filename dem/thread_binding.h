#pragma once
// Keeps each OpenMP thread of the force loop on a core of its own.
//
// Unbound, the operating system moves the threads between cores from one parallel loop to the
// next, and each move costs the moved thread its cache: on a 2-core machine the 6500-grain
// bench ran at 1.3-1.6 ms a step on two threads, 1.05-1.1 ms with the threads bound (the same
// work, measured side by side). libgomp binds only when OMP_PROC_BIND is set before the program
// starts, so the DEM binds its threads itself.

namespace pilelab::dem {

/// Binds thread t of the current OpenMP team size to the t-th core the process may run on, if
/// the team has more than one thread and no more threads than the process has cores, and the
/// user has not chosen a binding (OMP_PROC_BIND, OMP_PLACES or GOMP_CPU_AFFINITY set). Returns
/// how many threads it bound (0: left to the system).
int bind_threads_to_cores();

}  // namespace pilelab::dem
