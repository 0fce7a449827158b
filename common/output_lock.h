#pragma once
// One writer per output folder: a command that writes OUT/ holds OUT/.pilelab.lock (an advisory
// flock, which the kernel releases when the process ends however it ends, so a lock of a killed
// run is never stale) for as long as it runs. A second command on the same folder is refused with
// the holder's process id and command, instead of interleaving its files with the first's.
#include <string>

namespace pilelab {

class OutputLock {
 public:
  /// Creates dir if needed and locks it for `command` (e.g. "pilelab dem scene.toml"); throws
  /// InputError naming the folder, the holder's pid and command if another process holds it.
  OutputLock(const std::string& dir, const std::string& command);
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace pilelab
