#include "common/atomic_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <fcntl.h>
#include <unistd.h>

#include "common/error.h"

namespace pilelab {

namespace {
// Forces a file's (or a directory's) contents to the disk. Without it a crash after the
// rename could leave the new name pointing at blocks that were never written.
// Returns an empty string, or why it failed.
std::string sync_to_disk(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0) return std::string("cannot open it: ") + std::strerror(errno);
  const bool ok = ::fsync(fd) == 0;
  const int error = errno;
  ::close(fd);
  return ok ? std::string() : std::string("fsync failed: ") + std::strerror(error);
}
}  // namespace

void write_atomically(const std::string& path, const std::function<void(const std::string&)>& write) {
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  try {
    write(tmp);
    const std::string failed = sync_to_disk(tmp);
    if (!failed.empty()) throw InputError("cannot write " + tmp + " to the disk: " + failed);
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw InputError("cannot move " + tmp + " to " + path + ": " + ec.message());
  }
  // The rename itself lives in the directory; a failure here leaves the new file in place.
  const std::string dir = std::filesystem::path(path).parent_path().string();
  sync_to_disk(dir.empty() ? "." : dir);
}

void write_text_atomically(const std::string& path, const std::string& text) {
  write_atomically(path, [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    out.close();
    if (!out) throw InputError("cannot write " + tmp);
  });
}

std::string read_text_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open file for reading");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace pilelab
