#include "packing/packing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/error.hpp"
#include "packing/close_pairs.hpp"

namespace granflow {
namespace {

template <class T>
[[noreturn]] void reject(const char* option, T value, const char* rule) {
  std::ostringstream msg;
  msg << option << ": " << value << " " << rule;
  throw UsageError(msg.str());
}

void validate_grain_sizes(double mean_diameter, double polydispersity) {
  // Written as !(ok) so that NaN is rejected too.
  if (!(mean_diameter > 0 && std::isfinite(mean_diameter))) reject("--mean-diameter", mean_diameter, "must be > 0");
  if (!(polydispersity >= 0 && polydispersity < 1))
    reject("--polydispersity", polydispersity, "must be in [0, 1) (it is Δ/σ; diameters must stay positive)");
}

// Grain indices are int throughout (cell lists, contact pairs).
constexpr std::int64_t max_grains = std::numeric_limits<int>::max();

}  // namespace

void validate(const PackingParams& p) {
  if (p.grains < 2) reject("--grains", p.grains, "must be >= 2");
  if (p.grains > max_grains) reject("--grains", p.grains, "must be <= 2147483647");
  // 0.91 is just above the densest disk packing, π/(2√3) ≈ 0.9069; near and above
  // jamming (≈ 0.84) the result keeps a residual overlap, reported in max_overlap.
  if (!(p.packing_fraction > 0 && p.packing_fraction < 0.91))
    reject("--packing-fraction", p.packing_fraction, "must be in (0, 0.91)");
  validate_grain_sizes(p.mean_diameter, p.polydispersity);
  if (!(p.overlap_tolerance > 0 && std::isfinite(p.overlap_tolerance)))
    reject("--tolerance", p.overlap_tolerance, "must be > 0 (max overlap in units of the mean diameter)");
}

void validate(const InclineParams& p) {
  // A grain must never reach two periodic images of another: lx > 2 (σ+Δ) suffices.
  if (!(p.width >= 4 && std::isfinite(p.width))) reject("--width", p.width, "must be >= 4 (mean diameters)");
  if (!(p.height > 0 && std::isfinite(p.height))) reject("--height", p.height, "must be > 0 (mean diameters)");
  if (p.grains < 0) reject("--grains", p.grains, "must be >= 0 (0: derived from --height)");
  if (p.grains > max_grains) reject("--grains", p.grains, "must be <= 2147483647");
  validate_grain_sizes(p.mean_diameter, p.polydispersity);
}

std::vector<double> draw_radii(std::int64_t n, double mean_diameter, double polydispersity, Rng& rng) {
  const double delta = polydispersity * mean_diameter;
  std::vector<double> radius(std::size_t(std::max<std::int64_t>(n, 0)));
  for (double& r : radius) r = 0.5 * rng.uniform(mean_diameter - delta, mean_diameter + delta);
  return radius;
}

double max_overlap(const Box& box, const std::vector<Vec2>& position, const std::vector<double>& radius) {
  double worst = 0;
  for_each_close_pair(box, position, radius,
                      [&](int i, int j, const Vec2& d) { worst = std::max(worst, radius[i] + radius[j] - d.norm()); });
  return worst;
}

}  // namespace granflow
