#pragma once
// A dataset that grows along its first dimension ("rows"): unlimited, chunked,
// shuffle + deflate. Everything time-dependent in a trajectory is one of these.
#include <algorithm>
#include <string>
#include <vector>

#include "io/hdf5_handle.hpp"

namespace granflow::io {

class ExtendibleDataset {
 public:
  ExtendibleDataset() = default;

  // Creates loc/name with shape [0]+inner. A chunk holds whole rows, about 64 KiB:
  // one frame of a large system, many frames of a small one.
  template <class T>
  static ExtendibleDataset create(hid_t loc, const std::string& name, const std::vector<hsize_t>& inner) {
    return create(loc, name, file_type<T>(), native_type<T>(), inner);
  }
  static ExtendibleDataset create(hid_t loc, const std::string& name, hid_t file_type, hid_t mem_type,
                                  const std::vector<hsize_t>& inner);
  // Opens one made by create(), e.g. to resume appending; Hdf5Error if it cannot grow.
  template <class T>
  static ExtendibleDataset open(hid_t loc, const std::string& name) {
    return open(loc, name, native_type<T>());
  }
  static ExtendibleDataset open(hid_t loc, const std::string& name, hid_t mem_type);

  // Appends rows laid out in memory as [rows]+inner, C order.
  void append(const void* data, hsize_t rows);
  // Cuts the dataset to its first rows (or grows it with fill values).
  void resize(hsize_t rows);
  hsize_t rows() const { return rows_; }
  // At most the bytes a flush of the file writes for this dataset's rows changed since
  // the last flushed(): those rows still in HDF5's chunk cache (1 MiB per dataset, or one
  // chunk), and its last chunk rewritten whole (the rows in it and its compressed fill).
  std::size_t unflushed_bytes() const {
    if (!changed_) return 0;
    constexpr std::size_t kChunkCache = std::size_t(1) << 20;
    const std::size_t chunk_rows = row_bytes_ > 0 ? chunk_bytes_ / row_bytes_ : 1;
    return std::min(unflushed_, std::max(kChunkCache, chunk_bytes_)) +
           std::min<std::size_t>(std::size_t(rows_), chunk_rows) * row_bytes_ + chunk_bytes_ / 64 + 1024;
  }
  void flushed() {
    unflushed_ = 0;
    changed_ = false;
  }
  const std::vector<hsize_t>& inner() const { return inner_; }
  hid_t id() const { return dataset_.get(); }

 private:
  Dataset dataset_;
  hid_t mem_type_ = H5I_INVALID_HID;  // a library constant, not owned
  std::vector<hsize_t> inner_;
  hsize_t rows_ = 0;
  std::size_t row_bytes_ = 0, chunk_bytes_ = 0, unflushed_ = 0;
  bool changed_ = false;
};

}  // namespace granflow::io
