#pragma once
// The per-run analysis tables (gf-correlate, gf-kinetic, gf-network, gf-stz fit; docs/
// file-format.md): one group of one-dimensional datasets, one row per run, each column
// declared once — name, units in words (io::unit_of), meaning, and the name and meaning of
// its error column — and written through AnalysisWriter from that declaration. The same
// declarations describe the tables to the docs' check (tests/unit/test_table_columns.cpp
// compares docs/file-format.md's column lists with table_datasets()).
#include <cstdint>
#include <functional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "io/analysis_writer.hpp"

namespace granflow::io {

// real: double; int32, int64; flag: uint8 0/1; text: fixed-length UTF-8 strings.
enum class ColumnType { real, int32, int64, flag, text };

struct Column {
  std::string name;
  std::string units;  // in words; empty for text
  std::string meaning;
  std::string error{};  // name of the error column (same units), empty: none
  std::string error_meaning{};
  ColumnType type = ColumnType::real;
};

// A column with how to read it from a row of the program's table.
template <class Row>
struct RowColumn {
  Column column;
  std::function<double(const Row&)> value{}, error{};
  std::function<std::int64_t(const Row&)> integer{};  // int32, int64 and flag columns
  std::function<std::string(const Row&)> text{};
};

// A real column; with error_meaning and error: its error column <name>_error.
template <class Row>
RowColumn<Row> real(std::string name, std::string units, std::string meaning, double Row::*value) {
  return {{std::move(name), std::move(units), std::move(meaning)}, [value](const Row& r) { return r.*value; }};
}
template <class Row>
RowColumn<Row> real(std::string name, std::string units, std::string meaning, double Row::*value,
                    std::string error_meaning, double Row::*error) {
  std::string error_name = name + "_error";
  return {{std::move(name), std::move(units), std::move(meaning), std::move(error_name), std::move(error_meaning)},
          [value](const Row& r) { return r.*value; },
          [error](const Row& r) { return r.*error; }};
}
// An integer column of the member's width (int32 or int64).
template <class Row, class Int>
requires std::is_same_v<Int, std::int32_t> || std::is_same_v<Int, std::int64_t> RowColumn<Row> integer(
    std::string name, std::string units, std::string meaning, Int Row::*value) {
  const ColumnType type = std::is_same_v<Int, std::int32_t> ? ColumnType::int32 : ColumnType::int64;
  return {{std::move(name), std::move(units), std::move(meaning), {}, {}, type}, {}, {}, [value](const Row& r) {
            return std::int64_t(r.*value);
          }};
}
// A flag (uint8 0/1, units "1").
template <class Row>
RowColumn<Row> flag(std::string name, std::string meaning, bool Row::*value) {
  return {{std::move(name), "1", std::move(meaning), {}, {}, ColumnType::flag}, {}, {}, [value](const Row& r) {
            return std::int64_t(r.*value ? 1 : 0);
          }};
}
template <class Row>
RowColumn<Row> text(std::string name, std::string meaning, std::string Row::*value) {
  return {{std::move(name), {}, std::move(meaning), {}, {}, ColumnType::text}, {}, {}, {}, [value](const Row& r) {
            return r.*value;
          }};
}

// A column declared elsewhere (e.g. identity_column), read from a row's member.
template <class Row>
RowColumn<Row> real(Column column, double Row::*value) {
  return {std::move(column), [value](const Row& r) { return r.*value; }};
}
template <class Row>
RowColumn<Row> integer(Column column, std::int32_t Row::*value) {
  column.type = ColumnType::int32;
  return {std::move(column), {}, {}, [value](const Row& r) { return std::int64_t(r.*value); }};
}

// Columns read by a function of the row.
template <class Row>
RowColumn<Row> real(Column column, std::function<double(const Row&)> value) {
  return {std::move(column), std::move(value)};
}
// With column.error set: its error column read by error.
template <class Row>
RowColumn<Row> real(Column column, std::function<double(const Row&)> value, std::function<double(const Row&)> error) {
  return {std::move(column), std::move(value), std::move(error)};
}
// An int32 column (column.type int32 unless int64 or flag).
template <class Row>
RowColumn<Row> integer(Column column, std::function<std::int64_t(const Row&)> value) {
  if (column.type != ColumnType::int64 && column.type != ColumnType::flag) column.type = ColumnType::int32;
  return {std::move(column), {}, {}, std::move(value)};
}
template <class Row>
RowColumn<Row> text(std::string name, std::string meaning, std::function<std::string(const Row&)> value) {
  return {{std::move(name), {}, std::move(meaning), {}, {}, ColumnType::text}, {}, {}, {}, std::move(value)};
}

// The columns of a run's identity (io/run_identity.hpp) as the tables name them: grains,
// packing_fraction, restitution, friction, tangential_restitution, rate, dt. std::out_of_range
// for another name.
const Column& identity_column(const std::string& name);

// The datasets a list of columns makes, in writing order: each column, then its error column.
std::vector<Column> table_datasets(const std::vector<Column>& columns);
template <class Row>
std::vector<Column> table_datasets(const std::vector<RowColumn<Row>>& columns) {
  std::vector<Column> plain;
  for (const auto& c : columns) plain.push_back(c.column);
  return table_datasets(plain);
}

class TableWriter {
 public:
  // Datasets under group ("/runs"); rows_note: the `rows` attribute of every numeric dataset
  // (empty: none).
  TableWriter(AnalysisWriter& writer, std::string group, std::string rows_note);

  void write(const Column& column, const std::vector<double>& values, const std::vector<double>& errors = {});
  // The integers of an int32, int64 or flag column, narrowed to its type.
  void write(const Column& column, const std::vector<std::int64_t>& values);
  void write(const Column& column, const std::vector<std::string>& values);

  // Every column of the declaration, in its order.
  template <class Row>
  void write(const std::vector<Row>& rows, const std::vector<RowColumn<Row>>& columns) {
    for (const auto& c : columns) {
      if (c.column.type == ColumnType::text) {
        write(c.column, collect<std::string>(rows, c.text));
      } else if (c.column.type != ColumnType::real) {
        write(c.column, collect<std::int64_t>(rows, c.integer));
      } else {
        write(c.column, collect<double>(rows, c.value),
              c.error ? collect<double>(rows, c.error) : std::vector<double>{});
      }
    }
  }

 private:
  template <class T, class Row, class F>
  static std::vector<T> collect(const std::vector<Row>& rows, const F& read) {
    std::vector<T> out;
    out.reserve(rows.size());
    for (const Row& r : rows) out.push_back(read(r));
    return out;
  }
  std::string path(const std::string& name) const { return group_ + "/" + name; }

  AnalysisWriter& writer_;
  std::string group_;
  Parameters extra_;
};

}  // namespace granflow::io
