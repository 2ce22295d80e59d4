#include "correlation/table_lookup.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/error.hpp"
#include "core/sha256.hpp"
#include "io/hdf5_handle.hpp"

namespace granflow::correlation {

namespace {

double read_scalar(hid_t file, const std::string& name) {
  io::Dataset d = io::open_dataset(file, name);
  if (!io::shape(d.get()).empty()) throw io::Hdf5Error(io::where(d.get()) + ": expected a scalar");
  double x = 0;
  io::check(H5Dread(d.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, &x), d.get(), "read");
  return x;
}

struct Reading {
  XiReading reading;
  const char* name;
  const char* ratio;  // dataset of /correlation
  const char* el;
};
constexpr Reading kReadings[] = {
    {XiReading::abs, "abs", "xi_abs_ratio", "xi_abs_el"},
    {XiReading::signed_area, "signed", "xi_ratio", "xi_el"},
    {XiReading::signed_length, "signed-length", "xi_length_ratio", "xi_length_el"},
};

const Reading& reading_of(XiReading reading) {
  for (const Reading& r : kReadings)
    if (r.reading == reading) return r;
  return kReadings[0];
}

}  // namespace

const char* xi_reading_name(XiReading reading) { return reading_of(reading).name; }

const char* xi_ratio_dataset(XiReading reading) { return reading_of(reading).ratio; }

std::optional<XiReading> parse_xi_reading(const std::string& name) {
  for (const Reading& r : kReadings)
    if (name == r.name) return r.reading;
  return std::nullopt;
}

std::vector<XiValue> read_xi_ratios(const std::string& table, const std::vector<std::string>& runs, XiReading reading,
                                    const std::string& program) {
  const bool signed_xi = reading != XiReading::abs;
  auto bad = [&](const std::string& what) { return UsageError("'" + table + "': " + what); };
  io::silence_hdf5_errors();
#if H5_VERSION_GE(1, 12, 0)
  const htri_t is_hdf5 = H5Fis_accessible(table.c_str(), H5P_DEFAULT);
#else
  const htri_t is_hdf5 = H5Fis_hdf5(table.c_str());
#endif
  if (is_hdf5 < 0) throw bad("cannot read: " + io::hdf5_reason());
  if (is_hdf5 == 0) throw bad("not an HDF5 file");
  try {
    const io::File file = io::open_file(table, false);
    const hid_t f = file.get();
    auto attribute = [&](const std::string& name) -> std::string {
      if (!io::exists(f, "/parameters")) return "";
      const io::Group g = io::open_group(f, "/parameters");
      if (!io::has_attribute(g.get(), name)) return "";
      const io::Attribute a = io::open_attribute(g.get(), name);
      if (io::attribute_class(a.get()) != H5T_STRING) return "";
      return io::read_string_attribute(a.get());
    };
    if (attribute("program") != "gf-correlate")
      throw bad("not a gf-correlate table (/parameters program is not gf-correlate); --correlation needs one");
    const std::string ratio = std::string("/correlation/") + reading_of(reading).ratio;
    const std::string el = std::string("/correlation/") + reading_of(reading).el;
    for (const std::string& name : {ratio, ratio + "_error", el})
      if (!io::exists(f, name))
        throw bad("no " + name + ": made without --reference" +
                  (reading == XiReading::signed_length ? " or by a gf-correlate older than xi_length" : "") + " (" +
                  program + " needs xi_el to read xi/xi_el)");
    const double xi_el = read_scalar(f, el);
    if (!std::isfinite(xi_el))
      throw bad(el + " is not finite: made without --reference (" + program + " needs xi_el to read xi/xi_el)");
    const std::vector<double> value = io::read_all<double>(io::open_dataset(f, ratio).get());
    const std::vector<double> error = io::read_all<double>(io::open_dataset(f, ratio + "_error").get());
    std::vector<std::int32_t> measurable;
    if (!signed_xi) {
      if (!io::exists(f, "/correlation/measurable")) throw bad("no /correlation/measurable: not a gf-correlate table");
      measurable = io::read_all<std::int32_t>(io::open_dataset(f, "/correlation/measurable").get());
    }
    // The table's inputs: input, input_1, ... with their sha256, one /correlation row each.
    std::vector<std::string> hashes;
    for (std::size_t k = 0;; ++k) {
      const std::string key = k == 0 ? "input_sha256" : "input_" + std::to_string(k) + "_sha256";
      const std::string h = attribute(key);
      if (h.empty()) break;
      hashes.push_back(h);
    }
    if (hashes.empty() || hashes.size() != value.size() || error.size() != value.size() ||
        (!signed_xi && measurable.size() != value.size()))
      throw bad("its inputs (/parameters input_<k>_sha256) and " + ratio + " rows differ in number");
    std::vector<XiValue> out;
    for (const std::string& run : runs) {
      const std::string h = sha256_file(run);
      const auto it = std::find(hashes.begin(), hashes.end(), h);
      if (it == hashes.end())
        throw UsageError("'" + run + "': not among the runs of the correlation table '" + table +
                         "' (no input with its sha256)");
      const std::size_t k = std::size_t(it - hashes.begin());
      out.push_back({value[k], error[k], signed_xi ? std::isfinite(value[k]) : measurable[k] != 0});
    }
    return out;
  } catch (const io::Hdf5Error& e) {
    throw UsageError(e.what());
  }
}

}  // namespace granflow::correlation
