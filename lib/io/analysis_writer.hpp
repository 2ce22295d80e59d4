#pragma once
// Analysis outputs (docs/file-format.md, Analysis tables): small HDF5 files of named datasets,
// each with `meaning`, `units` (the quantity in words, e.g. "force/length") and `unit` (its
// H5MD unit string, io::unit_of: "M T-2") attributes, and the provenance in /parameters.
// Paths are absolute ("/correlation/xi"); missing parent groups are created.
// Errors are RuntimeFailures naming the file and the object.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "io/trajectory.hpp"

namespace granflow::io {

class AnalysisWriter {
 public:
  explicit AnalysisWriter(const std::string& path);  // creates (truncates) the file
  ~AnalysisWriter();                                 // closes; never throws
  AnalysisWriter(const AnalysisWriter&) = delete;
  AnalysisWriter& operator=(const AnalysisWriter&) = delete;

  // One attribute per entry, on /parameters or on any group (created if missing).
  void write_parameters(const Parameters& parameters);
  void write_attributes(const std::string& group_path, const Parameters& values);

  // A new dataset of the given shape (row-major; the product of shape must equal the
  // number of values; an empty shape is a scalar) with its meaning, units and any
  // further attributes.
  void write(const std::string& path, const std::vector<std::size_t>& shape, const std::vector<double>& values,
             const std::string& meaning, const std::string& units, const Parameters& extra = {});
  void write(const std::string& path, const std::vector<std::size_t>& shape, const std::vector<std::int32_t>& values,
             const std::string& meaning, const std::string& units, const Parameters& extra = {});
  void write(const std::string& path, const std::vector<std::size_t>& shape, const std::vector<std::int64_t>& values,
             const std::string& meaning, const std::string& units, const Parameters& extra = {});
  void write(const std::string& path, const std::vector<std::size_t>& shape, const std::vector<std::uint8_t>& values,
             const std::string& meaning, const std::string& units, const Parameters& extra = {});
  // A one-dimensional dataset of fixed-length UTF-8 strings.
  void write(const std::string& path, const std::vector<std::string>& values, const std::string& meaning);

  void close();  // RuntimeFailure if HDF5 cannot finish the file

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace granflow::io
