#include "io/analysis_writer.hpp"

#include <algorithm>
#include <cstdio>
#include <exception>
#include <variant>

#include "io/hdf5_handle.hpp"
#include "io/units.hpp"

namespace granflow::io {

struct AnalysisWriter::Impl {
  std::string path;
  File file;

  hid_t id() const {
    if (!file) throw RuntimeFailure("'" + path + "': analysis writer used after close()");
    return file.get();
  }

  // Creates the missing groups above an absolute path, one level at a time.
  void parents(const std::string& object) {
    if (object.empty() || object.front() != '/' || object.back() == '/')
      throw RuntimeFailure("'" + path + "': '" + object + "' is not an absolute dataset path");
    for (std::size_t slash = object.find('/', 1); slash != std::string::npos; slash = object.find('/', slash + 1)) {
      const std::string parent = object.substr(0, slash);
      if (!exists(id(), parent)) create_group(id(), parent);
    }
  }

  Group group(const std::string& group_path) {
    if (!exists(id(), group_path)) {
      parents(group_path);
      return create_group(id(), group_path);
    }
    return open_group(id(), group_path);
  }

  template <class T>
  void dataset(const std::string& object, const std::vector<std::size_t>& shape, const std::vector<T>& values,
               const std::string& meaning, const std::string& units, const Parameters& extra) {
    std::size_t count = 1;
    for (std::size_t d : shape) count *= d;
    if (count != values.size())
      throw RuntimeFailure("'" + path + "': dataset " + object + " of shape " +
                           shape_text({shape.begin(), shape.end()}) + " given " + std::to_string(values.size()) +
                           " values");
    parents(object);
    write_dataset(id(), object, {shape.begin(), shape.end()}, values.data());
    Dataset d = open_dataset(id(), object);
    write_attribute(d.get(), "meaning", meaning);
    write_attribute(d.get(), "units", units);
    write_unit(d.get(), unit_of(units));
    attributes(d.get(), extra);
  }

  static void attributes(hid_t loc, const Parameters& values) {
    // name captured explicitly: Clang before 16 cannot capture a structured binding.
    for (const auto& [name, value] : values.items())
      std::visit([&, &name = name](const auto& v) { write_attribute(loc, name, v); }, value);
  }
};

AnalysisWriter::AnalysisWriter(const std::string& path) : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  impl_->file = create_file(path);
}

AnalysisWriter::~AnalysisWriter() {
  try {
    if (impl_->file) close();
  } catch (const std::exception& e) {
    // While an exception unwinds, that one is reported.
    if (std::uncaught_exceptions() == 0) std::fprintf(stderr, "granflow: %s\n", e.what());
  }
}

void AnalysisWriter::write_parameters(const Parameters& parameters) { write_attributes("/parameters", parameters); }

void AnalysisWriter::write_attributes(const std::string& group_path, const Parameters& values) {
  Group g = impl_->group(group_path);
  Impl::attributes(g.get(), values);
}

void AnalysisWriter::write(const std::string& path, const std::vector<std::size_t>& shape,
                           const std::vector<double>& values, const std::string& meaning, const std::string& units,
                           const Parameters& extra) {
  impl_->dataset(path, shape, values, meaning, units, extra);
}

void AnalysisWriter::write(const std::string& path, const std::vector<std::size_t>& shape,
                           const std::vector<std::int32_t>& values, const std::string& meaning,
                           const std::string& units, const Parameters& extra) {
  impl_->dataset(path, shape, values, meaning, units, extra);
}

void AnalysisWriter::write(const std::string& path, const std::vector<std::size_t>& shape,
                           const std::vector<std::int64_t>& values, const std::string& meaning,
                           const std::string& units, const Parameters& extra) {
  impl_->dataset(path, shape, values, meaning, units, extra);
}

void AnalysisWriter::write(const std::string& path, const std::vector<std::size_t>& shape,
                           const std::vector<std::uint8_t>& values, const std::string& meaning,
                           const std::string& units, const Parameters& extra) {
  impl_->dataset(path, shape, values, meaning, units, extra);
}

void AnalysisWriter::write(const std::string& path, const std::vector<std::string>& values,
                           const std::string& meaning) {
  hid_t file = impl_->id();
  impl_->parents(path);
  std::size_t width = 1;  // HDF5 has no zero-length strings
  for (const auto& v : values) width = std::max(width, v.size());
  std::string packed(width * values.size(), '\0');
  for (std::size_t i = 0; i < values.size(); ++i) packed.replace(i * width, values[i].size(), values[i]);
  Datatype type(check(H5Tcopy(H5T_C_S1), file, "copy string type"));
  check(H5Tset_size(type.get(), width), file, "set string size");
  check(H5Tset_strpad(type.get(), H5T_STR_NULLPAD), file, "set string padding");
  check(H5Tset_cset(type.get(), H5T_CSET_UTF8), file, "set string encoding");
  const hsize_t rows = values.size();
  Dataspace space(check(H5Screate_simple(1, &rows, nullptr), file, "create dataspace for " + path));
  PropList dcpl = creation_plist(H5P_DATASET_CREATE);
  Dataset dataset(check(H5Dcreate2(file, path.c_str(), type.get(), space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
                        file, "create dataset " + path));
  if (!values.empty())
    check(H5Dwrite(dataset.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, packed.data()), dataset.get(), "write");
  write_attribute(dataset.get(), "meaning", meaning);
}

void AnalysisWriter::close() { close_file(impl_->file, impl_->path); }

}  // namespace granflow::io
