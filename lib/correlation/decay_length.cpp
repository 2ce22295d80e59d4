#include "correlation/decay_length.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "statistics/jackknife.hpp"

namespace granflow::correlation {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Σw (moment) or Σw/ℓ (integral) per coarse bin, divided by the normalisation of the
// profile: 2πW for the angle average, 2Δθ·W for a sector (C averaged over the sector).
std::vector<double> coarse_sums(const PairSums& sums, const LagGrid& grid, int sector, bool moment) {
  const int nc = grid.coarse_bins();
  std::vector<double> out(std::size_t(nc), 0.0);
  if (!(sums.norm > 0)) return std::vector<double>(out.size(), kNaN);
  if (sector < 0) {
    const std::vector<double>& fine = moment ? sums.w : sums.w_over_lag;
    for (int b = 0; b < grid.radial_bins; ++b) out[std::size_t(b / grid.coarse)] += fine[std::size_t(b)];
    for (double& x : out) x /= 2 * M_PI * sums.norm;
  } else {
    const std::vector<double>& by_sector = moment ? sums.sector_w : sums.sector_w_over_lag;
    for (int c = 0; c < nc; ++c)
      out[std::size_t(c)] =
          by_sector[std::size_t(sector) * std::size_t(nc) + std::size_t(c)] / (2 * grid.sector_width() * sums.norm);
  }
  return out;
}

// Every profile's I_c, isotropic first, then sector by sector: the quantities whose
// jackknife errors set the noise floors.
std::vector<double> all_integrals(const PairSums& sums, const LagGrid& grid) {
  std::vector<double> all = bin_integrals(sums, grid);
  for (int k = 0; k < grid.angle_bins; ++k) {
    const std::vector<double> s = bin_integrals(sums, grid, k);
    all.insert(all.end(), s.begin(), s.end());
  }
  return all;
}

}  // namespace

std::vector<double> bin_integrals(const PairSums& sums, const LagGrid& grid, int sector) {
  return coarse_sums(sums, grid, sector, false);
}

std::vector<double> bin_moments(const PairSums& sums, const LagGrid& grid, int sector) {
  return coarse_sums(sums, grid, sector, true);
}

DecayLength decay_length(const std::vector<double>& integral, const std::vector<double>& moment,
                         const std::vector<double>& floor, const LagGrid& grid, double tail_from, bool hard) {
  double num = 0, den = 0, tail = 0;
  const double outer = tail_from * grid.max_lag();
  for (std::size_t c = 0; c < integral.size(); ++c) {
    const double lo = grid.coarse_lower(int(c)), hi = grid.coarse_upper(int(c));
    const double cut = std::isfinite(floor[c]) ? floor[c] : 0.0;
    if (!std::isfinite(integral[c]) || !std::isfinite(moment[c])) return {kNaN, kNaN};
    const double a = hard ? (std::fabs(integral[c]) > cut ? std::fabs(integral[c]) : 0.0)
                          : std::max(std::fabs(integral[c]) - cut, 0.0);
    if (a == 0) continue;
    // I_c ≠ 0 here; the C-weighted mean lag in the bin, which only a sign change inside the
    // bin can move outside it.
    const double lag = std::clamp(moment[c] / integral[c], lo, hi);
    num += lag * a;
    den += a;
    if (0.5 * (lo + hi) > outer) tail += lag * a;
  }
  if (!(den > 0)) return {kNaN, kNaN};
  return {num / den, tail / num};
}

MagnitudeLength magnitude_length(const std::vector<PairSums>& blocks, const LagGrid& grid,
                                 const MagnitudeSettings& settings) {
  PairSums total(grid);
  for (const PairSums& b : blocks) total += b;
  const std::size_t nc = std::size_t(grid.coarse_bins()), nk = std::size_t(grid.angle_bins);

  // Noise floors k·δI from the full-sample jackknife, fixed for every replicate below.
  std::vector<double> floors = jackknife_errors(blocks, [&](const PairSums& s) { return all_integrals(s, grid); });
  for (double& f : floors) f = std::isfinite(f) ? settings.noise * f : 0.0;
  auto floor_of = [&](std::size_t profile) {  // 0: isotropic, 1 + k: sector k
    return std::vector<double>(floors.begin() + std::ptrdiff_t(profile * nc),
                               floors.begin() + std::ptrdiff_t((profile + 1) * nc));
  };
  const std::vector<double> iso_floor = floor_of(0);
  std::vector<std::vector<double>> sector_floor;
  for (std::size_t k = 0; k < nk; ++k) sector_floor.push_back(floor_of(1 + k));

  // [ξ_|C|, T, ξ_|C|(θ_0), …, ξ_|C|(θ_{K−1})] of a sum of blocks.
  auto estimate = [&](const PairSums& s) {
    const DecayLength iso =
        decay_length(bin_integrals(s, grid), bin_moments(s, grid), iso_floor, grid, settings.tail_from, settings.hard);
    std::vector<double> out{iso.xi, iso.tail_share};
    for (std::size_t k = 0; k < nk; ++k)
      out.push_back(decay_length(bin_integrals(s, grid, int(k)), bin_moments(s, grid, int(k)), sector_floor[k], grid,
                                 settings.tail_from, settings.hard)
                        .xi);
    return out;
  };
  const std::vector<double> value = estimate(total);
  const std::vector<double> error = jackknife_errors(blocks, estimate);

  MagnitudeLength m;
  m.xi = value[0];
  m.xi_error = error[0];
  m.tail_share = value[1];
  m.tail_share_error = error[1];
  m.measurable = std::isfinite(m.xi) && m.tail_share <= settings.max_tail_share;
  m.xi_theta.assign(value.begin() + 2, value.end());
  m.xi_theta_error.assign(error.begin() + 2, error.end());
  return m;
}

}  // namespace granflow::correlation
