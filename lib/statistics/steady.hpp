#pragma once
// The steady-state rule, one implementation for every consumer: gf-incline (flow rate and
// kinetic energy), gf-correlate --detect-transient (T and p of shear runs) and, through the
// C ABI (statistics/c_api.h) and python/granflow/statistics.py, the Python tables
// (steady_state.py, critical_angle.py).
//
// The rule: MSER truncation on block means of each series, the latest truncation wins;
// then the part kept must be stationary — the means of its first and second halves differ
// by at most a few combined standard errors. The error estimate fits the series it is
// given, the rule stays the same:
// - halves_agree() takes values that are already means of blocks longer than the
//   correlation time (gf-incline's /profiles blocks), i.e. independent values: each half's
//   error is the plain standard error of its values.
// - halves_change() takes one value per recorded row (the shear tables' T and p at every
//   strain step), correlated in time: each half's error is a blocking error
//   (statistics/blocking.hpp).
#include <cstddef>
#include <span>
#include <vector>

namespace granflow {

// MSER (White, Simulation 69, 323 (1997)): the truncation point d ≤ n/2 minimising
// Σ_{i≥d} (x_i − x̄_d)² / (n − d)², x̄_d the mean of x[d:] — the d that best trades the
// bias of a transient against the shorter average. Applied to block means this is
// MSER-b with b the block length. The first minimum on ties; 0 for n < 2.
std::size_t mser_truncation(std::span<const double> x);

// Whether the means of the first and second halves of x (the middle value of an odd
// count goes to neither) differ by at most `sigmas` combined standard errors, each
// half's error from the scatter of its values as independent block means. False with
// fewer than two values per half.
bool halves_agree(std::span<const double> x, double sigmas = 3);

struct HalvesChange {
  double change = 0;  // mean of the second half − mean of the first
  double error = 0;   // √(δ₁² + δ₂²), δ the blocking error of each half's mean
};

// The halves of a per-row series (the middle value of an odd count in neither), each
// half's error by blocking_error(): |change| / error is the stationarity test of the shear
// tables (steady_state.py's halves_z). The means are numpy's (python_arithmetic.hpp): the
// result equals the numpy formulation bit for bit. Throws std::invalid_argument when a half
// has fewer than kBlockingMinSamples values.
HalvesChange halves_change(std::span<const double> x);

struct SteadyState {
  std::size_t first = 0;                // first block of the steady part
  std::vector<std::size_t> truncation;  // MSER's d per series
  bool steady = false;                  // every series stationary from `first` on
};

// MSER on each series (equal lengths); the latest truncation wins. steady: every series
// passes halves_agree over blocks [first, n).
SteadyState detect_steady(const std::vector<std::vector<double>>& series);

// The same check for a steady part chosen by the user from block `first` on.
SteadyState steady_from(const std::vector<std::vector<double>>& series, std::size_t first);

// First row of the steady part of per-row series (equal lengths): each is cut into
// `blocks` blocks of max(1, rows / blocks) rows (rows left over at the end belong to
// none), MSER picks a truncation of each one's block means, and the latest wins; returned
// as a row (0 for an empty series). gf-correlate and steady_state.py's steady_start() both
// use it. The block means and MSER's sums are sequential sums (numpy's pairwise ones
// differ in the last bits, which can move MSER's choice only between near-equal minima).
std::size_t mser_first_row(const std::vector<std::vector<double>>& series, std::size_t blocks = 100);

}  // namespace granflow
