#pragma once
// Child processes that die with their parent: a killed `pilelab run` leaves no member pouring
// on and no figure script writing into OUT.
#include <sys/types.h>

#include <string>
#include <vector>

namespace pilelab::app {

/// Starts argv[0] (a path) with argv, its stdout and stderr into output_file (or inherited when
/// empty). The child gets SIGTERM when this process dies. Throws std::runtime_error if the
/// process cannot be started.
pid_t start_child(const std::vector<std::string>& argv, const std::string& output_file = "");

/// Waits for the child; its exit code, or 128 + the signal that ended it.
int wait_for_child(pid_t pid);

/// This program's own executable, for children that run pilelab again.
std::string own_executable();

}  // namespace pilelab::app
