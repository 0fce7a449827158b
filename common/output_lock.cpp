#include "common/output_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/error.h"

namespace pilelab {

OutputLock::OutputLock(const std::string& dir, const std::string& command) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(dir + ": cannot create the output folder: " + ec.message() + " (expected a folder this process can write)");
  const std::string path = (std::filesystem::path(dir) / ".pilelab.lock").string();
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0)
    throw InputError(dir + ": cannot create the lock file " + path + ": " + std::strerror(errno) +
                     " (expected a folder this process can write)");
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    std::ifstream in(path);
    std::stringstream holder;
    holder << in.rdbuf();
    ::close(fd_);
    fd_ = -1;
    if (error == EWOULDBLOCK)
      throw InputError(dir + ": another pilelab process writes into this folder (" + path + ": " +
                       (holder.str().empty() ? std::string("no details") : holder.str()) +
                       "); wait for it to end, or give another output folder");
    throw InputError(dir + ": cannot lock " + path + ": " + std::strerror(error));
  }
  // Who holds it, for the message of a refused second writer.
  const std::string text = "pid " + std::to_string(::getpid()) + ", " + command;
  if (::ftruncate(fd_, 0) == 0 && ::pwrite(fd_, text.data(), text.size(), 0) < 0) {
    // The lock holds without the note; a refused writer then says "no details".
  }
}

OutputLock::~OutputLock() {
  if (fd_ < 0) return;
  // Emptied, not removed: removing a locked file lets a second writer lock a new file of the
  // same name while a third still holds the old one. An empty file also keeps two runs' folders
  // byte-identical.
  if (::ftruncate(fd_, 0) != 0) {
    // Nothing to do: the lock is released by close() all the same.
  }
  ::close(fd_);
}

}  // namespace pilelab
