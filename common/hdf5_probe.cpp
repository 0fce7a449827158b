#include "common/hdf5_probe.h"

#include <hdf5.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "common/error.h"

namespace pilelab {

namespace {

// Reads an attribute's value into a buffer of its own type (variable-length ones reclaimed).
herr_t read_attribute(hid_t object, const char* name, const H5A_info_t*, void*) {
  const hid_t a = H5Aopen(object, name, H5P_DEFAULT);
  if (a < 0) return -1;
  const hid_t type = H5Aget_type(a), space = H5Aget_space(a);
  herr_t status = -1;
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  const size_t size = H5Tget_size(type);
  if (n >= 0 && size > 0 && static_cast<double>(n) * size < 1e9) {
    std::vector<unsigned char> buffer(static_cast<size_t>(n) * size + 1);
    status = H5Aread(a, type, buffer.data());
    if (status >= 0 && (H5Tdetect_class(type, H5T_VLEN) > 0 || H5Tis_variable_str(type) > 0))
      H5Dvlen_reclaim(type, space, H5P_DEFAULT, buffer.data());
  }
  H5Sclose(space);
  H5Tclose(type);
  H5Aclose(a);
  return status;
}

// Every object: its attributes, and a dataset's data in its own type. On failure, `failed`
// (a std::string) names the object and the part that did not read.
herr_t read_object(hid_t file, const char* name, const H5O_info_t* info, void* failed) {
  std::string& failure = *static_cast<std::string*>(failed);
  failure = std::string("/") + name + ": cannot open it";
  const hid_t object = H5Oopen(file, name, H5P_DEFAULT);
  if (object < 0) return -1;
  failure = std::string("/") + name + ": its attributes do not read";
  herr_t status = H5Aiterate2(object, H5_INDEX_NAME, H5_ITER_NATIVE, nullptr, read_attribute, nullptr);
  if (status >= 0 && info->type == H5O_TYPE_DATASET) {
    const hid_t type = H5Dget_type(object), space = H5Dget_space(object);
    const hssize_t n = H5Sget_simple_extent_npoints(space);
    const size_t size = H5Tget_size(type);
    status = -1;
    failure = std::string("/") + name + ": its data do not read (they fail their checksum, or the file is damaged)";
    if (n >= 0 && size > 0 && static_cast<double>(n) * size < 4e9) {
      std::vector<unsigned char> buffer(static_cast<size_t>(n) * size + 1);
      status = n == 0 ? 0 : H5Dread(object, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data());
      if (status >= 0 && n > 0 && (H5Tdetect_class(type, H5T_VLEN) > 0 || H5Tis_variable_str(type) > 0))
        H5Dvlen_reclaim(type, space, H5P_DEFAULT, buffer.data());
    }
    H5Sclose(space);
    H5Tclose(type);
  }
  H5Oclose(object);
  return status;
}

// The child's work: 0 if every part of the file reads, 1 if HDF5 refuses a part, whose name
// and failure go to report_fd for the parent's message.
int read_everything(const char* path, int report_fd) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) return 1;
  std::string failure;
  const herr_t status = H5Ovisit2(file, H5_INDEX_NAME, H5_ITER_NATIVE, read_object, &failure, H5O_INFO_BASIC);
  if (status < 0 && report_fd >= 0) {
    failure.resize(std::min<std::size_t>(failure.size(), 1000));
    (void)!::write(report_fd, failure.data(), failure.size());
  }
  return status < 0 ? 1 : 0;  // the file is not closed: the child ends without HDF5's clean-up
}

}  // namespace

void probe_hdf5_file(const std::string& path, unsigned limit_s) {
  // A stage opens the same file several times (compare reads fields.h5 for the fields, the
  // piles, the pile's scale): each version of a file is read in a child once per process.
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return;  // the open that follows names the problem
  const std::string version = path + '|' + std::to_string(st.st_dev) + ':' + std::to_string(st.st_ino) + '|' +
                              std::to_string(st.st_size) + '|' + std::to_string(st.st_mtim.tv_sec) + '.' +
                              std::to_string(st.st_mtim.tv_nsec);
  static std::mutex mutex;
  static std::set<std::string> readable;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    if (readable.count(version)) return;
  }
  if (const char* limit = std::getenv("PILELAB_HDF5_PROBE_LIMIT_S")) limit_s = static_cast<unsigned>(std::max(1, std::atoi(limit)));
  int report[2] = {-1, -1};  // the child names the part that did not read
  if (::pipe2(report, O_CLOEXEC) != 0) report[0] = report[1] = -1;
  const auto close_report = [&] {
    for (int& fd : report)
      if (fd >= 0) ::close(fd), fd = -1;
  };
  const pid_t child = fork();
  if (child < 0) {
    close_report();
    return;  // no process to spare: read the file as it is
  }
  if (child == 0) {
    // The child dies with its parent, and a hang ends with SIGALRM whatever handler the parent
    // had installed (libFuzzer has one: found when a fuzzed file hung HDF5 past every limit).
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() == 1) _exit(1);  // the parent died before prctl took effect
    signal(SIGALRM, SIG_DFL);
    sigset_t alarm_only;
    sigemptyset(&alarm_only);
    sigaddset(&alarm_only, SIGALRM);
    sigprocmask(SIG_UNBLOCK, &alarm_only, nullptr);
    alarm(limit_s);
    _exit(read_everything(path.c_str(), report[1]));
  }
  if (report[1] >= 0) ::close(report[1]), report[1] = -1;
  // The parent keeps the limit too: a child still running a second after it is killed.
  int status = 0;
  bool killed = false;
  const auto start = std::chrono::steady_clock::now();
  while (true) {
    const pid_t done = waitpid(child, &status, WNOHANG);
    if (done == child) break;
    // A host that ignores SIGCHLD has its children reaped for it: the outcome is unknown, so
    // the file is not taken as read (not cached); the reader's own checks follow.
    if (done < 0 && errno != EINTR) return;
    const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!killed && waited > limit_s + 1.0) {
      kill(child, SIGKILL);
      killed = true;
    }
    usleep(waited < 0.1 ? 500 : 10000);  // most files are read in milliseconds
  }
  std::string failure(1000, '\0');
  const ssize_t reported = report[0] >= 0 ? ::read(report[0], failure.data(), failure.size()) : 0;
  failure.resize(reported > 0 ? static_cast<std::size_t>(reported) : 0);
  close_report();
  if (killed && !(WIFEXITED(status) && WEXITSTATUS(status) == 0))
    throw InputError(path + ": HDF5 did not finish reading this file within " + std::to_string(limit_s) +
                     " s (a damaged file can make it loop)");
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
    const std::lock_guard<std::mutex> lock(mutex);
    readable.insert(version);
    return;
  }
  if (WIFEXITED(status))
    throw InputError(path + ": " + (failure.empty() ? std::string("HDF5 cannot read every part of this file (damaged or truncated?)")
                                                    : failure + " (a damaged file)"));
  const int signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  if (signal == SIGALRM)
    throw InputError(path + ": HDF5 did not finish reading this file within " + std::to_string(limit_s) +
                     " s (a damaged file can make it loop)");
  throw InputError(path + ": HDF5 crashed reading this file (signal " + std::to_string(signal) + ", " +
                   strsignal(signal) + "): it is damaged");
}

}  // namespace pilelab
