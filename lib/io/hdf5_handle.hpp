#pragma once
// Thin RAII layer over the HDF5 C API: every hid_t is owned by a handle that closes
// it, so nothing leaks when an exception unwinds; every failing call throws
// Hdf5Error naming the file, the object and HDF5's own reason. HDF5's automatic
// error printing is switched off: granflow reports errors itself, in one line.
#include <hdf5.h>

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/error.hpp"

namespace granflow::io {

// A failed HDF5 call. Writers let it through as a write failure (exit 1); the reader
// turns it into a UsageError, since it then means a bad input file.
struct Hdf5Error : WriteFailure {
  using WriteFailure::WriteFailure;
};

// H5Fclose that, when it fails, makes run_tool end the process without HDF5's exit
// handler (core/tool.hpp): a failed close leaves the file half closed, and that handler
// would close it again and crash.
herr_t close_file_id(hid_t file);

template <herr_t (*Close)(hid_t)>
class Handle {
 public:
  Handle() = default;
  explicit Handle(hid_t id) : id_(id) {}
  Handle(Handle&& other) noexcept : id_(std::exchange(other.id_, H5I_INVALID_HID)) {}
  Handle& operator=(Handle&& other) noexcept {
    if (this != &other) {
      reset();
      id_ = std::exchange(other.id_, H5I_INVALID_HID);
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { reset(); }

  hid_t get() const { return id_; }
  explicit operator bool() const { return id_ >= 0; }
  // Gives up ownership, e.g. to close a file and check the result.
  hid_t release() { return std::exchange(id_, H5I_INVALID_HID); }
  void reset() noexcept {
    if (id_ >= 0) Close(id_);
    id_ = H5I_INVALID_HID;
  }

 private:
  hid_t id_ = H5I_INVALID_HID;
};

using File = Handle<close_file_id>;
using Group = Handle<H5Gclose>;
using Dataset = Handle<H5Dclose>;
using Dataspace = Handle<H5Sclose>;
using Datatype = Handle<H5Tclose>;
using PropList = Handle<H5Pclose>;
using Attribute = Handle<H5Aclose>;

// Turns off HDF5's printing of error stacks on this thread (idempotent, cheap).
void silence_hdf5_errors();

// "'<file>' <object path>" for any open HDF5 identifier, for error messages.
std::string where(hid_t loc);
// HDF5's innermost error description from the current error stack, which it clears.
std::string hdf5_reason();
// Throws Hdf5Error "<where(loc)>: <action>: <reason>".
[[noreturn]] void fail(hid_t loc, std::string_view action);
// Returns the status of an HDF5 call, or fails when it is negative.
template <class T>
T check(T status, hid_t loc, std::string_view action) {
  if (status < 0) fail(loc, action);
  return status;
}

// Memory types for the element types granflow stores.
template <class T>
hid_t native_type();
template <>
inline hid_t native_type<double>() {
  return H5T_NATIVE_DOUBLE;
}
template <>
inline hid_t native_type<std::int64_t>() {
  return H5T_NATIVE_INT64;
}
template <>
inline hid_t native_type<std::int32_t>() {
  return H5T_NATIVE_INT32;
}
template <>
inline hid_t native_type<std::uint8_t>() {
  return H5T_NATIVE_UINT8;
}
// Little-endian file types, so files are the same on every machine.
template <class T>
hid_t file_type();
template <>
inline hid_t file_type<double>() {
  return H5T_IEEE_F64LE;
}
template <>
inline hid_t file_type<std::int64_t>() {
  return H5T_STD_I64LE;
}
template <>
inline hid_t file_type<std::int32_t>() {
  return H5T_STD_I32LE;
}
template <>
inline hid_t file_type<std::uint8_t>() {
  return H5T_STD_U8LE;
}

// File access: HDF5 1.8 object format (dense attribute storage, so a long command line
// fits in an attribute), a 1.10 superblock where create_file needs it, and file locking
// that degrades gracefully on cluster file systems without it.
PropList file_access_plist();
// File, group and dataset creation without object timestamps: identical inputs give
// byte-identical files.
PropList creation_plist(hid_t plist_class);

// Truncates. File space is never reused and, for files opened writable, metadata reaches
// the disk only when flushed or closed: a process killed between two flushes leaves the
// file as of the last flush, plus data nothing indexes yet.
File create_file(const std::string& path);
// Opens an existing file; the caller has checked that it exists and is HDF5. A file that
// another process holds locked (it is writing it) is refused as an unfinished run.
File open_file(const std::string& path, bool writable);
// Flushes a file being written so that a full file system cannot leave it half written:
// first the file is extended by the most the flush can add (`raw_bytes`, the data its
// chunk caches may hold, plus its cached metadata) with zeros, and on failure
// (WriteFailure naming the file and the reason) the flush is not attempted, the file
// stays as its last flush left it. Then HDF5 writes into space that is already there, and
// the file is cut back to what HDF5 wrote.
void flush_file(hid_t file, const std::string& path, std::size_t raw_bytes);
// Closes the file; Hdf5Error naming path and the reason if HDF5 cannot finish it.
void close_file(File& file, const std::string& path);
// Gives the file up without writing to it again (no flush, no close): after a write
// failure, a resumable run's partial output stays as its last flush left it, as after a
// kill -9. The process must then end through run_tool (skip_exit_handlers).
void abandon_file(File& file);

// Whether every component of a relative or absolute path exists under loc.
bool exists(hid_t loc, const std::string& path);
Group create_group(hid_t loc, const std::string& name);
Group open_group(hid_t loc, const std::string& name);
Dataset open_dataset(hid_t loc, const std::string& name);
// Names of the links directly in a group, in name order.
std::vector<std::string> link_names(hid_t group);

// Current extent of a dataset or attribute's dataspace.
std::vector<hsize_t> shape(hid_t dataset);
// "[3][100][2]" for messages.
std::string shape_text(const std::vector<hsize_t>& dims);

// A fixed-size, contiguous dataset written in one go (per-grain properties).
template <class T>
void write_dataset(hid_t loc, const std::string& name, const std::vector<hsize_t>& dims, const T* data);
// Rows [first, first+count) along the first dimension, all of the others.
void read_rows(hid_t dataset, hsize_t first, hsize_t count, hid_t mem_type, void* out);
template <class T>
std::vector<T> read_rows(hid_t dataset, hsize_t first, hsize_t count);
template <class T>
std::vector<T> read_all(hid_t dataset);
// Reads every row of every fixed-size dataset in the file, in blocks, and throws Hdf5Error
// naming the first one that cannot be read (a chunk overwritten or cut short). A file that
// opens can still hold such a chunk: a power loss or a disk error can leave one.
void read_every_dataset(hid_t file);

// Attributes. Strings are stored as fixed-length UTF-8 (H5MD 1.1); reading also accepts
// variable-length strings, as h5py writes them.
void delete_attribute_if_exists(hid_t loc, const std::string& name);
void write_attribute(hid_t loc, const std::string& name, double value);
void write_attribute(hid_t loc, const std::string& name, std::int64_t value);
void write_attribute(hid_t loc, const std::string& name, std::int32_t value);
void write_attribute(hid_t loc, const std::string& name, const std::string& value);
void write_attribute(hid_t loc, const std::string& name, const std::vector<std::int32_t>& values);
void write_attribute(hid_t loc, const std::string& name, const std::vector<std::string>& values);
bool has_attribute(hid_t loc, const std::string& name);
Attribute open_attribute(hid_t loc, const std::string& name);
// The attribute's type class (H5T_FLOAT, H5T_INTEGER, H5T_STRING, ...).
H5T_class_t attribute_class(hid_t attribute);
double read_double_attribute(hid_t attribute);
std::int64_t read_int_attribute(hid_t attribute);
std::vector<std::int64_t> read_int_array_attribute(hid_t attribute);
std::vector<std::string> read_string_attributes(hid_t attribute);  // any rank, flattened
std::string read_string_attribute(hid_t attribute);                // must hold one string
// Names of a group's attributes, in name order.
std::vector<std::string> attribute_names(hid_t loc);

}  // namespace granflow::io
