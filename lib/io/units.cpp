#include "io/units.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "core/error.hpp"

namespace granflow::io {

namespace {

// The symbols in the order unit strings list them, and the powers of each word.
constexpr std::array<const char*, 6> kSymbols{"M", "L", "T", "tau", "rad", "deg"};
using Powers = std::array<int, kSymbols.size()>;

struct Word {
  const char* name;
  Powers powers;
};
constexpr Word kWords[] = {
    {"length", {0, 1, 0, 0, 0, 0}},    {"mass", {1, 0, 0, 0, 0, 0}},    {"time", {0, 0, 1, 0, 0, 0}},
    {"velocity", {0, 1, -1, 0, 0, 0}}, {"force", {1, 1, -2, 0, 0, 0}},  {"tau", {0, 0, 0, 1, 0, 0}},
    {"radian", {0, 0, 0, 0, 1, 0}},    {"degrees", {0, 0, 0, 0, 0, 1}},
};

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(' ');
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(' ') - first + 1);
}

// Adds sign × the powers of one factor ("velocity²", "length^2", "1") to total.
void add_factor(const std::string& quantity, std::string factor, int sign, Powers& total) {
  factor = trim(factor);
  int power = 1;
  if (const auto caret = factor.find('^'); caret != std::string::npos) {
    const std::string digits = factor.substr(caret + 1);
    if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos)
      throw RuntimeFailure("unit of '" + quantity + "': bad power '" + digits + "'");
    power = std::stoi(digits);
    factor.resize(caret);
  } else if (factor.size() > 2 && factor.compare(factor.size() - 2, 2, "\u00b2") == 0) {
    power = 2;
    factor.resize(factor.size() - 2);
  } else if (factor.size() > 2 && factor.compare(factor.size() - 2, 2, "\u00b3") == 0) {
    power = 3;
    factor.resize(factor.size() - 2);
  }
  if (factor == "1") return;
  for (const Word& w : kWords)
    if (factor == w.name) {
      for (std::size_t k = 0; k < total.size(); ++k) total[k] += sign * power * w.powers[k];
      return;
    }
  throw RuntimeFailure("unit of '" + quantity + "': unknown quantity '" + factor + "'");
}

void add_product(const std::string& quantity, const std::string& product, int sign, Powers& total) {
  const std::string dot = "\u00b7";
  std::size_t begin = 0;
  for (;;) {
    const std::size_t end = product.find(dot, begin);
    add_factor(quantity, product.substr(begin, end - begin), sign, total);
    if (end == std::string::npos) return;
    begin = end + dot.size();
  }
}

}  // namespace

std::string unit_of(const std::string& quantity) {
  std::string words = quantity;
  // A remark in parentheses ("(2D stress)", "(code units)") names no unit.
  for (std::size_t open; (open = words.find('(')) != std::string::npos;) {
    const std::size_t close = words.find(')', open);
    if (close == std::string::npos) throw RuntimeFailure("unit of '" + quantity + "': unclosed '('");
    words.erase(open, close - open + 1);
  }
  words = trim(words);
  if (words.empty()) throw RuntimeFailure("unit of '" + quantity + "': no quantity");
  Powers powers{};
  const std::size_t slash = words.find('/');
  if (slash != std::string::npos && words.find('/', slash + 1) != std::string::npos)
    throw RuntimeFailure("unit of '" + quantity + "': more than one '/'");
  add_product(quantity, words.substr(0, slash), +1, powers);
  if (slash != std::string::npos) add_product(quantity, words.substr(slash + 1), -1, powers);
  std::string unit;
  for (std::size_t k = 0; k < kSymbols.size(); ++k) {
    if (powers[k] == 0) continue;
    if (!unit.empty()) unit += ' ';
    unit += kSymbols[k];
    if (powers[k] != 1) unit += (powers[k] > 0 ? "+" : "") + std::to_string(powers[k]);
  }
  return unit.empty() ? "1" : unit;
}

namespace {

void write_ascii_attribute(hid_t loc, const std::string& name, const std::string& value) {
  if (has_attribute(loc, name)) check(H5Adelete(loc, name.c_str()), loc, "delete attribute " + name);
  Datatype type(check(H5Tcopy(H5T_C_S1), loc, "copy string type"));
  check(H5Tset_size(type.get(), std::max<std::size_t>(value.size(), 1)), loc, "set string size");
  check(H5Tset_strpad(type.get(), H5T_STR_NULLPAD), loc, "set string padding");
  check(H5Tset_cset(type.get(), H5T_CSET_ASCII), loc, "set string character set");
  Dataspace space(check(H5Screate(H5S_SCALAR), loc, "create dataspace for attribute " + name));
  Attribute attribute(check(H5Acreate2(loc, name.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT), loc,
                            "create attribute " + name));
  std::string padded = value;
  padded.resize(std::max<std::size_t>(value.size(), 1), '\0');
  check(H5Awrite(attribute.get(), type.get(), padded.data()), loc, "write attribute " + name);
}

}  // namespace

void write_unit(hid_t dataset, const std::string& unit) { write_ascii_attribute(dataset, "unit", unit); }

void write_units_module(hid_t h5md_group) {
  Group modules =
      exists(h5md_group, "modules") ? open_group(h5md_group, "modules") : create_group(h5md_group, "modules");
  Group units = create_group(modules.get(), "units");
  write_attribute(units.get(), "version", std::vector<std::int32_t>{1, 0});
  write_ascii_attribute(units.get(), "system", kUnitSystem);
}

}  // namespace granflow::io
