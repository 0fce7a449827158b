#include "apps/run_log.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ctime>

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include "common/error.h"

namespace pilelab::app {

namespace {
// Writes all of [data, data + n) to fd, as far as fd takes it (a closed console is not an error
// worth stopping a run for).
void write_all(int fd, const char* data, ssize_t n) {
  while (n > 0) {
    const ssize_t written = ::write(fd, data, static_cast<std::size_t>(n));
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) return;
    data += written;
    n -= written;
  }
}
}  // namespace

RunLog::RunLog(const std::string& path, const std::string& command) : path_(path) {
  log_fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (log_fd_ < 0) throw InputError(path + ": cannot open the run's log: " + std::strerror(errno));
  char when[64];
  const std::time_t now = std::time(nullptr);
  std::strftime(when, sizeof when, "%Y-%m-%d %H:%M:%S UTC", std::gmtime(&now));
  const std::string header = "=== " + std::string(when) + ": " + command + "\n";
  write_all(log_fd_, header.data(), static_cast<ssize_t>(header.size()));
  std::fflush(stdout);
  std::fflush(stderr);
  for (int k = 0; k < 2; ++k) {
    const int stream = k + 1;  // stdout, stderr
    int ends[2];
    if (::pipe2(ends, O_CLOEXEC) != 0) throw InputError(path + ": cannot start the run's log: " + std::strerror(errno));
    console_[k] = ::fcntl(stream, F_DUPFD_CLOEXEC, 0);
    ::dup2(ends[1], stream);  // the new stdout or stderr is inherited by children (no CLOEXEC)
    ::close(ends[1]);
    pipe_read_[k] = ends[0];
  }
  copier_ = std::thread([this] { copy(); });
}

// Copies each pipe to its console stream and to the log until both are closed, or until the
// run ends and nothing more is waiting (a child that outlives the run keeps its end open).
void RunLog::copy() {
  pollfd fds[2] = {{pipe_read_[0], POLLIN, 0}, {pipe_read_[1], POLLIN, 0}};
  char buffer[65536];
  while (fds[0].fd >= 0 || fds[1].fd >= 0) {
    const int ready = ::poll(fds, 2, 100);
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) {
      if (stopping_) return;
      continue;
    }
    for (int k = 0; k < 2; ++k) {
      if (fds[k].fd < 0 || fds[k].revents == 0) continue;
      const ssize_t n = ::read(fds[k].fd, buffer, sizeof buffer);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        fds[k].fd = -1;  // closed: ignored by poll from now on
        continue;
      }
      write_all(console_[k], buffer, n);
      write_all(log_fd_, buffer, n);
    }
  }
}

RunLog::~RunLog() {
  std::fflush(stdout);
  std::fflush(stderr);
  for (int k = 0; k < 2; ++k) ::dup2(console_[k], k + 1);  // closes this process's write ends
  stopping_ = true;
  copier_.join();
  for (int k = 0; k < 2; ++k) {
    ::close(console_[k]);
    ::close(pipe_read_[k]);
  }
  ::close(log_fd_);
}

}  // namespace pilelab::app
