#pragma once
// Standard error of the mean of a correlated series (one value per recorded row, e.g. T
// and p of a shear run at every strain step) by Flyvbjerg–Petersen blocking
// (J. Chem. Phys. 91, 461 (1989)) with the level chosen by Jonsson's test (Phys. Rev. E
// 98, 043304 (2018)). This is the error estimate for series whose values are correlated
// in time; series of block means longer than the correlation time (gf-incline's flow-rate
// blocks) are independent values, and their standard error is the plain one
// (statistics/steady.hpp, halves_agree()).
//
// Level 0 is the series itself; each next level replaces it by the means of neighbouring
// pairs, after dropping the oldest value of an odd count so that the pairs stay aligned.
// At each level with m values, mean x̄ and variance σ² = Σ(x − x̄)²/m, the squared
// standard error estimate is σ²/(m − 1): it grows with the level until the blocks are
// longer than the correlation time, then stays flat. Jonsson's statistic of a level is
// m·(γ/σ²)², γ = (m − 1)σ²/m² + Σ_i (x_i − x̄)(x_{i+1} − x̄)/(m − 1) the bias-corrected lag-1
// autocovariance; the plateau starts at the first level j whose sum of statistics over
// levels ≥ j is below the 99 % quantile of χ² with (levels − j) degrees of freedom
// (Wilson–Hilferty). The error is read one level higher than that (blocks twice as long,
// which halves the bias left by the residual correlation at the first level), and only
// from levels with at least kBlockingMinBlocks blocks: when no such level passes the test,
// the longest such blocks are used and `plateau` is false — the error is then a lower
// bound, the series too short for its correlation time. On AR(1) series the error is low
// by at most 15 % when the series spans 50 integrated correlation times, 10 % at 100 and
// 3 % beyond 1000.
//
// The means are numpy's pairwise sums (statistics/python_arithmetic.hpp): every value here
// equals bit for bit the same algorithm written with numpy (pipelines/tests/test_statistics.py
// checks it).
#include <cstddef>
#include <span>

namespace granflow {

inline constexpr std::size_t kBlockingMinSamples = 32;  // fewest values blocking accepts
inline constexpr std::size_t kBlockingMinBlocks = 16;   // fewest blocks an error is read from (±18 %)

struct Blocking {
  double error = 0;        // standard error of the mean
  std::size_t blocks = 0;  // values at the level the error is read from
  bool plateau = false;    // whether Jonsson's test found the plateau
};

// Throws std::invalid_argument with fewer than kBlockingMinSamples values.
Blocking blocking_error(std::span<const double> x);

// The 99 % quantile of χ² with `dof` degrees of freedom by the Wilson–Hilferty
// approximation (within 1 % for dof ≥ 1).
double chi2_quantile_99(std::size_t dof);

}  // namespace granflow
