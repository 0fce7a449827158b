#pragma once
// What every fuzz target shares. A target feeds one input to one of pilelab's readers; a reader
// may refuse it only with InputError (a clear message naming the file and what was expected).
// Anything else that escapes — another exception, a crash, a sanitizer report, a hang — is a
// defect, and aborts so that libFuzzer keeps the input.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <string>
#include <unistd.h>

#include "common/error.h"

namespace pilelab::fuzz {

/// Runs the reader; InputError is the expected refusal (printed with PILELAB_FUZZ_VERBOSE set),
/// anything else aborts.
template <class Reader>
void expect_clean_refusal(const char* target, Reader&& read) {
  try {
    read();
  } catch (const InputError& e) {
    if (std::getenv("PILELAB_FUZZ_VERBOSE")) std::fprintf(stderr, "fuzz %s: refused: %s\n", target, e.what());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz %s: an exception other than InputError escaped: %s\n", target, e.what());
    std::abort();
  } catch (...) {
    std::fprintf(stderr, "fuzz %s: a non-standard exception escaped\n", target);
    std::abort();
  }
}

/// The input as a file of its own (the readers take paths), removed when done.
class InputFile {
 public:
  // A new name for every input: the HDF5 probe reads each version of a file once per process,
  // and a file rewritten in place within the clock's resolution could pass for the last one.
  InputFile(const std::uint8_t* data, std::size_t size, const char* suffix)
      : path_("/tmp/pilelab-fuzz-" + std::to_string(::getpid()) + "-" + std::to_string(next_number()) + suffix) {
    std::ofstream(path_, std::ios::binary).write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  ~InputFile() { std::remove(path_.c_str()); }
  const std::string& path() const { return path_; }

 private:
  static unsigned long next_number() {
    static unsigned long n = 0;
    return n++;
  }
  std::string path_;
};

}  // namespace pilelab::fuzz
