#pragma once
// A damaged HDF5 file can crash or hang the HDF5 library itself (1.10 on Debian 12: found by
// fuzzing, docs/RELIABILITY.md), where no check of ours runs. Before a file is opened for
// reading, a child process reads every object, attribute and dataset in it; if the child dies
// or takes longer than the limit, the file is refused with the reason, and the run goes on to
// stop cleanly instead of crashing.
#include <string>

namespace pilelab {

/// Throws InputError naming the file if HDF5 cannot read all of it within limit_s seconds
/// without crashing (PILELAB_HDF5_PROBE_LIMIT_S overrides the limit). Costs one fork and one
/// read of the file (about 10 ms for a paper pile's dem.h5), once per version of the file (its
/// inode, size and modification time) and process.
void probe_hdf5_file(const std::string& path, unsigned limit_s = 60);

}  // namespace pilelab
