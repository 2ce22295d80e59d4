#include "shear/steady_window.hpp"
#include "core/format.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.hpp"
#include "statistics/steady.hpp"

namespace granflow::shear_run {

namespace {

template <class Read>
auto observable_rows(const Opened& o, const std::string& path, const char* name, Read read) {
  if (!o.reader.has_observable(name))
    throw UsageError("'" + path + "': no /observables/" + name + " (not a gf-shear trajectory of this version)");
  auto x = read(name);
  if (x.size() != o.strain.size())
    throw UsageError("'" + path + "': /observables/" + name + " and /observables/strain differ in length");
  return x;
}

}  // namespace

Opened open(const std::string& path, const std::string& program) {
  Opened o{io::TrajectoryReader(path)};
  auto bad = [&](const std::string& what) { return UsageError("'" + path + "': " + what); };
  o.parameters = o.reader.parameters();
  if (o.parameters.has("program") && o.parameters.get_string("program") == "gf-pack")
    throw bad("is a packing (made by gf-pack), not a trajectory; run gf-shear on it first");
  if (!o.reader.has_observable("strain")) throw bad("no /observables/strain: not a gf-shear trajectory");
  if (!o.reader.box(0).periodic_y)
    throw bad("the box is open in y (an incline run); " + program + " needs a gf-shear run");
  o.strain = o.reader.observable_scalar("strain");
  o.time = o.reader.observable_time("strain");
  o.step = o.reader.observable_step("strain");
  if (o.strain.empty()) throw bad("no observable rows");
  o.rate = o.reader.lees_edwards_rate();
  return o;
}

std::vector<double> observable(const Opened& o, const std::string& path, const char* name) {
  return observable_rows(o, path, name, [&](const char* n) { return o.reader.observable_scalar(n); });
}

std::vector<Mat2> tensor(const Opened& o, const std::string& path, const char* name) {
  return observable_rows(o, path, name, [&](const char* n) { return o.reader.observable_tensor(n); });
}

Window window(const Opened& o, const std::string& path, const WindowSettings& s) {
  const std::size_t rows = o.strain.size();
  std::size_t transient = 0;
  if (s.detect_transient)
    transient = mser_first_row({observable(o, path, "temperature"), observable(o, path, "pressure")});
  std::size_t first = rows;
  if (o.rate != 0) {
    double from = s.from_strain;
    if (transient < rows) from = std::max(from, std::fabs(o.strain[transient]));
    // The tolerance absorbs the round-off of strain = γ̇·t at the row meant to start at it.
    for (std::size_t r = 0; r < rows && first == rows; ++r)
      if (std::fabs(o.strain[r]) >= from - 1e-9) first = r;
    if (first == rows)
      throw UsageError("'" + path + "': --from-strain " + format_number(from) +
                       " is past the end of the run (last row at strain " + format_number(std::fabs(o.strain.back())) +
                       ")");
  } else {
    double from = s.from_time >= 0 ? s.from_time : 0.5 * o.time.back();
    if (transient < rows) from = std::max(from, o.time[transient]);
    for (std::size_t r = 0; r < rows && first == rows; ++r)
      if (o.time[r] >= from * (1 - 1e-12)) first = r;
    if (first == rows)
      throw UsageError("'" + path + "': --from-time " + format_number(from) +
                       " is past the end of the run (last row at time " + format_number(o.time.back()) + ")");
  }
  if (rows - first < 2)
    throw UsageError("'" + path + "': fewer than 2 observable rows in the window; start it earlier");
  return {first, first > 0 ? o.step[first - 1] : 0};
}

std::vector<std::size_t> window_frames(const Opened& o, const Window& w) {
  const std::vector<std::int64_t> steps = o.reader.frame_steps();
  std::vector<std::size_t> frames;
  for (std::size_t k = 0; k < steps.size(); ++k)
    if (steps[k] > 0 && steps[k] > w.previous_step && steps[k] <= o.step.back()) frames.push_back(k);
  return frames;
}

}  // namespace granflow::shear_run
