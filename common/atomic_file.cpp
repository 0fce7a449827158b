#include "common/atomic_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <fcntl.h>
#include <signal.h>
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
    if (!out) throw InputError("cannot create " + tmp + ": " + std::strerror(errno));
    out << text;
    out.close();
    if (!out) throw InputError("cannot write " + tmp + ": " + std::strerror(errno ? errno : EIO));
  });
}

namespace {
// The PID of NAME.tmp.PID, or of NAME.tmp.PID.EXT (a library that picks its format from the
// extension, as gmsh does, writes that), or 0 when the name is of neither form.
pid_t temporary_file_owner(const std::string& name) {
  const std::size_t dot = name.rfind(".tmp.");
  if (dot == std::string::npos) return 0;
  std::string digits = name.substr(dot + 5);
  const std::size_t extension = digits.find('.');
  if (extension != std::string::npos) digits.resize(extension);
  if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) return 0;
  return static_cast<pid_t>(std::stol(digits));
}
}  // namespace

void prepare_output_directory(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir + ": cannot create the output directory: " + ec.message());
  const std::string probe = (fs::path(dir) / (".pilelab-write-probe." + std::to_string(::getpid()))).string();
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) throw InputError(dir + ": cannot write in the output directory: " + std::strerror(errno));
  const bool written = ::write(fd, "x", 1) == 1;
  const int error = errno;
  ::close(fd);
  ::unlink(probe.c_str());
  if (!written) throw InputError(dir + ": cannot write in the output directory: " + std::strerror(error));
  // Leftovers of killed runs: a temporary file whose writer is no longer alive.
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const pid_t owner = temporary_file_owner(entry.path().filename().string());
    if (owner > 0 && owner != ::getpid() && ::kill(owner, 0) != 0 && errno == ESRCH) fs::remove_all(entry.path(), ec);
  }
}

std::string read_text_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open file for reading");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace pilelab
