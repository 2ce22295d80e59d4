#pragma once
// Window means of per-row (or per-frame) series and their errors, shared by the analysis
// tables of gf-kinetic and gf-network.
//
// Every quantity is a smooth function f of window means x̄_k of series of equal length; its
// error is the standard error of the mean of the linearised series Σ_k (∂f/∂x̄_k)·x_k (the
// delta method, covariances included), by blocking (statistics/blocking.hpp) with at least
// kBlockingMinSamples values, else the plain standard error (stored frames are usually far
// apart in time).
#include <span>
#include <utility>
#include <vector>

namespace granflow::statistics {

// Arithmetic mean; NaN for an empty series.
double mean(std::span<const double> x);

// Standard error of the mean of x: blocking_error() with ≥ kBlockingMinSamples values, the
// plain standard error with 2 to kBlockingMinSamples − 1, NaN with fewer.
double mean_error(std::span<const double> x);

// Error of f(x̄_1, x̄_2, ...) by the delta method: mean_error of Σ_k g_k·x_k, g_k = ∂f/∂x̄_k;
// every series of the same length (std::invalid_argument otherwise); NaN without a term.
double delta_error(const std::vector<std::pair<std::span<const double>, double>>& terms);

}  // namespace granflow::statistics
