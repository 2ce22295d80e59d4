#pragma once
// Block jackknife: errors of estimators that are nonlinear in sums over frames (ratios
// such as gf-correlate's C = Σw/W or ξ = Σw/Σ(w/ℓ)), where blocking a series of values
// (statistics/blocking.hpp) does not apply: a ratio of sums has no per-frame value to
// block. Frames are grouped into consecutive blocks longer than the correlation time; the
// estimator is recomputed with each block left out, and
//   error² = (B − 1)/B · Σ_b (x_(b) − x̄)²,   x̄ = mean of the x_(b).
#include <cmath>
#include <limits>
#include <vector>

namespace granflow {

// Per component of estimate(sums) (a std::vector<double>): the jackknife standard error
// over blocks; NaN with fewer than two blocks or where a leave-one-out value is NaN.
// Sums needs copy and +=.
template <class Sums, class Estimator>
std::vector<double> jackknife_errors(const std::vector<Sums>& blocks, const Estimator& estimate) {
  const std::size_t n = blocks.size();
  std::vector<std::vector<double>> left_out;
  for (std::size_t b = 0; n >= 2 && b < n; ++b) {
    Sums others = blocks[b == 0 ? 1 : 0];
    for (std::size_t k = 0; k < n; ++k)
      if (k != b && k != (b == 0 ? 1u : 0u)) others += blocks[k];
    left_out.push_back(estimate(others));
  }
  if (left_out.empty())
    return std::vector<double>(estimate(blocks.front()).size(), std::numeric_limits<double>::quiet_NaN());
  std::vector<double> error(left_out.front().size());
  for (std::size_t c = 0; c < error.size(); ++c) {
    double mean = 0;
    for (const auto& x : left_out) mean += x[c] / double(n);
    double sum2 = 0;
    for (const auto& x : left_out) sum2 += (x[c] - mean) * (x[c] - mean);
    error[c] = std::sqrt(double(n - 1) / double(n) * sum2);
  }
  return error;
}

}  // namespace granflow
