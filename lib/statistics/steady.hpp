#pragma once
// Where a run's steady state starts, from series of block means (one value per time
// block of equal length): MSER truncation, then a check that what is left is stationary.
// gf-incline applies it to flow rate and kinetic energy, gf-correlate (and the pipelines'
// steady_state.py, with the same rule) to T and p of shear runs.
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
// as a row (0 for an empty series).
std::size_t mser_first_row(const std::vector<std::vector<double>>& series, std::size_t blocks = 100);

}  // namespace granflow
