#include "io/extendible_dataset.hpp"

#include <algorithm>

namespace granflow::io {

namespace {

constexpr hsize_t kChunkBytes = 64 * 1024;
constexpr unsigned kDeflateLevel = 4;

}  // namespace

ExtendibleDataset ExtendibleDataset::create(hid_t loc, const std::string& name, hid_t file_type, hid_t mem_type,
                                            const std::vector<hsize_t>& inner) {
  hsize_t row_bytes = H5Tget_size(file_type);
  for (hsize_t d : inner) row_bytes *= d;
  std::vector<hsize_t> dims{0}, max_dims{H5S_UNLIMITED}, chunk{std::max<hsize_t>(1, kChunkBytes / row_bytes)};
  for (hsize_t d : inner) {
    dims.push_back(d);
    max_dims.push_back(d);
    chunk.push_back(d);
  }
  Dataspace space(
      check(H5Screate_simple(int(dims.size()), dims.data(), max_dims.data()), loc, "create dataspace for " + name));
  PropList dcpl = creation_plist(H5P_DATASET_CREATE);
  check(H5Pset_chunk(dcpl.get(), int(chunk.size()), chunk.data()), loc, "chunk " + name);
  check(H5Pset_shuffle(dcpl.get()), loc, "set shuffle filter for " + name);
  check(H5Pset_deflate(dcpl.get(), kDeflateLevel), loc, "set deflate filter for " + name);

  ExtendibleDataset d;
  d.dataset_ =
      Dataset(check(H5Dcreate2(loc, name.c_str(), file_type, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT), loc,
                    "create dataset " + name));
  d.mem_type_ = mem_type;
  d.inner_ = inner;
  d.row_bytes_ = std::size_t(row_bytes);
  d.chunk_bytes_ = std::size_t(row_bytes * chunk[0]);
  return d;
}

ExtendibleDataset ExtendibleDataset::open(hid_t loc, const std::string& name, hid_t mem_type) {
  ExtendibleDataset d;
  d.dataset_ = open_dataset(loc, name);
  Dataspace space(check(H5Dget_space(d.id()), d.id(), "get dataspace"));
  int rank = check(H5Sget_simple_extent_ndims(space.get()), d.id(), "get rank");
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank)), max_dims(static_cast<std::size_t>(rank));
  H5Sget_simple_extent_dims(space.get(), dims.data(), max_dims.data());
  if (rank == 0 || max_dims[0] != H5S_UNLIMITED)
    throw Hdf5Error(where(d.id()) + ": cannot append: the dataset is not extendible");
  d.mem_type_ = mem_type;
  d.inner_.assign(dims.begin() + 1, dims.end());
  d.rows_ = dims[0];
  Datatype type(check(H5Dget_type(d.id()), d.id(), "get type"));
  d.row_bytes_ = H5Tget_size(type.get());
  for (hsize_t n : d.inner_) d.row_bytes_ *= std::size_t(n);
  PropList dcpl(check(H5Dget_create_plist(d.id()), d.id(), "get creation list"));
  std::vector<hsize_t> chunk(dims.size(), 1);
  if (H5Pget_chunk(dcpl.get(), int(chunk.size()), chunk.data()) < 0) H5Eclear2(H5E_DEFAULT);
  d.chunk_bytes_ = std::max<std::size_t>(d.row_bytes_, d.row_bytes_ * std::size_t(chunk[0]));
  return d;
}

void ExtendibleDataset::append(const void* data, hsize_t rows) {
  if (rows == 0) return;
  hsize_t first = rows_;
  resize(first + rows);
  std::vector<hsize_t> start(inner_.size() + 1, 0), count{rows};
  start[0] = first;
  count.insert(count.end(), inner_.begin(), inner_.end());
  Dataspace file_space(check(H5Dget_space(id()), id(), "get dataspace"));
  check(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start.data(), nullptr, count.data(), nullptr), id(),
        "select rows");
  Dataspace mem_space(
      check(H5Screate_simple(int(count.size()), count.data(), nullptr), id(), "create memory dataspace"));
  check(H5Dwrite(id(), mem_type_, mem_space.get(), file_space.get(), H5P_DEFAULT, data), id(), "append rows");
  unflushed_ += std::size_t(rows) * row_bytes_;
}

void ExtendibleDataset::resize(hsize_t rows) {
  std::vector<hsize_t> dims{rows};
  dims.insert(dims.end(), inner_.begin(), inner_.end());
  check(H5Dset_extent(id(), dims.data()), id(), "resize to " + std::to_string(rows) + " rows");
  rows_ = rows;
  changed_ = true;
}

}  // namespace granflow::io
