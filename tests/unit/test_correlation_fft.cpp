// The FFT pair sums (lib/correlation/fft_correlation): known answers on constructed
// inputs (one pair across the sheared boundary, a sheared lattice), exact agreement with
// the exact pair sums of the grains moved to their cell centres, agreement within the
// binning on a 10⁴-grain frame (map, C̄, ξ and ξ_|C| within their errors), translation
// invariance and bitwise determinism.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <numeric>

#include "core/error.hpp"
#include "core/random.hpp"
#include "correlation/decay_length.hpp"
#include "correlation/fft_correlation.hpp"
#include "statistics/jackknife.hpp"

using namespace granflow;
using namespace granflow::correlation;

namespace {

LoadedGrains grains_of(const Box& box, std::vector<Vec2> position, std::vector<Vec2> force) {
  LoadedGrains g;
  g.box = box;
  for (Vec2& r : position) {
    Vec2 v = Vec2::Zero();
    box.wrap(r, v, 0);
  }
  g.position = std::move(position);
  g.force = std::move(force);
  return g;
}

// r = u·(Lx, 0) + v·(s, Ly) at the centre of cell (c1, c2) of an m1 × m2 grid.
Vec2 cell_centre(const Box& box, int m1, int m2, int c1, int c2) {
  const double s = box.offset - box.lx * std::round(box.offset / box.lx);
  const double u = (c1 + 0.5) / m1, v = (c2 + 0.5) / m2;
  return Vec2(u * box.lx + v * s, v * box.ly);
}

struct Result {
  PairSums sums;
  std::vector<double> map;
};

Result by_pairs(const LagGrid& grid, const LoadedGrains& g) {
  Result r{PairSums(grid), std::vector<double>(std::size_t(grid.map_side()) * grid.map_side(), 0.0)};
  Correlator(grid).accumulate(g, r.sums, r.map);
  return r;
}

Result by_fft(const LagGrid& grid, double cell, const LoadedGrains& g) {
  Result r{PairSums(grid), std::vector<double>(std::size_t(grid.map_side()) * grid.map_side(), 0.0)};
  FftCorrelator(grid, cell).accumulate(g, r.sums, r.map);
  return r;
}

double max_abs_difference(const std::vector<double>& a, const std::vector<double>& b) {
  EXPECT_EQ(a.size(), b.size());
  double d = 0;
  for (std::size_t k = 0; k < a.size(); ++k) d = std::max(d, std::fabs(a[k] - b[k]));
  return d;
}

// Every sum of a and b equal within tol (absolute); the map too, except its two rows on
// either side of ℓ_y = 0: lags exactly on that bin edge land in the row the pair sums'
// order of the pair picks (half of the pair is then mirrored into the other row), so only
// the two rows' total is comparable there.
void expect_same(const Result& a, const Result& b, const LagGrid& grid, double tol) {
  EXPECT_NEAR(a.sums.norm, b.sums.norm, tol);
  EXPECT_LE(max_abs_difference(a.sums.w, b.sums.w), tol);
  EXPECT_LE(max_abs_difference(a.sums.w_over_lag, b.sums.w_over_lag), tol);
  EXPECT_LE(max_abs_difference(a.sums.sector, b.sums.sector), tol);
  EXPECT_LE(max_abs_difference(a.sums.sector_w, b.sums.sector_w), tol);
  EXPECT_LE(max_abs_difference(a.sums.sector_w_over_lag, b.sums.sector_w_over_lag), tol);
  const std::vector<double> ca = correlation_map(a.map, a.sums.norm, grid),
                            cb = correlation_map(b.map, b.sums.norm, grid);
  const int side = grid.map_side(), half = grid.map_half;
  double axis_a = 0, axis_b = 0, worst = 0;
  for (int iy = 0; iy < side; ++iy)
    for (int ix = 0; ix < side; ++ix) {
      const std::size_t k = std::size_t(iy) * side + ix;
      if (std::isnan(ca[k]) || std::isnan(cb[k])) {
        EXPECT_EQ(std::isnan(ca[k]), std::isnan(cb[k]));
        continue;
      }
      if (iy == half || iy == half - 1) {
        axis_a += ca[k];
        axis_b += cb[k];
      } else {
        worst = std::max(worst, std::fabs(ca[k] - cb[k]));
      }
    }
  const double scale = a.sums.norm * grid.map_bin * grid.map_bin;  // map values are sums / (W h²)
  EXPECT_LE(worst * scale, tol);
  EXPECT_NEAR(axis_a * scale, axis_b * scale, tol);
}

// A jittered triangular-ish lattice of about n grains (σ = 1.4) at ν ≈ 0.8 in a square
// Lees–Edwards box with the given offset, and F^i = Σ_c g_c exp(−|r_i − R_c|²/2λ²), a
// smooth random field (random vector amplitudes g_c at random centres R_c, minimum image),
// whose correlation decays over ≈ 2λ.
LoadedGrains correlated_frame(int n, double offset_fraction, double lambda, std::uint64_t seed) {
  constexpr double kSigma = 1.4;
  Rng rng(seed);
  const int side = int(std::round(std::sqrt(double(n))));
  const double l = std::sqrt(side * side * M_PI * 0.25 * kSigma * kSigma / 0.8), a = l / side;
  const Box box{l, l, true, offset_fraction * l};
  std::vector<Vec2> position;
  for (int iy = 0; iy < side; ++iy)
    for (int ix = 0; ix < side; ++ix)
      position.emplace_back((ix + 0.5 * (iy % 2) + 0.1 * rng.uniform(-1, 1)) * a, (iy + 0.1 * rng.uniform(-1, 1)) * a);
  const int centres = int(l * l / (16 * lambda * lambda));
  std::vector<Vec2> centre, amplitude;
  for (int c = 0; c < centres; ++c) {
    centre.emplace_back(rng.uniform(0, l), rng.uniform(0, l));
    amplitude.emplace_back(rng.normal(), rng.normal());
  }
  std::vector<Vec2> force(position.size(), Vec2::Zero());
  const double reach2 = 25 * lambda * lambda;
  for (std::size_t i = 0; i < position.size(); ++i)
    for (int c = 0; c < centres; ++c) {
      const double d2 = box.minimum_image(position[i] - centre[c]).squaredNorm();
      if (d2 < reach2) force[i] += amplitude[c] * std::exp(-d2 / (2 * lambda * lambda));
    }
  return grains_of(box, position, force);
}

}  // namespace

// One pair of grains on cell centres on either side of the sheared boundary: all of
// F^A·F^B at the hand-computed minimum image ℓ = r_A − (r_B + (s, Ly)), in the radial bin,
// sector and map bins of ±ℓ. A wrong sign of the offset puts it at ℓ_x = −0.658 instead of
// −1.342; a transposed grid (m1 ≠ m2, Lx ≠ Ly) elsewhere; a wrong normalisation off 1.
TEST(FftCorrelation, OnePairAcrossTheShearedBoundary) {
  const Box box{20, 16, true, 7.3};
  const LagGrid grid = LagGrid::make(0.05, 5, 24, 0.2);
  const double cell = 0.25;
  const FftShape shape = fft_shape(box, cell);
  ASSERT_EQ(shape.m1, 80);
  ASSERT_EQ(shape.m2, 64);
  const Vec2 a = cell_centre(box, 80, 64, 10, 62), b = cell_centre(box, 80, 64, 14, 1);
  const LoadedGrains g = grains_of(box, {a, b}, {Vec2(1, 2), Vec2(3, -1)});  // w = 1, W = 15
  const Result r = by_fft(grid, cell, g);
  // Δu = −4/80, Δv = 61/64 − 1 = −3/64: ℓ = −(4/80)·(20, 0) − (3/64)·(7.3, 16).
  const Vec2 lag(-1 - 3.0 / 64 * 7.3, -0.75);
  EXPECT_NEAR(lag.x(), -1.3421875, 1e-15);
  EXPECT_DOUBLE_EQ(r.sums.norm, 15);
  const int bin = int(lag.norm() / grid.bin_width);
  for (int k = 0; k < grid.radial_bins; ++k) {
    EXPECT_NEAR(r.sums.w[k], k == bin ? 1 : 0, 1e-12) << k;
    EXPECT_NEAR(r.sums.w_over_lag[k], k == bin ? 1 / lag.norm() : 0, 1e-12) << k;
  }
  const double angle = std::atan2(lag.y(), lag.x()) + M_PI;  // mod π
  const int sector = int(angle / grid.sector_width());
  ASSERT_EQ(sector, 3);
  for (int k = 0; k < grid.angle_bins; ++k) EXPECT_NEAR(r.sums.sector[k], k == sector ? 1 : 0, 1e-12) << k;
  EXPECT_NEAR(correlation_length(r.sums), lag.norm(), 1e-12);
  const std::vector<double> c = correlation_map(r.map, r.sums.norm, grid);
  const int side = grid.map_side(), h = grid.map_half;
  auto map_bin = [&](const Vec2& l) {
    return std::size_t(int(std::floor(l.y() / grid.map_bin)) + h) * side +
           std::size_t(int(std::floor(l.x() / grid.map_bin)) + h);
  };
  const double expected = 0.5 * 1 / (15 * grid.map_bin * grid.map_bin);
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (std::isnan(c[k])) continue;
    EXPECT_NEAR(c[k], (k == map_bin(lag) || k == map_bin(-lag)) ? expected : 0, 1e-12) << k;
  }
  // The exact pair sums of the same two grains agree.
  expect_same(r, by_pairs(grid, g), grid, 1e-12);
}

// An 8 × 8 lattice in lattice coordinates of a sheared box: the oblique lattice spanned by
// e1 = a1/8 = (1.5, 0) and e2 = a2/8 = (0.5625, 1.5). With F^i = (1, 0), each of ±e1, ±e2,
// ±(e2 − e1) holds N = 64 pairs (w = 1 each), and the mirror lag (0.9375, 1.5) none: a
// wrong offset sign gives the mirror lattice, whose shells have the same lengths.
TEST(FftCorrelation, ShearedLatticeShells) {
  const Box box{12, 12, true, 4.5};
  const LagGrid grid = LagGrid::make(0.05, 5.9, 24, 0.2);
  std::vector<Vec2> position;
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 8; ++i) position.push_back(cell_centre(box, 48, 48, 6 * i, 6 * j));
  const LoadedGrains g = grains_of(box, position, std::vector<Vec2>(64, Vec2(1, 0)));
  const Result r = by_fft(grid, 0.25, g);
  const Vec2 e1(1.5, 0), e2(0.5625, 1.5);
  for (const Vec2& shell : {e1, e2, Vec2(e2 - e1)})
    EXPECT_NEAR(r.sums.w[std::size_t(shell.norm() / grid.bin_width)], 64, 1e-9) << shell.transpose();
  const std::vector<double> c = correlation_map(r.map, r.sums.norm, grid);
  const int side = grid.map_side(), h = grid.map_half;
  auto at = [&](const Vec2& l) {
    return c[std::size_t(int(std::floor(l.y() / grid.map_bin)) + h) * side +
             std::size_t(int(std::floor(l.x() / grid.map_bin)) + h)];
  };
  const double per_shell = 0.5 / (grid.map_bin * grid.map_bin);  // (N/2)/(W h²), W = N
  EXPECT_NEAR(at(e2 - e1), per_shell, 1e-9);
  EXPECT_NEAR(at(e1 - e2), per_shell, 1e-9);
  EXPECT_NEAR(at(e2), per_shell, 1e-9);
  EXPECT_NEAR(at(Vec2(0.9375, 1.5)), 0, 1e-9);
  EXPECT_NEAR(at(Vec2(-0.5625, 1.5)), 0, 1e-9);
}

// The FFT sums are the exact pair sums of the grains moved to their cell centres, to
// round-off: every radial, sector and map sum, in a sheared box with Lx ≠ Ly, m1 ≠ m2, and
// a cell size incommensurate with the bins (no lag on a bin edge except ℓ_y = 0).
TEST(FftCorrelation, EqualsPairSumsOfSnappedPositions) {
  Rng rng(7);
  // Lengths chosen so that no lattice lag but ℓ_y = 0 falls on a bin edge or sector boundary.
  const Box box{30.2917, 23.6843, true, 11.8731};
  std::vector<Vec2> position, force;
  for (int i = 0; i < 400; ++i) {
    position.emplace_back(rng.uniform(0, box.lx), rng.uniform(0, box.ly));
    force.emplace_back(rng.normal(), rng.normal());
  }
  const LoadedGrains g = grains_of(box, position, force);
  const LagGrid grid = LagGrid::make(0.07, 11.8, 24, 0.3, 3);
  const double cell = 0.37;
  const FftShape shape = fft_shape(box, cell);
  EXPECT_NE(shape.m1, shape.m2);
  const LoadedGrains snapped = grains_of(box, snapped_positions(g.position, box, shape), g.force);
  const Result fft = by_fft(grid, cell, g), exact = by_pairs(grid, snapped);
  const double w = fft.sums.norm;
  expect_same(fft, exact, grid, 1e-11 * w);
  // And they are not the sums of the original positions (the binning is there).
  EXPECT_GT(max_abs_difference(fft.sums.w, by_pairs(grid, g).sums.w), 1e-3 * w);
}

// A 10⁴-grain frame at ν ≈ 0.8 with a force field correlated over ≈ 2σ: (1) the FFT sums
// equal the exact sums of the snapped grains to round-off; (2) over 10 such frames (the
// blocks of the jackknife), the FFT and the exact pair sums of the real positions give the
// same C̄ on coarse bins and the same map within the binning error, and the same ξ
// (eq. 5.2) and ξ_|C| within their jackknife errors.
TEST(FftCorrelation, TenThousandGrainsAgreeWithPairSums) {
  constexpr double kSigma = 1.4;
  const double cell = kSigma / 20;  // gf-correlate's default
  const LagGrid grid = LagGrid::make(kSigma / 20, 10 * kSigma, 24, kSigma / 5, 5);
  std::vector<PairSums> exact_blocks, fft_blocks;
  std::vector<double> exact_map(std::size_t(grid.map_side()) * grid.map_side(), 0.0), fft_map = exact_map,
                                                                                      jittered_map = exact_map;
  PairSums jittered(grid);
  Rng rng(11);
  FftCorrelator fft(grid, cell);
  const Correlator pairs(grid);
  for (int frame = 0; frame < 10; ++frame) {
    const LoadedGrains g = correlated_frame(10000, 0.1 * frame + 0.0317, kSigma, 100 + frame);
    ASSERT_EQ(g.position.size(), 10000u);
    if (frame == 0) {
      const FftShape shape = fft_shape(g.box, cell);
      const LoadedGrains snapped = grains_of(g.box, snapped_positions(g.position, g.box, shape), g.force);
      expect_same(by_fft(grid, cell, g), by_pairs(grid, snapped), grid, 1e-10 * by_pairs(grid, g).sums.norm);
    }
    exact_blocks.emplace_back(grid);
    fft_blocks.emplace_back(grid);
    pairs.accumulate(g, exact_blocks.back(), exact_map);
    fft.accumulate(g, fft_blocks.back(), fft_map);
    // The scale of the binning error: the exact sums of the grains each moved at random by
    // as much as the binning moves them (up to half a cell along a1 and along a2).
    const FftShape shape = fft_shape(g.box, cell);
    const double s = g.box.offset - g.box.lx * std::round(g.box.offset / g.box.lx);
    std::vector<Vec2> moved;
    for (const Vec2& r : g.position) {
      const double du = rng.uniform(-0.5, 0.5) / shape.m1, dv = rng.uniform(-0.5, 0.5) / shape.m2;
      moved.push_back(r + Vec2(du * g.box.lx + dv * s, dv * g.box.ly));
    }
    pairs.accumulate(grains_of(g.box, moved, g.force), jittered, jittered_map);
  }
  PairSums exact_total(grid), fft_total(grid);
  for (int b = 0; b < 10; ++b) exact_total += exact_blocks[b], fft_total += fft_blocks[b];

  // C̄ integrated over coarse bins of σ/4, relative to its largest value.
  const std::vector<double> ie = bin_integrals(exact_total, grid), iff = bin_integrals(fft_total, grid);
  double peak = 0, worst = 0;
  for (std::size_t c = 0; c < ie.size(); ++c) peak = std::max(peak, std::fabs(ie[c]));
  for (std::size_t c = 0; c < ie.size(); ++c) worst = std::max(worst, std::fabs(ie[c] - iff[c]));
  std::printf("coarse-bin integrals of C: largest difference %.3g of the largest bin\n", worst / peak);
  EXPECT_LT(worst / peak, 0.03);

  // The map. Each of its bins (σ/5) sums the lag distribution at the 4 × 4 grid lags inside
  // it (cells of σ/20, here commensurate with the lattice: a = 20 cells), a poor quadrature
  // of the narrow neighbour shells beside moving each lag by less than a cell: the FFT map
  // differs from the exact one by
  // ≈ 13 % of its rms on its own bins, ≈ 9 % on bins merged 5 × 5, several times more than
  // the exact map of grains moved at random by as much (printed for comparison). A wrong
  // sign, transposition or normalisation gives differences of order 1.
  const std::vector<double> ce = correlation_map(exact_map, exact_total.norm, grid),
                            cf = correlation_map(fft_map, fft_total.norm, grid),
                            cj = correlation_map(jittered_map, jittered.norm, grid);
  auto rms_difference = [&](const std::vector<double>& other, int merge) {
    const int side = grid.map_side(), coarse_side = side / merge;
    double diff = 0, norm = 0;
    for (int by = 0; by < coarse_side; ++by)
      for (int bx = 0; bx < coarse_side; ++bx) {
        double e = 0, f = 0;
        bool inside = true;
        for (int iy = by * merge; iy < (by + 1) * merge; ++iy)
          for (int ix = bx * merge; ix < (bx + 1) * merge; ++ix) {
            const std::size_t k = std::size_t(iy) * side + ix;
            inside = inside && !std::isnan(ce[k]);
            e += ce[k];
            f += other[k];
          }
        if (!inside) continue;
        diff += (e - f) * (e - f);
        norm += e * e;
      }
    return std::sqrt(diff / norm);
  };
  const double fine = rms_difference(cf, 1), merged = rms_difference(cf, 5);
  const double fine_moved = rms_difference(cj, 1), merged_moved = rms_difference(cj, 5);
  std::printf(
      "map: rms difference from the exact map, relative to its rms: fft %.3g (bins merged 5 x 5: %.3g), "
      "grains moved at random %.3g (%.3g)\n",
      fine, merged, fine_moved, merged_moved);
  EXPECT_LT(fine, 0.2);
  EXPECT_LT(merged, 0.15);

  const double xi_exact = correlation_length(exact_total), xi_fft = correlation_length(fft_total);
  auto xi_error = [](const std::vector<PairSums>& blocks) {
    return jackknife_errors(blocks, [](const PairSums& s) { return std::vector<double>{correlation_length(s)}; })[0];
  };
  const double error_exact = xi_error(exact_blocks), error_fft = xi_error(fft_blocks);
  std::printf("xi: pairs %.5g +- %.2g, fft %.5g +- %.2g\n", xi_exact, error_exact, xi_fft, error_fft);
  EXPECT_LT(std::fabs(xi_exact - xi_fft), error_exact);
  const MagnitudeLength me = magnitude_length(exact_blocks, grid, {}), mf = magnitude_length(fft_blocks, grid, {});
  std::printf("xi_abs: pairs %.5g +- %.2g, fft %.5g +- %.2g\n", me.xi, me.xi_error, mf.xi, mf.xi_error);
  EXPECT_LT(std::fabs(me.xi - mf.xi), me.xi_error);
}

// Moving every grain by the same vector leaves C alone: exactly (round-off) for a shift by
// whole cells in lattice coordinates, through the sheared boundary; within the binning for
// an arbitrary shift.
TEST(FftCorrelation, TranslationInvariance) {
  constexpr double kSigma = 1.4;
  const LoadedGrains g = correlated_frame(2500, 0.3711, kSigma, 3);
  const LagGrid grid = LagGrid::make(kSigma / 20, 8 * kSigma, 24, kSigma / 5, 5);
  const double cell = kSigma / 10;
  const FftShape shape = fft_shape(g.box, cell);
  const Result base = by_fft(grid, cell, g);
  const double s = g.box.offset - g.box.lx * std::round(g.box.offset / g.box.lx);
  // 17 cells along a1 and 23 along a2 (plus a fraction of a cell that keeps every grain in
  // its cell's interior, so that the shift moves no grain across a cell edge by round-off).
  const double du = 17.0 / shape.m1, dv = 23.0 / shape.m2;
  const Vec2 whole(du * g.box.lx + dv * s, dv * g.box.ly);
  std::vector<Vec2> moved;
  const std::vector<Vec2> snapped = snapped_positions(g.position, g.box, shape);
  for (const Vec2& r : snapped) moved.push_back(r + whole);
  const Result centred = by_fft(grid, cell, grains_of(g.box, snapped, g.force));
  const Result shifted = by_fft(grid, cell, grains_of(g.box, moved, g.force));
  expect_same(centred, shifted, grid, 1e-10 * base.sums.norm);
  // Any shift: ξ within 2 % (the binning moves every lag by less than a cell).
  std::vector<Vec2> any;
  for (const Vec2& r : g.position) any.push_back(r + Vec2(3.217, 11.93));
  const Result other = by_fft(grid, cell, grains_of(g.box, any, g.force));
  const double xi = correlation_length(base.sums), xi_other = correlation_length(other.sums),
               xi_exact = correlation_length(by_pairs(grid, g).sums);
  std::printf("translation: xi %.5g, shifted %.5g, exact %.5g\n", xi, xi_other, xi_exact);
  EXPECT_NEAR(xi_other, xi, 0.02 * xi);
}

// Identical inputs give identical bits (FFTW_ESTIMATE plans, one thread), also through a
// correlator that has meanwhile planned another grid shape.
TEST(FftCorrelation, DeterministicBits) {
  const LoadedGrains g = correlated_frame(900, 0.21, 1.4, 5), other = correlated_frame(1600, 0.4, 1.4, 6);
  const LagGrid grid = LagGrid::make(0.07, 8, 12, 0.28, 4);
  const Result a = by_fft(grid, 0.14, g);
  FftCorrelator reused(grid, 0.14);
  Result b{PairSums(grid), std::vector<double>(a.map.size(), 0.0)}, scratch = b;
  reused.accumulate(other, scratch.sums, scratch.map);
  reused.accumulate(g, b.sums, b.map);
  EXPECT_EQ(std::memcmp(a.sums.w.data(), b.sums.w.data(), a.sums.w.size() * sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(a.sums.sector_w_over_lag.data(), b.sums.sector_w_over_lag.data(),
                        a.sums.sector_w_over_lag.size() * sizeof(double)),
            0);
  EXPECT_EQ(std::memcmp(a.map.data(), b.map.data(), a.map.size() * sizeof(double)), 0);
}

TEST(FftCorrelation, GridShapesAndBadSettings) {
  const Box box{20, 16, true, 3};
  const FftShape s = fft_shape(box, 0.3);  // 66.7 → 70, 53.3 → 54
  EXPECT_EQ(s.m1, 70);
  EXPECT_EQ(s.m2, 54);
  EXPECT_THROW(fft_shape(box, 0), UsageError);
  try {
    fft_shape(box, 1e-4);
    ADD_FAILURE() << "a grid of 3.2e10 cells was accepted";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("--fft-cell"), std::string::npos) << e.what();
  }
  FftCorrelator fft(LagGrid::make(0.1, 9, 12, 0.5), 0.5);  // ℓ_max 9 > 16/2
  PairSums sums(fft.grid());
  std::vector<double> map;
  EXPECT_THROW(fft.accumulate(grains_of(box, {Vec2(1, 1), Vec2(2, 2)}, {Vec2(1, 0), Vec2(0, 1)}), sums, map),
               UsageError);
}
