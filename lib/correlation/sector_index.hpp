#pragma once
// The sector of a lag's angle and the binning of a lag into the pair sums and the map, shared
// by the exact pair sums (force_correlation.cpp) and the FFT sums (fft_correlation.cpp), so
// that both put a lag in the same bins by the same arithmetic.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "correlation/force_correlation.hpp"

namespace granflow::correlation {

// Sector of a lag's angle mod π among K equal sectors of [0, π), without atan2 (which
// would cost more than everything else per pair), exactly as exact() decides it:
// - exact(): the direction is folded onto the upper half-plane, where t = 1 − cos θ grows
//   monotonically over [0, 2); the sector boundaries are precomputed in t, and a table
//   over t finds the sector with at most one comparison (its cells are at most half as
//   wide as the narrowest sector, 1 − cos(π/K) at the ends);
// - of(): most lags fall in a bin of the map grid that lies wholly inside one sector (its
//   four corners do, and it does not touch an axis); a table per map bin stores that
//   sector, and only lags in the other bins need exact().
class SectorIndex {
 public:
  explicit SectorIndex(const LagGrid& grid)
      : sectors_(grid.angle_bins), boundary_(grid.angle_bins + 1),
        table_(std::size_t(std::ceil(4 / (1 - std::cos(M_PI / grid.angle_bins))))),
        by_bin_(std::size_t(grid.map_side()) * grid.map_side()) {
    for (int m = 0; m <= sectors_; ++m) boundary_[m] = 1 - std::cos(m * M_PI / sectors_);
    boundary_[0] = 0;
    boundary_[sectors_] = 2;
    scale_ = 0.5 * double(table_.size());
    last_cell_ = int(table_.size()) - 1;
    for (std::size_t c = 0, k = 0; c < table_.size(); ++c) {
      while (int(k) + 1 < sectors_ && boundary_[k + 1] <= double(c) / scale_) ++k;
      table_[c] = int(k);
    }
    const int side = grid.map_side();
    for (int iy = 0; iy < side; ++iy)
      for (int ix = 0; ix < side; ++ix) {
        int sector = -2;
        for (int corner = 0; corner < 4 && sector != -1; ++corner) {
          const double x = (ix - grid.map_half + corner % 2) * grid.map_bin;
          const double y = (iy - grid.map_half + corner / 2) * grid.map_bin;
          const int k = (x == 0 || y == 0) ? -1 : exact(x, y, 1 / std::hypot(x, y));
          sector = (sector == -2 || sector == k) ? k : -1;
        }
        by_bin_[iy * side + ix] = std::int16_t(sector);
      }
  }

  // The sector of the lag (dx, dy) of length 1/inv_length, which lies in map bin `bin`.
  int of(int bin, double dx, double dy, double inv_length) const {
    const int k = by_bin_[bin];
    return k >= 0 ? k : exact(dx, dy, inv_length);
  }

  // The lower half-plane maps onto the upper by d → −d, i.e. cos θ → −cos θ, without a
  // branch; directions along the x axis (θ = 0 or π, both 0 mod π) are decided apart.
  int exact(double dx, double dy, double inv_length) const {
    if (dy == 0) return 0;
    const double t = 1 - std::copysign(1.0, dy) * dx * inv_length;
    int k = table_[std::min(int(t * scale_), last_cell_)];
    if (k + 1 < sectors_ && t >= boundary_[k + 1]) ++k;
    return k;
  }

 private:
  int sectors_;
  std::vector<double> boundary_;
  std::vector<int> table_;
  double scale_;
  int last_cell_;
  std::vector<std::int16_t> by_bin_;
};

// Adds a weight w at a lag (dx, dy), 0 < dx² + dy² = lag2 < ℓ_max², to every sum of PairSums
// and to the map (if it is not empty), for one frame.
class LagBinner {
 public:
  LagBinner(const LagGrid& grid, const SectorIndex& sectors, PairSums& sums, std::vector<double>& map)
      : sectors_(sectors), sums_(sums), map_(map), inv_bin_(1 / grid.bin_width), inv_h_(1 / grid.map_bin),
        half_(grid.map_half), last_bin_(grid.radial_bins - 1), side_(grid.map_side()),
        coarse_of_(std::size_t(grid.radial_bins)), coarse_bins_(std::size_t(grid.coarse_bins())),
        with_map_(!map.empty()) {
    // Each radial bin's coarse bin (a table: an integer division per lag would cost more than
    // the two additions it feeds).
    for (int b = 0; b < grid.radial_bins; ++b) coarse_of_[std::size_t(b)] = b / grid.coarse;
  }

  void add(double dx, double dy, double lag2, double w) {
    const double lag = std::sqrt(lag2), inv_lag = 1 / lag;
    const int b = std::min(int(lag * inv_bin_), last_bin_);
    sums_.w[b] += w;
    sums_.w_over_lag[b] += w * inv_lag;
    sums_.w_times_lag[b] += w * lag;
    // |x| < ℓ_max ≤ map_half·h, so x/h + map_half > 0 and truncation is the floor.
    const int bin =
        std::min(int(dy * inv_h_ + half_), side_ - 1) * side_ + std::min(int(dx * inv_h_ + half_), side_ - 1);
    const int k = sectors_.of(bin, dx, dy, inv_lag);
    sums_.sector[k] += w;
    const std::size_t kc = std::size_t(k) * coarse_bins_ + std::size_t(coarse_of_[std::size_t(b)]);
    sums_.sector_w[kc] += w;
    sums_.sector_w_over_lag[kc] += w * inv_lag;
    if (with_map_) map_[bin] += w;
  }

 private:
  const SectorIndex& sectors_;
  PairSums& sums_;
  std::vector<double>& map_;
  double inv_bin_, inv_h_, half_;
  int last_bin_, side_;
  std::vector<int> coarse_of_;
  std::size_t coarse_bins_;
  bool with_map_;
};

}  // namespace granflow::correlation
