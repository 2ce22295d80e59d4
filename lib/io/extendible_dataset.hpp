#pragma once
// A dataset that grows along its first dimension ("rows"): unlimited, chunked,
// shuffle + deflate. Everything time-dependent in a trajectory is one of these.
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
  const std::vector<hsize_t>& inner() const { return inner_; }
  hid_t id() const { return dataset_.get(); }

 private:
  Dataset dataset_;
  hid_t mem_type_ = H5I_INVALID_HID;  // a library constant, not owned
  std::vector<hsize_t> inner_;
  hsize_t rows_ = 0;
};

}  // namespace granflow::io
