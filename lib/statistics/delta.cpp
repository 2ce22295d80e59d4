#include "statistics/delta.hpp"

#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "statistics/blocking.hpp"

namespace granflow::statistics {

double mean(std::span<const double> x) {
  if (x.empty()) return std::numeric_limits<double>::quiet_NaN();
  return std::accumulate(x.begin(), x.end(), 0.0) / double(x.size());
}

double mean_error(std::span<const double> x) {
  if (x.size() >= kBlockingMinSamples) return blocking_error(x).error;
  if (x.size() < 2) return std::numeric_limits<double>::quiet_NaN();
  const double m = mean(x);
  double ss = 0;
  for (double v : x) ss += (v - m) * (v - m);
  return std::sqrt(ss / double(x.size() - 1) / double(x.size()));
}

double delta_error(const std::vector<std::pair<std::span<const double>, double>>& terms) {
  if (terms.empty()) return std::numeric_limits<double>::quiet_NaN();
  const std::size_t n = terms.front().first.size();
  std::vector<double> linear(n, 0.0);
  for (const auto& [x, g] : terms) {
    if (x.size() != n) throw std::invalid_argument("delta_error: series of different lengths");
    for (std::size_t r = 0; r < n; ++r) linear[r] += g * x[r];
  }
  return mean_error(linear);
}

}  // namespace granflow::statistics
