// The column lists of the per-run analysis tables in docs/file-format.md against the
// programs' own declarations (io/table_writer.hpp): every declared dataset is documented
// with its type, units, H5MD unit and meaning, and the docs list no other (in a group that
// also holds curves or maps, e.g. gf-correlate's /correlation, no other per-run [R] dataset).
// The docs keep their tables in name order; the declarations in writing order.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "correlation/report.hpp"
#include "io/table_writer.hpp"
#include "io/units.hpp"
#include "kinetic/table.hpp"
#include "network/table.hpp"
#include "stz/fit_table.hpp"

using namespace granflow;

namespace {

struct Documented {
  std::string type, units, unit, meaning;
  bool operator==(const Documented&) const = default;
};

std::ostream& operator<<(std::ostream& out, const Documented& d) {
  return out << d.type << " | " << d.units << " | " << d.unit << " | " << d.meaning;
}

// The cells of a markdown table row, `\|` read as a literal bar, each trimmed.
std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  for (std::size_t i = 1; i < line.size(); ++i) {
    if (line[i] == '\\' && i + 1 < line.size() && line[i + 1] == '|') {
      cell += '|';
      ++i;
    } else if (line[i] == '|') {
      const auto first = cell.find_first_not_of(' '), last = cell.find_last_not_of(' ');
      out.push_back(first == std::string::npos ? "" : cell.substr(first, last - first + 1));
      cell.clear();
    } else {
      cell += line[i];
    }
  }
  return out;
}

std::string unquoted(const std::string& cell) {
  return cell.size() >= 2 && cell.front() == '`' && cell.back() == '`' ? cell.substr(1, cell.size() - 2) : cell;
}

// The dataset table that follows the line "`<group>`:" in the section "### <section>" of
// docs/file-format.md, by dataset name; with shape (e.g. "[R]"), only its rows of that shape.
std::map<std::string, Documented> documented(const std::string& section, const std::string& group,
                                             const std::string& shape = "") {
  std::ifstream in(std::string(GRANFLOW_SOURCE_DIR) + "/docs/file-format.md");
  EXPECT_TRUE(in) << "docs/file-format.md not found under " << GRANFLOW_SOURCE_DIR;
  std::map<std::string, Documented> out;
  std::string line;
  bool in_section = false, in_group = false, in_table = false;
  while (std::getline(in, line)) {
    if (line.rfind("### ", 0) == 0) {
      in_section = line == "### " + section;
      in_group = false;
    } else if (in_section && line == "`" + group + "`:") {
      in_group = true;
    } else if (in_group && line.rfind("| `", 0) == 0) {
      in_table = true;
      const std::vector<std::string> c = cells(line);
      if (c.size() == 6 && (shape.empty() || c[1] == shape)) out[unquoted(c[0])] = {c[2], c[3], unquoted(c[4]), c[5]};
    } else if (in_table && line.empty()) {
      break;
    }
  }
  return out;
}

const char* type_name(io::ColumnType type) {
  switch (type) {
    case io::ColumnType::int32: return "int32";
    case io::ColumnType::int64: return "int64";
    case io::ColumnType::flag: return "uint8";
    case io::ColumnType::text: return "string";
    case io::ColumnType::real: break;
  }
  return "double";
}

// The datasets of a declaration (io::table_datasets), by name.
std::map<std::string, Documented> declared(const std::vector<io::Column>& datasets) {
  std::map<std::string, Documented> out;
  for (const io::Column& c : datasets) {
    if (c.type == io::ColumnType::text) out[c.name] = {"string", "", "", c.meaning};
    else out[c.name] = {type_name(c.type), c.units, io::unit_of(c.units), c.meaning};
  }
  return out;
}

// Names in reworded: their meaning depends on an option; the docs' may differ (the rest must not).
// With shape: the group's datasets of that shape (e.g. "[R]", its per-run table) against the
// declaration; its others (curves, maps, scalars) are not declared columns.
void expect_documented(const std::string& section, const std::string& group, const std::vector<io::Column>& datasets,
                       const std::set<std::string>& reworded = {}, const std::string& shape = "") {
  const std::map<std::string, Documented> docs = documented(section, group, shape), code = declared(datasets);
  ASSERT_FALSE(docs.empty()) << "no table after `" << group << "`: in ### " << section
                             << (shape.empty() ? "" : " with rows of shape " + shape);
  for (const auto& [name, d] : code) {
    const auto it = docs.find(name);
    if (it == docs.end()) ADD_FAILURE() << section << " " << group << "/" << name << ": declared, not documented";
    else if (reworded.contains(name))
      EXPECT_EQ(it->second, (Documented{d.type, d.units, d.unit, it->second.meaning}))
          << section << " " << group << "/" << name << ": docs (left) and declaration differ";
    else EXPECT_EQ(it->second, d) << section << " " << group << "/" << name << ": docs (left) and declaration differ";
  }
  for (const auto& [name, d] : docs)
    if (!code.contains(name)) ADD_FAILURE() << section << " " << group << "/" << name << ": documented, not declared";
}

}  // namespace

TEST(TableColumns, CellsReadEscapedBars) {
  EXPECT_EQ(cells("| `a` | <m\\|V\\|^2> |"), (std::vector<std::string>{"`a`", "<m|V|^2>"}));
}

TEST(TableColumns, ErrorColumnFollowsItsValue) {
  const std::vector<io::Column> d = io::table_datasets(
      {{"x", "length", "x", "x_error", "error of x"}, {"n", "1", "count", {}, {}, io::ColumnType::int32}});
  ASSERT_EQ(d.size(), 3u);
  EXPECT_EQ(d[1].name, "x_error");
  EXPECT_EQ(d[1].units, "length");
  EXPECT_EQ(d[1].meaning, "error of x");
  EXPECT_EQ(d[2].name, "n");
}

TEST(TableColumns, GfKineticAsDocumented) {
  expect_documented("gf-kinetic table", "/runs", io::table_datasets(kinetic::run_columns()));
  expect_documented("gf-kinetic table", "/equilibrium", io::table_datasets(kinetic::equilibrium_columns()));
}

TEST(TableColumns, GfCorrelateAsDocumented) {
  expect_documented("gf-correlate table", "/runs", io::table_datasets(correlation::run_columns()));
  expect_documented("gf-correlate table", "/reference", io::table_datasets(correlation::reference_columns()));
  expect_documented("gf-correlate table", "/correlation", io::table_datasets(correlation::correlation_columns()), {},
                    "[R]");
  expect_documented("gf-correlate table", "/forces", io::table_datasets(correlation::force_columns()), {}, "[R]");
}

TEST(TableColumns, GfNetworkAsDocumented) {
  expect_documented("gf-network table", "/runs", io::table_datasets(network::run_columns()));
  // xi_ratio's meaning names the --xi reading; the docs name all three.
  expect_documented("gf-network table", "/prediction",
                    io::table_datasets(network::prediction_columns(correlation::XiReading::abs)), {"xi_ratio"});
}

TEST(TableColumns, GfStzFitAsDocumented) {
  expect_documented("gf-stz fit table", "/runs", io::table_datasets(stz::run_columns()));
  expect_documented("gf-stz fit table", "/fit", io::table_datasets(stz::fit_columns()));
}
