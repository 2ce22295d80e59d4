#include "io/trajectory.hpp"

#include "core/error.hpp"

namespace granflow::io {

const Parameters::Value& Parameters::find(const std::string& name) const {
  auto it = values_.find(name);
  if (it == values_.end()) {
    if (origin_.empty()) throw UsageError("parameter '" + name + "' is not set");
    throw UsageError("'" + origin_ + "': /parameters has no '" + name + "'");
  }
  return it->second;
}

void Parameters::wrong_type(const std::string& name, const char* expected) const {
  std::string where = origin_.empty() ? "" : "'" + origin_ + "': ";
  throw UsageError(where + "parameter '" + name + "' is not " + expected);
}

double Parameters::get_double(const std::string& name) const {
  const Value& v = find(name);
  if (const auto* d = std::get_if<double>(&v)) return *d;
  if (const auto* i = std::get_if<std::int64_t>(&v)) return double(*i);
  wrong_type(name, "a number");
}

std::int64_t Parameters::get_int(const std::string& name) const {
  const Value& v = find(name);
  if (const auto* i = std::get_if<std::int64_t>(&v)) return *i;
  wrong_type(name, "an integer");
}

const std::string& Parameters::get_string(const std::string& name) const {
  const Value& v = find(name);
  if (const auto* s = std::get_if<std::string>(&v)) return *s;
  wrong_type(name, "a string");
}

void write_packing(const std::string& path, const Frame& frame, const GrainProperties& grains,
                   const Parameters& parameters) {
  TrajectoryWriter writer(path);
  writer.write_parameters(parameters);
  writer.write_grains(grains, frame.box);
  writer.append_frame(frame);
  writer.close();
}

}  // namespace granflow::io
