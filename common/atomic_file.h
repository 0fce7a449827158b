#pragma once
// Output files are written under a temporary name in the same directory and renamed into
// place when complete, so a killed run never leaves a half-written file where a good one was.
#include <functional>
#include <string>

namespace pilelab {

/// Calls write(tmp_path) and then renames tmp_path to path. If write throws, the temporary
/// file is removed and the exception propagates; path is untouched.
void write_atomically(const std::string& path, const std::function<void(const std::string&)>& write);

/// Writes a whole text file atomically.
void write_text_atomically(const std::string& path, const std::string& text);

/// Makes dir (and its parents) and proves it writable by creating and removing a probe file,
/// so that a run learns at its start, not after hours, that its outputs cannot be written.
/// Removes temporary files (NAME.tmp.PID, NAME.tmp.PID.EXT) that dead processes left in dir. Throws InputError
/// naming the directory and the system's reason.
void prepare_output_directory(const std::string& dir);

/// Reads a whole text file; throws InputError naming the file if it cannot be read.
std::string read_text_file(const std::string& path);

}  // namespace pilelab
