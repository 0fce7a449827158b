#pragma once
// The log of a run: what `pilelab run` and the processes it starts (members, the figure script)
// print on the console, kept in OUT/run.log as well, so that a run's warnings and progress are
// on the disk beside its results (an ensemble's members had one each; a single run had none).
#include <atomic>
#include <string>
#include <thread>

namespace pilelab::app {

class RunLog {
 public:
  /// From now on, everything written to stdout and stderr (by this process or its children,
  /// which inherit them) also goes to `path`, appended after a header line naming `command`.
  /// The console still shows it, stdout on stdout and stderr on stderr.
  RunLog(const std::string& path, const std::string& command);
  /// Restores stdout and stderr and writes out what is still in the pipes.
  ~RunLog();
  RunLog(const RunLog&) = delete;
  RunLog& operator=(const RunLog&) = delete;
  const std::string& path() const { return path_; }

 private:
  void copy();
  std::string path_;
  int log_fd_ = -1;
  int console_[2] = {-1, -1};  ///< the original stdout and stderr
  int pipe_read_[2] = {-1, -1};
  std::atomic<bool> stopping_{false};
  std::thread copier_;
};

}  // namespace pilelab::app
