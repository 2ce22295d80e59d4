#pragma once
// The sector of a lag's angle, shared by the exact pair sums (force_correlation.cpp) and
// the FFT map (fft_correlation.cpp), so that both put a lag in the same sector.
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

}  // namespace granflow::correlation
