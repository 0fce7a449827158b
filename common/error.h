#pragma once
// The one exception type pilelab throws for bad input or failed I/O. Its message names the
// file, the field and what was expected, so the command line can print it and exit non-zero.
#include <stdexcept>
#include <string>

namespace pilelab {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace pilelab
