#include "io/hdf5_handle.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <memory>

#include "core/output_file.hpp"
#include "core/tool.hpp"

namespace granflow::io {

void silence_hdf5_errors() {
  // The error-reporting state is per thread in thread-safe HDF5 builds.
  thread_local bool silenced = false;
  if (!silenced) {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    silenced = true;
  }
}

namespace {

std::string object_name(hid_t loc, ssize_t (*get)(hid_t, char*, size_t)) {
  ssize_t n = get(loc, nullptr, 0);
  if (n <= 0) return {};
  std::string name(std::size_t(n) + 1, '\0');
  get(loc, name.data(), name.size());
  name.resize(std::size_t(n));
  return name;
}

herr_t keep_innermost(unsigned n, const H5E_error2_t* error, void* data) {
  if (n == 0 && error->desc) *static_cast<std::string*>(data) = error->desc;
  return 0;
}

// HDF5 describes a failed system call with its time (a line of its own), descriptor,
// buffer and sizes: "file write failed: time = ..., errno = 28, error message = 'No space
// left on device', ...". Kept: what failed and the system's reason.
std::string condensed(std::string reason) {
  const std::string message = "error message = '";
  const std::size_t at = reason.find(message);
  if (at != std::string::npos) {
    const std::size_t start = at + message.size(), end = reason.find('\'', start);
    const std::string what = reason.substr(0, std::min(reason.find(':'), reason.find(", errno")));
    reason = what + ": " + reason.substr(start, end == std::string::npos ? std::string::npos : end - start);
  }
  std::replace(reason.begin(), reason.end(), '\n', ' ');
  return reason;
}

}  // namespace

std::string where(hid_t loc) {
  std::string file = object_name(loc, H5Fget_name);
  std::string object = object_name(loc, H5Iget_name);
  H5Eclear2(H5E_DEFAULT);  // a failed name lookup must not mask the real error
  std::string text = "'" + file + "'";
  if (!object.empty()) text += " " + object;
  return text;
}

std::string hdf5_reason() {
  std::string reason;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, keep_innermost, &reason);
  H5Eclear2(H5E_DEFAULT);
  return reason.empty() ? "unknown HDF5 error" : condensed(reason);
}

herr_t close_file_id(hid_t file) {
  const herr_t status = H5Fclose(file);
  if (status < 0) skip_exit_handlers();
  return status;
}

namespace {

// Cuts a file to `size` bytes; a failure only leaves zeros after HDF5's end of file.
void cut(int fd, std::size_t size) {
  if (::ftruncate(fd, off_t(size)) != 0) return;
}

}  // namespace

void flush_file(hid_t file, const std::string& path, std::size_t raw_bytes) {
  void* handle = nullptr;
  const bool have_fd = H5Fget_vfd_handle(file, H5P_DEFAULT, &handle) >= 0 && handle != nullptr;
  H5Eclear2(H5E_DEFAULT);
  if (have_fd) {
    const int fd = *static_cast<int*>(handle);
    size_t max_size = 0, min_clean = 0, cached = 0;
    int entries = 0;
    if (H5Fget_mdc_size(file, &max_size, &min_clean, &cached, &entries) < 0) H5Eclear2(H5E_DEFAULT);
    haddr_t eoa = 0;
    if (H5Fget_eoa(file, &eoa) < 0) H5Eclear2(H5E_DEFAULT);
    struct stat st {};
    if (::fstat(fd, &st) == 0) {
      const std::size_t size = std::size_t(st.st_size);
      const std::size_t reserve = raw_bytes + raw_bytes / 64 + cached + (std::size_t(64) << 10);
      const std::size_t end = std::max<std::size_t>(size, std::size_t(eoa)) + reserve;
      static const std::vector<char> zeros(std::size_t(1) << 20, 0);
      int error = 0;
      for (std::size_t at = size; error == 0 && at < end;) {
        const ssize_t n = ::pwrite(fd, zeros.data(), std::min(zeros.size(), end - at), off_t(at));
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) error = errno;
        else at += std::size_t(n);
      }
      if (error != 0) {
        // What HDF5 wrote before stays; only the zeros go.
        cut(fd, size);
        throw Hdf5Error("'" + path + "': flush: cannot reserve " + std::to_string(reserve) +
                        " bytes: " + std::strerror(error));
      }
    }
  }
  check(H5Fflush(file, H5F_SCOPE_LOCAL), file, "flush");
  hsize_t written = 0;
  if (have_fd && H5Fget_filesize(file, &written) >= 0) cut(*static_cast<int*>(handle), std::size_t(written));
  H5Eclear2(H5E_DEFAULT);
}

void close_file(File& file, const std::string& path) {
  if (file && close_file_id(file.release()) < 0) throw Hdf5Error("'" + path + "': close: " + hdf5_reason());
}

void abandon_file(File& file) {
  if (file) skip_exit_handlers();
  file.release();
}

void fail(hid_t loc, std::string_view action) {
  std::string reason = hdf5_reason();  // before where(), which clears the stack
  throw Hdf5Error(where(loc) + ": " + std::string(action) + ": " + reason);
}

namespace {

// For calls that have no HDF5 object to name yet (file creation, property lists).
hid_t check_path(hid_t status, const std::string& path, std::string_view action) {
  if (status < 0) throw Hdf5Error("'" + path + "': " + std::string(action) + ": " + hdf5_reason());
  return status;
}

}  // namespace

PropList file_access_plist() {
  silence_hdf5_errors();
  PropList fapl(check_path(H5Pcreate(H5P_FILE_ACCESS), "", "create file access list"));
  // Objects in the 1.8 format; the file-space strategy below needs the 1.10 superblock.
  check_path(H5Pset_libver_bounds(fapl.get(), H5F_LIBVER_V18, H5F_LIBVER_V110), "", "set HDF5 format version");
#if H5_VERSION_GE(1, 10, 7)
  check_path(H5Pset_file_locking(fapl.get(), true, true), "", "set file locking");
#endif
  return fapl;
}

PropList creation_plist(hid_t plist_class) {
  silence_hdf5_errors();
  PropList plist(check_path(H5Pcreate(plist_class), "", "create property list"));
  check_path(H5Pset_obj_track_times(plist.get(), false), "", "disable object timestamps");
  return plist;
}

namespace {

// For files being written: HDF5 writes metadata (object headers, chunk indexes, the
// superblock) only when flushed or closed, never in between on its own to make room in
// its cache, so a process killed (kill -9) between two flushes leaves the metadata of
// the last flush, consistent with itself, and (see create_file) the data it indexes.
// The cache holds the metadata touched since the file was opened: small against the
// data (one chunk index entry per 64 KiB chunk).
PropList writer_access_plist(const std::string& path) {
  PropList fapl = file_access_plist();
  H5AC_cache_config_t config;
  config.version = H5AC__CURR_CACHE_CONFIG_VERSION;
  check_path(H5Pget_mdc_config(fapl.get(), &config), path, "get metadata cache configuration");
  config.evictions_enabled = false;
  config.incr_mode = H5C_incr__off;
  config.flash_incr_mode = H5C_flash_incr__off;
  config.decr_mode = H5C_decr__off;
  check_path(H5Pset_mdc_config(fapl.get(), &config), path, "set metadata cache configuration");
  return fapl;
}

}  // namespace

File create_file(const std::string& path) {
  PropList fcpl = creation_plist(H5P_FILE_CREATE);
  // File space is only ever taken at the end of the file, never reused: a chunk that
  // grows is written elsewhere and its old copy stays intact, so the chunk index a
  // checkpoint flushed keeps pointing at valid data until the next flush, whenever a
  // process is killed (kill -9) in between.
  check_path(H5Pset_file_space_strategy(fcpl.get(), H5F_FSPACE_STRATEGY_NONE, false, 1), path,
             "set file space strategy");
  // That strategy is stored in a superblock extension, an object header HDF5 creates with
  // its default group creation list, timestamps included: without them, identical inputs
  // still give byte-identical files. (granflow creates every object of its own with
  // creation_plist, so changing that process-wide default affects nothing else.)
  check_path(H5Pset_obj_track_times(H5P_GROUP_CREATE_DEFAULT, false), path, "disable object timestamps");
  PropList fapl = writer_access_plist(path);
  return File(
      check_path(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, fcpl.get(), fapl.get()), path, "cannot create HDF5 file"));
}

File open_file(const std::string& path, bool writable) {
  require_regular_file(path);
  PropList fapl = writable ? writer_access_plist(path) : file_access_plist();
  const hid_t file = H5Fopen(path.c_str(), writable ? H5F_ACC_RDWR : H5F_ACC_RDONLY, fapl.get());
  if (file < 0) {
    const std::string reason = hdf5_reason();
    // HDF5 locks a file it writes (flock): the writer is alive.
    if (reason.find("unable to lock file") != std::string::npos) throw UsageError(unfinished_run_message(path));
    throw Hdf5Error("'" + path + "': cannot open as HDF5 (truncated or corrupt?): " + reason);
  }
  return File(file);
}

bool exists(hid_t loc, const std::string& path) {
  // H5Lexists fails, rather than answering false, when an intermediate group is missing.
  std::string prefix = path.starts_with('/') ? "/" : "";
  std::size_t start = prefix.size();
  while (start < path.size()) {
    std::size_t end = std::min(path.find('/', start), path.size());
    prefix += path.substr(start, end - start);
    if (check(H5Lexists(loc, prefix.c_str(), H5P_DEFAULT), loc, "look up " + prefix) <= 0) return false;
    prefix += '/';
    start = end + 1;
  }
  return true;
}

Group create_group(hid_t loc, const std::string& name) {
  PropList gcpl = creation_plist(H5P_GROUP_CREATE);
  return Group(check(H5Gcreate2(loc, name.c_str(), H5P_DEFAULT, gcpl.get(), H5P_DEFAULT), loc, "create group " + name));
}

Group open_group(hid_t loc, const std::string& name) {
  return Group(check(H5Gopen2(loc, name.c_str(), H5P_DEFAULT), loc, "open group " + name));
}

Dataset open_dataset(hid_t loc, const std::string& name) {
  return Dataset(check(H5Dopen2(loc, name.c_str(), H5P_DEFAULT), loc, "open dataset " + name));
}

std::vector<std::string> link_names(hid_t group) {
  H5G_info_t info;
  check(H5Gget_info(group, &info), group, "list group");
  std::vector<std::string> names;
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    ssize_t n = check(H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT), group,
                      "list group");
    std::string name(std::size_t(n) + 1, '\0');
    H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), name.size(), H5P_DEFAULT);
    name.resize(std::size_t(n));
    names.push_back(std::move(name));
  }
  return names;
}

std::vector<hsize_t> shape(hid_t object) {
  bool is_attribute = H5Iget_type(object) == H5I_ATTR;
  Dataspace space(check(is_attribute ? H5Aget_space(object) : H5Dget_space(object), object, "get dataspace"));
  int rank = check(H5Sget_simple_extent_ndims(space.get()), object, "get rank");
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
  H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr);
  return dims;
}

std::string shape_text(const std::vector<hsize_t>& dims) {
  if (dims.empty()) return "scalar";
  std::string text;
  for (hsize_t d : dims) text += "[" + std::to_string(d) + "]";
  return text;
}

template <class T>
void write_dataset(hid_t loc, const std::string& name, const std::vector<hsize_t>& dims, const T* data) {
  Dataspace space(check(H5Screate_simple(int(dims.size()), dims.data(), nullptr), loc, "create dataspace for " + name));
  PropList dcpl = creation_plist(H5P_DATASET_CREATE);
  Dataset dataset(
      check(H5Dcreate2(loc, name.c_str(), file_type<T>(), space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT), loc,
            "create dataset " + name));
  check(H5Dwrite(dataset.get(), native_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, data), dataset.get(), "write");
}
template void write_dataset<double>(hid_t, const std::string&, const std::vector<hsize_t>&, const double*);
template void write_dataset<std::uint8_t>(hid_t, const std::string&, const std::vector<hsize_t>&, const std::uint8_t*);
template void write_dataset<std::int32_t>(hid_t, const std::string&, const std::vector<hsize_t>&, const std::int32_t*);
template void write_dataset<std::int64_t>(hid_t, const std::string&, const std::vector<hsize_t>&, const std::int64_t*);

void read_rows(hid_t dataset, hsize_t first, hsize_t count, hid_t mem_type, void* out) {
  std::vector<hsize_t> dims = shape(dataset);
  if (dims.empty() || first + count > dims[0])
    throw Hdf5Error(where(dataset) + ": rows " + std::to_string(first) + "+" + std::to_string(count) + " outside " +
                    shape_text(dims));
  if (count == 0) return;
  Dataspace file_space(check(H5Dget_space(dataset), dataset, "get dataspace"));
  std::vector<hsize_t> start(dims.size(), 0), extent = dims;
  start[0] = first;
  extent[0] = count;
  check(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start.data(), nullptr, extent.data(), nullptr), dataset,
        "select rows");
  Dataspace mem_space(
      check(H5Screate_simple(int(extent.size()), extent.data(), nullptr), dataset, "create memory dataspace"));
  check(H5Dread(dataset, mem_type, mem_space.get(), file_space.get(), H5P_DEFAULT, out), dataset, "read");
}

namespace {

// An H5Ovisit callback: an exception must not unwind through the C library, so the
// first failure is kept in *error and stops the walk.
herr_t read_dataset_in_blocks(hid_t loc, const char* name, const H5O_info_t* info, void* error) try {
  if (info->type != H5O_TYPE_DATASET) return 0;
  Dataset dataset = open_dataset(loc, name);
  Datatype type(check(H5Dget_type(dataset.get()), dataset.get(), "get type"));
  // Variable-length data (strings h5py writes) is not chunked trajectory data.
  if (H5Tis_variable_str(type.get()) > 0 || H5Tdetect_class(type.get(), H5T_VLEN) > 0) return 0;
  const std::vector<hsize_t> dims = shape(dataset.get());
  if (dims.empty()) return 0;
  hsize_t row_elements = 1;
  for (std::size_t i = 1; i < dims.size(); ++i) row_elements *= dims[i];
  const std::size_t row_bytes = std::max<std::size_t>(1, std::size_t(row_elements) * H5Tget_size(type.get()));
  const hsize_t block = std::max<hsize_t>(1, hsize_t((std::size_t(16) << 20) / row_bytes));
  std::vector<unsigned char> buffer;
  for (hsize_t first = 0; first < dims[0]; first += block) {
    const hsize_t count = std::min(block, dims[0] - first);
    buffer.resize(std::size_t(count) * row_bytes);
    read_rows(dataset.get(), first, count, type.get(), buffer.data());
  }
  return 0;
} catch (const std::exception& e) {
  *static_cast<std::string*>(error) = e.what();
  return -1;
}

}  // namespace

void read_every_dataset(hid_t file) {
  std::string error;
  if (H5Ovisit2(file, H5_INDEX_NAME, H5_ITER_NATIVE, read_dataset_in_blocks, &error, H5O_INFO_BASIC) < 0)
    throw Hdf5Error(error.empty() ? where(file) + ": read every dataset: " + hdf5_reason() : error);
}

namespace {

hsize_t elements_per_row(const std::vector<hsize_t>& dims) {
  hsize_t n = 1;
  for (std::size_t i = 1; i < dims.size(); ++i) n *= dims[i];
  return n;
}

}  // namespace

template <class T>
std::vector<T> read_rows(hid_t dataset, hsize_t first, hsize_t count) {
  std::vector<T> values(count * elements_per_row(shape(dataset)));
  read_rows(dataset, first, count, native_type<T>(), values.data());
  return values;
}
template std::vector<double> read_rows<double>(hid_t, hsize_t, hsize_t);
template std::vector<std::int64_t> read_rows<std::int64_t>(hid_t, hsize_t, hsize_t);
template std::vector<std::int32_t> read_rows<std::int32_t>(hid_t, hsize_t, hsize_t);
template std::vector<std::uint8_t> read_rows<std::uint8_t>(hid_t, hsize_t, hsize_t);

template <class T>
std::vector<T> read_all(hid_t dataset) {
  std::vector<hsize_t> dims = shape(dataset);
  if (dims.empty()) throw Hdf5Error(where(dataset) + ": expected an array, found a scalar");
  return read_rows<T>(dataset, 0, dims[0]);
}
template std::vector<double> read_all<double>(hid_t);
template std::vector<std::int64_t> read_all<std::int64_t>(hid_t);
template std::vector<std::int32_t> read_all<std::int32_t>(hid_t);
template std::vector<std::uint8_t> read_all<std::uint8_t>(hid_t);

// ---- attributes ----

namespace {

Datatype string_type(hid_t loc, std::size_t length) {
  Datatype type(check(H5Tcopy(H5T_C_S1), loc, "copy string type"));
  // HDF5 has no zero-size strings: an empty string is one NUL byte.
  H5Tset_size(type.get(), std::max<std::size_t>(length, 1));
  H5Tset_strpad(type.get(), H5T_STR_NULLPAD);
  H5Tset_cset(type.get(), H5T_CSET_UTF8);
  return type;
}

void write_attribute_raw(hid_t loc, const std::string& name, hid_t file_type, hid_t mem_type,
                         const std::vector<hsize_t>& dims, const void* data) {
  delete_attribute_if_exists(loc, name);
  Dataspace space(check(dims.empty() ? H5Screate(H5S_SCALAR) : H5Screate_simple(int(dims.size()), dims.data(), nullptr),
                        loc, "create dataspace for attribute " + name));
  Attribute attribute(check(H5Acreate2(loc, name.c_str(), file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT), loc,
                            "create attribute " + name));
  check(H5Awrite(attribute.get(), mem_type, data), loc, "write attribute " + name);
}

hsize_t element_count(hid_t attribute) {
  hsize_t n = 1;
  for (hsize_t d : shape(attribute)) n *= d;
  return n;
}

template <class T>
T read_scalar(hid_t attribute) {
  if (element_count(attribute) != 1)
    throw Hdf5Error(where(attribute) + ": attribute holds " + std::to_string(element_count(attribute)) +
                    " values, expected one");
  T value;
  check(H5Aread(attribute, native_type<T>(), &value), attribute, "read attribute");
  return value;
}

}  // namespace

void delete_attribute_if_exists(hid_t loc, const std::string& name) {
  if (has_attribute(loc, name)) check(H5Adelete(loc, name.c_str()), loc, "delete attribute " + name);
}

void write_attribute(hid_t loc, const std::string& name, double value) {
  write_attribute_raw(loc, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {}, &value);
}

void write_attribute(hid_t loc, const std::string& name, std::int64_t value) {
  write_attribute_raw(loc, name, H5T_STD_I64LE, H5T_NATIVE_INT64, {}, &value);
}

void write_attribute(hid_t loc, const std::string& name, std::int32_t value) {
  write_attribute_raw(loc, name, H5T_STD_I32LE, H5T_NATIVE_INT32, {}, &value);
}

void write_attribute(hid_t loc, const std::string& name, const std::string& value) {
  Datatype type = string_type(loc, value.size());
  std::string padded = value;
  padded.resize(std::max<std::size_t>(value.size(), 1), '\0');
  write_attribute_raw(loc, name, type.get(), type.get(), {}, padded.data());
}

void write_attribute(hid_t loc, const std::string& name, const std::vector<std::int32_t>& values) {
  write_attribute_raw(loc, name, H5T_STD_I32LE, H5T_NATIVE_INT32, {values.size()}, values.data());
}

void write_attribute(hid_t loc, const std::string& name, const std::vector<std::string>& values) {
  std::size_t width = 1;
  for (const auto& v : values) width = std::max(width, v.size());
  std::string packed(width * values.size(), '\0');
  for (std::size_t i = 0; i < values.size(); ++i) packed.replace(i * width, values[i].size(), values[i]);
  Datatype type = string_type(loc, width);
  write_attribute_raw(loc, name, type.get(), type.get(), {values.size()}, packed.data());
}

bool has_attribute(hid_t loc, const std::string& name) {
  return check(H5Aexists(loc, name.c_str()), loc, "look up attribute " + name) > 0;
}

Attribute open_attribute(hid_t loc, const std::string& name) {
  return Attribute(check(H5Aopen(loc, name.c_str(), H5P_DEFAULT), loc, "open attribute " + name));
}

H5T_class_t attribute_class(hid_t attribute) {
  Datatype type(check(H5Aget_type(attribute), attribute, "get attribute type"));
  return H5Tget_class(type.get());
}

double read_double_attribute(hid_t attribute) { return read_scalar<double>(attribute); }

std::int64_t read_int_attribute(hid_t attribute) { return read_scalar<std::int64_t>(attribute); }

std::vector<std::int64_t> read_int_array_attribute(hid_t attribute) {
  std::vector<std::int64_t> values(element_count(attribute));
  check(H5Aread(attribute, H5T_NATIVE_INT64, values.data()), attribute, "read attribute");
  return values;
}

std::vector<std::string> read_string_attributes(hid_t attribute) {
  Datatype type(check(H5Aget_type(attribute), attribute, "get attribute type"));
  if (H5Tget_class(type.get()) != H5T_STRING) throw Hdf5Error(where(attribute) + ": attribute is not a string");
  std::size_t count = element_count(attribute);
  std::vector<std::string> values;
  if (check(H5Tis_variable_str(type.get()), attribute, "inspect string type") > 0) {
    Datatype mem(check(H5Tcopy(H5T_C_S1), attribute, "copy string type"));
    H5Tset_size(mem.get(), H5T_VARIABLE);
    H5Tset_cset(mem.get(), H5Tget_cset(type.get()));
    std::vector<char*> pointers(count, nullptr);
    check(H5Aread(attribute, mem.get(), pointers.data()), attribute, "read attribute");
    for (char* p : pointers) {
      values.emplace_back(p ? p : "");
      H5free_memory(p);
    }
  } else {
    std::size_t width = H5Tget_size(type.get());
    std::string packed(width * count, '\0');
    check(H5Aread(attribute, type.get(), packed.data()), attribute, "read attribute");
    for (std::size_t i = 0; i < count; ++i) {
      std::string v = packed.substr(i * width, width);
      v.resize(std::min(v.find('\0'), v.size()));  // NULLPAD or NULLTERM
      values.push_back(std::move(v));
    }
  }
  return values;
}

std::string read_string_attribute(hid_t attribute) {
  std::vector<std::string> values = read_string_attributes(attribute);
  if (values.size() != 1)
    throw Hdf5Error(where(attribute) + ": attribute holds " + std::to_string(values.size()) + " strings, expected one");
  return values.front();
}

namespace {

herr_t collect_name(hid_t, const char* name, const H5A_info_t*, void* data) {
  static_cast<std::vector<std::string>*>(data)->emplace_back(name);
  return 0;
}

}  // namespace

std::vector<std::string> attribute_names(hid_t loc) {
  std::vector<std::string> names;
  hsize_t index = 0;
  check(H5Aiterate2(loc, H5_INDEX_NAME, H5_ITER_INC, &index, collect_name, &names), loc, "list attributes");
  return names;
}

}  // namespace granflow::io
