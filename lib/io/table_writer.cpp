#include "io/table_writer.hpp"

#include <stdexcept>

#include "core/error.hpp"

namespace granflow::io {

const Column& identity_column(const std::string& name) {
  static const std::vector<Column> columns = {
      {"grains", "1", "grains N", {}, {}, ColumnType::int32},
      {"packing_fraction", "1", "packing fraction ν (the run's /parameters)"},
      {"restitution", "1", "normal restitution e (the run's /parameters)"},
      {"friction", "1", "Coulomb friction μ (the run's /parameters)"},
      {"tangential_restitution", "1", "tangential restitution e_t (the run's /parameters; NaN if absent)"},
      {"rate", "1/time", "shear rate γ̇ (the run's /lees_edwards rate)"},
      {"dt", "time", "time step (the run's /parameters)"}};
  for (const Column& c : columns)
    if (c.name == name) return c;
  throw std::out_of_range("no identity column '" + name + "'");
}

std::vector<Column> table_datasets(const std::vector<Column>& columns) {
  std::vector<Column> out;
  for (const Column& c : columns) {
    out.push_back(c);
    out.back().error.clear();
    out.back().error_meaning.clear();
    if (!c.error.empty()) out.push_back({c.error, c.units, c.error_meaning});
  }
  return out;
}

TableWriter::TableWriter(AnalysisWriter& writer, std::string group, std::string rows_note)
    : writer_(writer), group_(std::move(group)) {
  if (!rows_note.empty()) extra_.set("rows", std::move(rows_note));
}

void TableWriter::write(const Column& c, const std::vector<double>& values, const std::vector<double>& errors) {
  writer_.write(path(c.name), {values.size()}, values, c.meaning, c.units, extra_);
  if (c.error.empty()) return;
  if (errors.size() != values.size())
    throw RuntimeFailure("column " + path(c.name) + ": " + std::to_string(errors.size()) + " errors for " +
                         std::to_string(values.size()) + " values");
  writer_.write(path(c.error), {errors.size()}, errors, c.error_meaning, c.units, extra_);
}

void TableWriter::write(const Column& c, const std::vector<std::int64_t>& values) {
  const std::vector<std::size_t> shape = {values.size()};
  if (c.type == ColumnType::int64) return writer_.write(path(c.name), shape, values, c.meaning, c.units, extra_);
  if (c.type == ColumnType::flag)
    return writer_.write(path(c.name), shape, std::vector<std::uint8_t>(values.begin(), values.end()), c.meaning,
                         c.units, extra_);
  writer_.write(path(c.name), shape, std::vector<std::int32_t>(values.begin(), values.end()), c.meaning, c.units,
                extra_);
}

void TableWriter::write(const Column& c, const std::vector<std::string>& values) {
  writer_.write(path(c.name), values, c.meaning);
}

}  // namespace granflow::io
