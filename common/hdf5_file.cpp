#include "common/hdf5_file.h"

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <sstream>

#include "common/error.h"
#include "common/hdf5_probe.h"

namespace pilelab {

namespace {
struct Silence {  // HDF5 prints its own error stack by default; we report errors ourselves.
  Silence() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }
};
void silence() { static Silence s; }

hsize_t product(const std::vector<std::uint64_t>& dims) {
  hsize_t n = 1;
  for (auto d : dims) n *= d;
  return n;
}

// Closes an HDF5 handle of any kind on scope exit.
struct Handle {
  hid_t id;
  explicit Handle(hid_t i) : id(i) {}
  ~Handle() {
    if (id >= 0) H5Idec_ref(id);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& other) noexcept : id(other.id) { other.id = -1; }
};

// Creation properties of an object (file root, group or dataset) without the creation and
// modification times HDF5 records by default: with them, two runs of the same scene and seed
// would write files that differ in the bytes of those clocks.
hid_t untimed(hid_t property_class) {
  hid_t plist = H5Pcreate(property_class);
  H5Pset_obj_track_times(plist, 0);
  return plist;
}

bool is_group(hid_t file, const std::string& path) {
  if (H5Oexists_by_name(file, path.c_str(), H5P_DEFAULT) <= 0) return false;  // e.g. a dangling soft link
  const Handle group(H5Gopen2(file, path.c_str(), H5P_DEFAULT));
  return group.id >= 0;
}

// Creates every missing group along `path` ("/a/b/c" makes /a, /a/b and /a/b/c) with untimed
// properties; HDF5's own intermediate-group creation would use the timed defaults.
void create_groups(hid_t file, const std::string& path, const std::string& file_path) {
  std::size_t end = 0;
  while (end != std::string::npos) {
    end = path.find('/', end + 1);
    const std::string prefix = path.substr(0, end);
    if (prefix.empty() || prefix == "/") continue;
    if (H5Lexists(file, prefix.c_str(), H5P_DEFAULT) > 0) {
      if (is_group(file, prefix)) continue;
      throw InputError(file_path + ": " + prefix + " exists and is not a group, so nothing can be written below it");
    }
    Handle gcpl(untimed(H5P_GROUP_CREATE));
    Handle g(H5Gcreate2(file, prefix.c_str(), H5P_DEFAULT, gcpl.id, H5P_DEFAULT));
    if (g.id < 0) throw InputError(file_path + ": " + prefix + ": cannot create group");
  }
}

// Creates the groups that hold `object_path` (all but its last component).
void create_parent_groups(hid_t file, const std::string& object_path, const std::string& file_path) {
  const std::size_t slash = object_path.rfind('/');
  if (slash != std::string::npos && slash > 0) create_groups(file, object_path.substr(0, slash), file_path);
}
}  // namespace

void disable_hdf5_exit_handler() { H5dont_atexit(); }

H5File H5File::create(const std::string& path) {
  silence();
  Handle fcpl(untimed(H5P_FILE_CREATE));  // the root group's times
  // The file format of HDF5 1.10 and later, whose superblock, object headers, B-trees and heaps
  // carry checksums that HDF5 verifies on reading: a damaged pilelab file is refused at its
  // first damaged structure instead of being parsed. (Fuzzing the format before 1.8, which has
  // none, crashed and hung HDF5 1.10's reader; docs/RELIABILITY.md.) 1.10's compact index of a
  // dataset stored in one chunk keeps the checksummed datasets (with_checksum) as small as
  // contiguous ones; 1.8's B-tree index made a quick pile's dem.h5 48 % larger.
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS));
  H5Pset_libver_bounds(fapl.id, H5F_LIBVER_V110, H5F_LIBVER_LATEST);
  hid_t id = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, fcpl.id, fapl.id);
  if (id < 0) throw InputError(path + ": cannot create HDF5 file");
  return H5File(id, path);
}

H5File H5File::open_read(const std::string& path) {
  silence();
  if (!std::filesystem::exists(path)) throw InputError(path + ": no such file");
  if (H5Fis_hdf5(path.c_str()) <= 0) throw InputError(path + ": not an HDF5 file (corrupt or truncated?)");
  probe_hdf5_file(path);  // a damaged file must not crash or hang the reader (hdf5_probe.h)
  hid_t id = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (id < 0) throw InputError(path + ": cannot open as HDF5 (corrupt?)");
  return H5File(id, path);
}

H5File::H5File(H5File&& o) noexcept : id_(o.id_), path_(std::move(o.path_)) { o.id_ = -1; }

H5File::~H5File() {
  if (id_ >= 0) H5Fclose(id_);
}

void H5File::close() {
  const std::int64_t id = id_;
  id_ = -1;
  if (id >= 0 && H5Fclose(id) < 0)
    throw InputError(path_ + ": cannot finish writing the HDF5 file (is the disk full?)");
}

void H5File::fail(const std::string& object, const std::string& what) const {
  throw InputError(path_ + ": " + object + ": " + what);
}

bool H5File::exists(const std::string& object_path) const {
  // Check each prefix: H5Lexists fails on a path whose parent is missing.
  std::size_t pos = 0;
  while (true) {
    pos = object_path.find('/', pos + 1);
    const std::string prefix = object_path.substr(0, pos);
    if (!prefix.empty() && prefix != "/" && H5Lexists(id_, prefix.c_str(), H5P_DEFAULT) <= 0) return false;
    if (pos == std::string::npos) return true;
  }
}

std::vector<std::string> H5File::list(const std::string& group_path) const {
  Handle g(H5Gopen2(id_, group_path.c_str(), H5P_DEFAULT));
  if (g.id < 0) fail(group_path, "no such group");
  H5G_info_t info;
  H5Gget_info(g.id, &info);
  std::vector<std::string> names;
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    char buf[512];
    ssize_t n = H5Lget_name_by_idx(g.id, ".", H5_INDEX_NAME, H5_ITER_INC, i, buf, sizeof buf, H5P_DEFAULT);
    if (n > 0) names.emplace_back(buf, static_cast<std::size_t>(n));
  }
  return names;
}

void H5File::ensure_group(const std::string& group_path) {
  if (group_path.empty() || group_path == "/" || exists(group_path)) return;
  create_groups(id_, group_path, path_);
}

namespace {
// Stores a dataset in chunks that carry HDF5's Fletcher-32 checksum, which HDF5 verifies on
// every read: a flipped bit in the data (HDF5's own metadata has checksums already) becomes a
// read error instead of a silently different pile. Chunks of at most 1 MiB, whole rows; an
// empty dataset has no data to protect and no chunk shape, so it stays contiguous.
void with_checksum(hid_t dcpl, const std::vector<hsize_t>& dims, std::size_t element_bytes) {
  hsize_t count = 1;
  for (hsize_t d : dims) count *= d;
  if (count == 0) return;
  std::vector<hsize_t> chunk = dims;
  const hsize_t row_bytes = count / dims[0] * element_bytes;
  chunk[0] = std::clamp<hsize_t>((hsize_t(1) << 20) / std::max<hsize_t>(row_bytes, 1), 1, dims[0]);
  H5Pset_chunk(dcpl, static_cast<int>(chunk.size()), chunk.data());
  H5Pset_fletcher32(dcpl);
}

template <class T>
void write_dataset(hid_t file, const std::string& name, const std::vector<T>& data,
                   std::vector<std::uint64_t> dims, hid_t type, const std::string& path) {
  if (dims.empty()) dims = {data.size()};
  if (product(dims) != data.size()) throw InputError(path + ": " + name + ": shape does not match data");
  std::vector<hsize_t> hd(dims.begin(), dims.end());
  Handle space(H5Screate_simple(static_cast<int>(hd.size()), hd.data(), nullptr));
  create_parent_groups(file, name, path);
  Handle dcpl(untimed(H5P_DATASET_CREATE));
  with_checksum(dcpl.id, hd, H5Tget_size(type));
  Handle ds(H5Dcreate2(file, name.c_str(), type, space.id, H5P_DEFAULT, dcpl.id, H5P_DEFAULT));
  if (ds.id < 0) throw InputError(path + ": " + name + ": cannot create dataset");
  if (!data.empty() && H5Dwrite(ds.id, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()) < 0)
    throw InputError(path + ": " + name + ": cannot write dataset");
}

template <class T>
std::vector<T> read_dataset(hid_t file, const std::string& name, hid_t mem_type, std::vector<std::uint64_t>* dims,
                            const std::string& path) {
  Handle ds(H5Dopen2(file, name.c_str(), H5P_DEFAULT));
  if (ds.id < 0) throw InputError(path + ": " + name + ": missing dataset");
  Handle space(H5Dget_space(ds.id));
  int rank = H5Sget_simple_extent_ndims(space.id);
  if (rank < 0) throw InputError(path + ": " + name + ": unreadable dataspace");
  std::vector<hsize_t> hd(static_cast<std::size_t>(rank));
  H5Sget_simple_extent_dims(space.id, hd.data(), nullptr);
  // A damaged header can claim any shape (one found by fuzzing claimed 4 TB): before
  // allocating, the claim must fit what the file stores. Stored data expands by at most about
  // 1000 on decompression (deflate's limit is 1032:1), and never beyond the file holding it.
  hsize_t n = 1;
  bool overflow = false;
  for (auto d : hd) {
    overflow = overflow || (d != 0 && n > std::numeric_limits<hsize_t>::max() / d);
    n *= d;
  }
  Handle file_type(H5Dget_type(ds.id));
  const hsize_t stored = H5Dget_storage_size(ds.id);
  const double claimed_bytes = static_cast<double>(n) * static_cast<double>(std::max<std::size_t>(H5Tget_size(file_type.id), 1));
  if (overflow || claimed_bytes > 1100.0 * static_cast<double>(stored) + 65536.0) {
    std::ostringstream m;
    m << path << ": " << name << ": the dataset's shape claims " << claimed_bytes << " bytes of data, but the file stores "
      << stored << " for it (a damaged file)";
    throw InputError(m.str());
  }
  std::vector<T> out(n);
  if (n > 0 && H5Dread(ds.id, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
    throw InputError(path + ": " + name + ": cannot read dataset (its data fail their checksum, or are of the wrong type: a damaged file)");
  if (dims) dims->assign(hd.begin(), hd.end());
  return out;
}
}  // namespace

void H5File::write(const std::string& dataset, const std::vector<double>& data, std::vector<std::uint64_t> dims,
                   const std::string& unit) {
  write_dataset(id_, dataset, data, std::move(dims), H5T_NATIVE_DOUBLE, path_);
  if (!unit.empty()) set_attribute(dataset, "unit", unit);
}

void H5File::write(const std::string& dataset, const std::vector<std::int64_t>& data,
                   std::vector<std::uint64_t> dims, const std::string& unit) {
  write_dataset(id_, dataset, data, std::move(dims), H5T_NATIVE_INT64, path_);
  if (!unit.empty()) set_attribute(dataset, "unit", unit);
}

void H5File::write(const std::string& dataset, const std::vector<std::uint64_t>& data,
                   std::vector<std::uint64_t> dims) {
  write_dataset(id_, dataset, data, std::move(dims), H5T_NATIVE_UINT64, path_);
}

namespace {
// Strings are written as variable-length UTF-8, as h5py writes a Python str (and reads one back
// as str). They live in the file's global heap, which HDF5 1.10 can loop on for ever when it is
// damaged (found by fuzzing); the probe of every file before it is read (hdf5_probe.h) turns
// that into a refusal.
Handle string_type() {
  Handle type(H5Tcopy(H5T_C_S1));
  H5Tset_size(type.id, H5T_VARIABLE);
  H5Tset_cset(type.id, H5T_CSET_UTF8);
  return type;
}

// A string dataset or attribute of either kind (variable-length, as pilelab and h5py write them,
// or fixed-length, as other tools do), read through `read(memory_type, buffer)`.
template <class Read>
bool read_any_string(hid_t file_type, Read&& read, std::string& out) {
  if (H5Tget_class(file_type) != H5T_STRING) return false;
  if (H5Tis_variable_str(file_type) > 0) {
    Handle memory(H5Tcopy(H5T_C_S1));
    H5Tset_size(memory.id, H5T_VARIABLE);
    H5Tset_cset(memory.id, H5Tget_cset(file_type));
    char* p = nullptr;
    if (read(memory.id, static_cast<void*>(&p)) < 0 || !p) return false;
    out.assign(p);
    H5free_memory(p);
    return true;
  }
  const std::size_t n = H5Tget_size(file_type);
  if (n == 0 || n > (std::size_t(1) << 30)) return false;
  std::string s(n, '\0');
  if (read(file_type, static_cast<void*>(s.data())) < 0) return false;
  s.resize(std::strlen(s.c_str()));  // NUL-padded or NUL-terminated
  out = std::move(s);
  return true;
}
}  // namespace

void H5File::write_string(const std::string& dataset, const std::string& text) {
  Handle type = string_type();
  Handle space(H5Screate(H5S_SCALAR));
  create_parent_groups(id_, dataset, path_);
  Handle dcpl(untimed(H5P_DATASET_CREATE));
  Handle ds(H5Dcreate2(id_, dataset.c_str(), type.id, space.id, H5P_DEFAULT, dcpl.id, H5P_DEFAULT));
  if (ds.id < 0) fail(dataset, "cannot create string dataset");
  const char* p = text.c_str();
  if (H5Dwrite(ds.id, type.id, H5S_ALL, H5S_ALL, H5P_DEFAULT, &p) < 0) fail(dataset, "cannot write string");
}

std::vector<double> H5File::read_doubles(const std::string& dataset, std::vector<std::uint64_t>* dims) const {
  return read_dataset<double>(id_, dataset, H5T_NATIVE_DOUBLE, dims, path_);
}
std::vector<std::int64_t> H5File::read_ints(const std::string& dataset, std::vector<std::uint64_t>* dims) const {
  return read_dataset<std::int64_t>(id_, dataset, H5T_NATIVE_INT64, dims, path_);
}
std::vector<std::uint64_t> H5File::read_uints(const std::string& dataset) const {
  return read_dataset<std::uint64_t>(id_, dataset, H5T_NATIVE_UINT64, nullptr, path_);
}

std::string H5File::read_string(const std::string& dataset) const {
  Handle ds(H5Dopen2(id_, dataset.c_str(), H5P_DEFAULT));
  if (ds.id < 0) fail(dataset, "missing dataset");
  Handle type(H5Dget_type(ds.id));
  Handle space(H5Dget_space(ds.id));
  if (H5Sget_simple_extent_npoints(space.id) != 1) fail(dataset, "not a single string");
  std::string s;
  const auto read = [&](hid_t memory, void* buffer) { return H5Dread(ds.id, memory, H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer); };
  if (!read_any_string(type.id, read, s)) fail(dataset, "not a string");
  return s;
}

namespace {
hid_t open_object(hid_t file, const std::string& path) { return H5Oopen(file, path.c_str(), H5P_DEFAULT); }
}  // namespace

void H5File::set_attribute(const std::string& object_path, const std::string& name, const std::string& value) {
  ensure_group(object_path);
  Handle obj(open_object(id_, object_path));
  if (obj.id < 0) fail(object_path, "no such object");
  Handle type = string_type();
  Handle space(H5Screate(H5S_SCALAR));
  if (H5Aexists(obj.id, name.c_str()) > 0) H5Adelete(obj.id, name.c_str());
  Handle a(H5Acreate2(obj.id, name.c_str(), type.id, space.id, H5P_DEFAULT, H5P_DEFAULT));
  const char* text = value.c_str();
  if (a.id < 0 || H5Awrite(a.id, type.id, &text) < 0) fail(object_path, "cannot write attribute " + name);
}

namespace {
template <class T>
void set_numeric_attribute(hid_t file, const std::string& object_path, const std::string& name, T value,
                           hid_t type, const std::string& path) {
  Handle obj(H5Oopen(file, object_path.c_str(), H5P_DEFAULT));
  if (obj.id < 0) throw InputError(path + ": " + object_path + ": no such object");
  Handle space(H5Screate(H5S_SCALAR));
  if (H5Aexists(obj.id, name.c_str()) > 0) H5Adelete(obj.id, name.c_str());
  Handle a(H5Acreate2(obj.id, name.c_str(), type, space.id, H5P_DEFAULT, H5P_DEFAULT));
  if (a.id < 0 || H5Awrite(a.id, type, &value) < 0)
    throw InputError(path + ": " + object_path + ": cannot write attribute " + name);
}

template <class T>
T get_numeric_attribute(hid_t file, const std::string& object_path, const std::string& name, hid_t type,
                        const std::string& path) {
  Handle obj(H5Oopen(file, object_path.c_str(), H5P_DEFAULT));
  if (obj.id < 0) throw InputError(path + ": " + object_path + ": no such object");
  Handle a(H5Aopen(obj.id, name.c_str(), H5P_DEFAULT));
  if (a.id < 0) throw InputError(path + ": " + object_path + ": missing attribute " + name);
  T v{};
  if (H5Aread(a.id, type, &v) < 0) throw InputError(path + ": " + object_path + ": attribute " + name + " has the wrong type");
  return v;
}
}  // namespace

void H5File::set_attribute(const std::string& object_path, const std::string& name, double value) {
  ensure_group(object_path);
  set_numeric_attribute(id_, object_path, name, value, H5T_NATIVE_DOUBLE, path_);
}
void H5File::set_attribute(const std::string& object_path, const std::string& name, std::int64_t value) {
  ensure_group(object_path);
  set_numeric_attribute(id_, object_path, name, value, H5T_NATIVE_INT64, path_);
}
double H5File::attribute_double(const std::string& object_path, const std::string& name) const {
  return get_numeric_attribute<double>(id_, object_path, name, H5T_NATIVE_DOUBLE, path_);
}
std::int64_t H5File::attribute_int(const std::string& object_path, const std::string& name) const {
  return get_numeric_attribute<std::int64_t>(id_, object_path, name, H5T_NATIVE_INT64, path_);
}

bool H5File::has_attribute(const std::string& object_path, const std::string& name) const {
  if (object_path != "/" && !exists(object_path)) return false;
  return H5Aexists_by_name(id_, object_path.c_str(), name.c_str(), H5P_DEFAULT) > 0;
}

std::string H5File::attribute_string(const std::string& object_path, const std::string& name) const {
  Handle obj(H5Oopen(id_, object_path.c_str(), H5P_DEFAULT));
  if (obj.id < 0) fail(object_path, "no such object");
  Handle a(H5Aopen(obj.id, name.c_str(), H5P_DEFAULT));
  if (a.id < 0) fail(object_path, "missing attribute " + name);
  Handle type(H5Aget_type(a.id));
  if (H5Tget_class(type.id) != H5T_STRING) fail(object_path, "attribute " + name + " is not a string");
  std::string s;
  if (!read_any_string(type.id, [&](hid_t memory, void* buffer) { return H5Aread(a.id, memory, buffer); }, s))
    fail(object_path, "cannot read attribute " + name);
  return s;
}

std::vector<double> H5File::read_finite_doubles(const std::string& dataset, std::vector<std::uint64_t>* dims) const {
  std::vector<double> v = read_doubles(dataset, dims);
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]))
      fail(dataset, "value " + std::to_string(i) + " is " + (std::isnan(v[i]) ? "NaN" : "infinite") + "; expected finite numbers");
  return v;
}

}  // namespace pilelab
