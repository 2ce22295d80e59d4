#pragma once
// Across a sweep: ν_bc(e), the packing fraction at which ξ/ξ_el crosses a threshold
// (1.25 in the thesis, §5.2–5.3, Figs 5.9, 5.10), for every (e, μ) of the sweep.
//
// Runs with the same (e, μ) form a series in ν (runs at the same ν are merged: mean ξ,
// error √Σσ²/n). Scanning up in ν, the first pair of neighbours with
// ξ_1 < c·ξ_el ≤ ξ_2 brackets the crossing, interpolated linearly:
//   ν_bc = ν_1 + (c·ξ_el − ξ_1)(ν_2 − ν_1)/(ξ_2 − ξ_1),
// with the error propagated to first order from the independent errors of ξ_1, ξ_2 and
// ξ_el (the interpolation's own error, from the curvature of ξ(ν), is not included).
#include <limits>
#include <vector>

namespace granflow::correlation {

struct SweepPoint {
  double packing_fraction, restitution, friction;
  double xi, xi_error;
};

enum class CrossingStatus : int {
  bracketed = 0,     // interpolated between two runs
  all_above = 1,     // every run has ξ/ξ_el ≥ threshold: ν_bc is below the lowest ν
  all_below = 2,     // every run has ξ/ξ_el < threshold: ν_bc is above the highest ν
  too_few = 3,       // fewer than two distinct ν
  only_downward = 4  // ξ/ξ_el crosses the threshold only downwards (noisy or non-monotonic data)
};

struct Crossing {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  double restitution = kNaN, friction = kNaN;
  double nu_bc = kNaN, nu_bc_error = kNaN;
  double nu_below = kNaN, nu_above = kNaN;  // the bracketing packing fractions
  int runs = 0;                             // runs in the series
  int sign_changes = 0;                     // of ξ/ξ_el − threshold along ν (1 for clean data)
  CrossingStatus status = CrossingStatus::too_few;
};

// One entry per distinct (e, μ) of the points, in increasing e, then μ; points with a
// non-finite ξ are left out of their series (which is too_few if none is left).
std::vector<Crossing> binary_collision_crossings(const std::vector<SweepPoint>& points, double xi_el,
                                                 double xi_el_error, double threshold);

}  // namespace granflow::correlation
