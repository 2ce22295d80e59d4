#include "packing/start_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.hpp"
#include "io/schema.hpp"
#include "packing/close_pairs.hpp"

namespace granflow {

void check_start_grains(const std::string& path, std::size_t frame, const Box& box, const std::vector<Vec2>& position,
                        const std::vector<double>& radius) {
  // The worst pair by overlap relative to the smaller radius, the lowest (i, j) among equals,
  // so that the message does not depend on the cell order.
  double worst = 0, worst_distance = 0;
  int wi = -1, wj = -1;
  for_each_close_pair(box, position, radius, [&](int i, int j, const Vec2& d) {
    const double distance = d.norm(), smaller = std::min(radius[i], radius[j]);
    const double share = (radius[i] + radius[j] - distance) / smaller;
    const int a = std::min(i, j), b = std::max(i, j);
    if (share > worst || (share == worst && wi >= 0 && std::pair(a, b) < std::pair(wi, wj))) {
      worst = share;
      worst_distance = distance;
      wi = a;
      wj = b;
    }
  });
  if (wi < 0 || worst <= kMaxStartOverlap) return;
  const std::string where = "'" + path + "': frame " + std::to_string(frame) + ": grains " + std::to_string(wi) +
                            " and " + std::to_string(wj);
  if (worst_distance <= kCoincidentCentres * std::min(radius[wi], radius[wj]))
    throw UsageError(where + " are at the same position (coincident centres)");
  char text[160];
  std::snprintf(text, sizeof text,
                " overlap by %.3g of the smaller radius (centres %.6g apart); a start may overlap by at most %g", worst,
                worst_distance, kMaxStartOverlap);
  throw UsageError(where + text);
}

void check_start_contacts(const std::string& path, std::size_t frame, const io::ContactRecords& contacts) {
  for (std::size_t r = 0; r < contacts.size(); ++r) {
    const auto [i, j] = contacts.pair[r];
    const std::string where = "'" + path + "': " + io::schema::kContacts + "/";
    const std::string which = ": frame " + std::to_string(frame) + ", contact " + std::to_string(r) + " ";
    const std::string pair = "(" + std::to_string(i) + ", " + std::to_string(j) + ")";
    if (!(i < j)) throw UsageError(where + "pair" + which + pair + " must have i < j");
    if (r > 0 && !(contacts.pair[r - 1] < contacts.pair[r]))
      throw UsageError(where + "pair" + which + pair + " repeats or breaks the increasing order of the pairs");
    if (!(contacts.age[r] >= 1))
      throw UsageError(where + "age" + which + "is " + std::to_string(contacts.age[r]) + ", must be >= 1");
  }
}

void require_run_contacts(const io::TrajectoryReader& input) {
  if (input.has_contacts()) return;
  const io::Parameters parameters = input.parameters();
  if (!parameters.has("program")) return;
  const io::Parameters::Value& program = parameters.items().at("program");
  const std::string* name = std::get_if<std::string>(&program);
  if (!name || (*name != "gf-shear" && *name != "gf-incline")) return;
  throw UsageError("'" + input.path() + "': no group " + io::schema::kContacts + ", which every " + *name +
                   " trajectory has (its contacts are the warm start of a restart from its frames)");
}

}  // namespace granflow
