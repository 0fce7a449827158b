#pragma once
// A thin RAII layer over the HDF5 C API: enough to write self-describing files (datasets with
// a "unit" attribute, string attributes) and to read them back with errors that name the file
// and the dataset. Uses the MPI build of HDF5 that deal.II links, serially.
#include <cstdint>
#include <string>
#include <vector>

namespace pilelab {

/// Keeps the HDF5 library from closing its objects in an exit handler. After a failed write
/// (a full disk) HDF5 holds objects it can no longer flush, and its exit handler crashed on
/// them (a segmentation fault after the clear error message). Our files are closed by RAII,
/// so nothing is left for that handler to do. Call first in main, before any HDF5 use.
void disable_hdf5_exit_handler();

class H5File {
 public:
  /// Creates (truncates) a file for writing.
  static H5File create(const std::string& path);
  /// Opens an existing file read-only; throws InputError if it is missing or not HDF5.
  static H5File open_read(const std::string& path);

  H5File(H5File&& other) noexcept;
  H5File& operator=(H5File&&) = delete;
  H5File(const H5File&) = delete;
  ~H5File();

  /// Closes the file, which flushes what HDF5 still caches; throws InputError if that fails
  /// (a full disk often shows only here). Writers call it before the file is renamed into
  /// place; the destructor closes silently, for files abandoned by an exception.
  void close();

  const std::string& path() const { return path_; }
  bool exists(const std::string& object_path) const;
  /// Names of the members of a group, in HDF5's (alphabetical) order.
  std::vector<std::string> list(const std::string& group_path) const;

  // Datasets: dims gives the shape (row-major); an empty dims means a 1-D array of data.size().
  void write(const std::string& dataset, const std::vector<double>& data, std::vector<std::uint64_t> dims = {},
             const std::string& unit = "");
  void write(const std::string& dataset, const std::vector<std::int64_t>& data,
             std::vector<std::uint64_t> dims = {}, const std::string& unit = "");
  void write(const std::string& dataset, const std::vector<std::uint64_t>& data,
             std::vector<std::uint64_t> dims = {});
  void write_string(const std::string& dataset, const std::string& text);

  std::vector<double> read_doubles(const std::string& dataset, std::vector<std::uint64_t>* dims = nullptr) const;
  /// read_doubles that refuses a NaN or an infinity, naming the dataset and its first bad index.
  std::vector<double> read_finite_doubles(const std::string& dataset, std::vector<std::uint64_t>* dims = nullptr) const;
  std::vector<std::int64_t> read_ints(const std::string& dataset, std::vector<std::uint64_t>* dims = nullptr) const;
  std::vector<std::uint64_t> read_uints(const std::string& dataset) const;
  std::string read_string(const std::string& dataset) const;

  // Attributes on a group or dataset (created as a group if it does not exist yet).
  void set_attribute(const std::string& object_path, const std::string& name, const std::string& value);
  void set_attribute(const std::string& object_path, const std::string& name, double value);
  void set_attribute(const std::string& object_path, const std::string& name, std::int64_t value);
  std::string attribute_string(const std::string& object_path, const std::string& name) const;
  double attribute_double(const std::string& object_path, const std::string& name) const;
  std::int64_t attribute_int(const std::string& object_path, const std::string& name) const;
  /// Whether the object exists and carries the attribute.
  bool has_attribute(const std::string& object_path, const std::string& name) const;

 private:
  H5File(std::int64_t id, std::string path) : id_(id), path_(std::move(path)) {}
  [[noreturn]] void fail(const std::string& object, const std::string& what) const;
  void ensure_group(const std::string& group_path);
  std::int64_t id_ = -1;
  std::string path_;
};

}  // namespace pilelab
