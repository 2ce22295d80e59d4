#include "correlation/sweep.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace granflow::correlation {

std::vector<Crossing> binary_collision_crossings(const std::vector<SweepPoint>& points, double xi_el,
                                                 double xi_el_error, double threshold) {
  // (e, μ) → ν → the runs' (ξ, σ) at that ν.
  std::map<std::pair<double, double>, std::map<double, std::vector<std::pair<double, double>>>> series;
  // Every (e, μ) of the points has an entry, even with no finite ξ (then too_few), so that
  // crossings of different ξ estimates over the same runs line up.
  for (const auto& p : points) {
    auto& by_nu = series[{p.restitution, p.friction}];
    if (std::isfinite(p.xi)) by_nu[p.packing_fraction].push_back({p.xi, p.xi_error});
  }

  std::vector<Crossing> out;
  const double target = threshold * xi_el;
  for (const auto& [key, by_nu] : series) {
    Crossing c;
    c.restitution = key.first;
    c.friction = key.second;
    std::vector<double> nu, xi, err;
    for (const auto& [v, runs] : by_nu) {
      double mean = 0, var = 0;
      for (const auto& [x, e] : runs) {
        mean += x / double(runs.size());
        var += e * e;
      }
      nu.push_back(v);
      xi.push_back(mean);
      err.push_back(std::sqrt(var) / double(runs.size()));
      c.runs += int(runs.size());
    }
    out.push_back(c);
    Crossing& r = out.back();
    if (nu.size() < 2 || !(xi_el > 0)) continue;
    for (std::size_t k = 0; k + 1 < nu.size(); ++k)
      if ((xi[k] < target) != (xi[k + 1] < target)) ++r.sign_changes;
    std::size_t k = 0;
    while (k + 1 < nu.size() && !(xi[k] < target && xi[k + 1] >= target)) ++k;
    if (k + 1 == nu.size()) {
      const bool above = std::all_of(xi.begin(), xi.end(), [&](double x) { return x >= target; });
      const bool below = std::all_of(xi.begin(), xi.end(), [&](double x) { return x < target; });
      r.status = above ? CrossingStatus::all_above : below ? CrossingStatus::all_below : CrossingStatus::only_downward;
      continue;
    }
    const double dnu = nu[k + 1] - nu[k], dxi = xi[k + 1] - xi[k];
    r.nu_below = nu[k];
    r.nu_above = nu[k + 1];
    r.nu_bc = nu[k] + (target - xi[k]) * dnu / dxi;
    // ∂ν/∂ξ_1, ∂ν/∂ξ_2, ∂ν/∂ξ_el of the interpolation.
    const double d1 = dnu * (target - xi[k + 1]) / (dxi * dxi);
    const double d2 = -dnu * (target - xi[k]) / (dxi * dxi);
    const double del = threshold * dnu / dxi;
    r.nu_bc_error = std::sqrt(d1 * d1 * err[k] * err[k] + d2 * d2 * err[k + 1] * err[k + 1] +
                              del * del * xi_el_error * xi_el_error);
    r.status = CrossingStatus::bracketed;
  }
  return out;
}

}  // namespace granflow::correlation
