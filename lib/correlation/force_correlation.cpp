#include "correlation/force_correlation.hpp"
#include "core/format.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numeric>
#include <string>

#include "core/error.hpp"
#include "correlation/sector_index.hpp"

namespace granflow::correlation {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Every pair of points closer than a cutoff in a Lees–Edwards box, each visited once with
// its minimum-image separation, without any per-pair rounding (which, as a libm call, would
// cost more than all the rest). The images of the box form the lattice spanned by
// a1 = (Lx, 0) and a2 = (s, Ly), s = δ reduced into [−Lx/2, Lx/2]; in the sheared
// coordinates (u, v) of that basis the lattice is Z², so cells of equal size in (u, v) —
// parallelograms in space — tile it, and a cell at a given offset from another is one exact
// lattice shift away. The offsets whose cells can hold a pair within the cutoff (exact
// parallelogram distance) form a stencil shared by all cells; half of it, plus pairs within
// a cell, visits each pair once. Two images of one pair cannot both lie within a cutoff
// ≤ min(Lx, Ly)/2, since every lattice vector is at least min(Lx, Ly) long.
class LagPairs {
 public:
  LagPairs(const std::vector<Vec2>& position, const Box& box, double cutoff) : cutoff2_(cutoff * cutoff) {
    const double s = box.offset - box.lx * std::round(box.offset / box.lx);
    a1_ = Vec2(box.lx, 0);
    a2_ = Vec2(s, box.ly);
    // About five cells per cutoff: smaller cells waste less area around the disc, but
    // each cell pair costs a little.
    nu_ = std::max(1, int(5 * box.lx / cutoff));
    nv_ = std::max(1, int(5 * box.ly / cutoff));
    const std::size_t n = position.size();
    std::vector<int> cell(n);
    std::vector<Vec2> representative(n);
    start_.assign(std::size_t(nu_) * nv_ + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
      const double v = position[i].y() / box.ly;
      double u = (position[i].x() - v * s) / box.lx;
      u -= std::floor(u);
      const int cu = std::min(int(u * nu_), nu_ - 1), cv = std::clamp(int(v * nv_), 0, nv_ - 1);
      representative[i] = u * a1_ + v * a2_;
      cell[i] = cv * nu_ + cu;
      ++start_[cell[i] + 1];
    }
    for (std::size_t c = 0; c + 1 < start_.size(); ++c) start_[c + 1] += start_[c];
    std::vector<int> fill(start_.begin(), start_.end() - 1);
    order_.resize(n);
    x_.resize(n);
    y_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const int at = fill[cell[i]]++;
      order_[at] = int(i);
      x_[at] = representative[i].x();
      y_[at] = representative[i].y();
    }
    build_stencil(cutoff);
  }

  // Grain indices in the order the visitor numbers them.
  const std::vector<int>& order() const { return order_; }

  // f(p, q, dx, dy) for every pair with |d| < cutoff, d = r_i − r_j (minimum image) for
  // the grains i = order()[p], j = order()[q].
  template <class F>
  void for_each(F&& f) const {
    for (int cv = 0; cv < nv_; ++cv)
      for (int cu = 0; cu < nu_; ++cu) {
        const int a = cv * nu_ + cu;
        for (int p = start_[a]; p < start_[a + 1]; ++p)
          for (int q = p + 1; q < start_[a + 1]; ++q) {
            const double dx = x_[p] - x_[q], dy = y_[p] - y_[q];
            if (dx * dx + dy * dy < cutoff2_) f(p, q, dx, dy);
          }
        for (const Offset& o : stencil_) {
          const int tu = cu + o.du, tv = cv + o.dv;
          const int ku = floor_div(tu, nu_), kv = floor_div(tv, nv_);
          const int b = (tv - kv * nv_) * nu_ + (tu - ku * nu_);
          // The partner cell's grains seen at their image r_j + ku·a1 + kv·a2.
          const double sx = ku * a1_.x() + kv * a2_.x(), sy = kv * a2_.y();
          for (int p = start_[a]; p < start_[a + 1]; ++p)
            for (int q = start_[b]; q < start_[b + 1]; ++q) {
              const double dx = x_[p] - x_[q] - sx, dy = y_[p] - y_[q] - sy;
              // Testing only where needed saves a mispredicted branch per pair.
              if (o.inside || dx * dx + dy * dy < cutoff2_) f(p, q, dx, dy);
            }
        }
      }
  }

 private:
  struct Offset {
    int du, dv;
    bool inside;  // every pair of the two cells is within the cutoff
  };

  static int floor_div(int a, int n) { return a >= 0 ? a / n : -((n - 1 - a) / n); }

  // Offsets (du, dv) with dv > 0, or dv = 0 and du > 0, whose cells can hold points closer
  // than the cutoff: the separations of two points of cells at offset o fill the
  // parallelogram D(o) + {x e1 + y e2 : |x|, |y| ≤ 1}, e1 = a1/nu, e2 = a2/nv.
  void build_stencil(double cutoff) {
    const Vec2 e1 = a1_ / nu_, e2 = a2_ / nv_;
    const int reach_v = int(std::ceil(cutoff / e2.y())) + 1;
    const int reach_u = int(std::ceil((cutoff + (reach_v + 1) * std::fabs(e2.x())) / e1.x())) + 2;
    for (int dv = 0; dv <= reach_v; ++dv)
      for (int du = -reach_u; du <= reach_u; ++du) {
        if (dv == 0 && du <= 0) continue;
        const Vec2 c = du * e1 + dv * e2;
        if (distance_to_parallelogram(c, e1, e2) >= cutoff) continue;
        const double farthest =
            std::max({(c + e1 + e2).norm(), (c + e1 - e2).norm(), (c - e1 + e2).norm(), (c - e1 - e2).norm()});
        stencil_.push_back({du, dv, farthest < cutoff * (1 - 1e-12)});  // margin for round-off
      }
  }

  // Distance from the origin to {c + x e1 + y e2 : |x|, |y| ≤ 1}.
  static double distance_to_parallelogram(const Vec2& c, const Vec2& e1, const Vec2& e2) {
    // Coordinates of −c in the basis (e1, e2): inside when both are within [−1, 1].
    const double det = cross(e1, e2), x = -cross(c, e2) / det, y = -cross(e1, c) / det;
    if (std::fabs(x) <= 1 && std::fabs(y) <= 1) return 0;
    auto segment = [&](const Vec2& from, const Vec2& along) {  // distance to from + t·along, t ∈ [0, 1]
      const double t = std::clamp(-from.dot(along) / along.squaredNorm(), 0.0, 1.0);
      return (from + t * along).norm();
    };
    const Vec2 corner = c - e1 - e2;
    return std::min({segment(corner, 2 * e1), segment(corner, 2 * e2), segment(c + e1 + e2, -2 * e1),
                     segment(c + e1 + e2, -2 * e2)});
  }

  double cutoff2_;
  Vec2 a1_, a2_;
  int nu_ = 1, nv_ = 1;
  std::vector<int> start_, order_;
  std::vector<double> x_, y_;
  std::vector<Offset> stencil_;
};

}  // namespace

LagGrid LagGrid::make(double bin_width, double max_lag, int angle_bins, double map_bin, int coarse) {
  if (!(bin_width > 0)) throw UsageError("option --bin-width: must be > 0");
  if (!(max_lag >= bin_width)) throw UsageError("option --max-lag: must be at least one --bin-width");
  // ≥ 3: eq. 5.3 has two parameters; ≤ 3600: the sector table grows as K².
  if (angle_bins < 3 || angle_bins > 3600) throw UsageError("option --angle-bins: must be in [3, 3600]");
  if (!(map_bin > 0)) throw UsageError("option --map-bin: must be > 0");
  if (coarse < 1) throw UsageError("option --abs-bin-width: must be a positive multiple of --bin-width");
  // Counts in double first: a tiny width must be refused, not overflow an int.
  const double radial = std::floor(max_lag / bin_width + 1e-9);
  if (radial > kMaxRadialBins)
    throw UsageError("option --bin-width: " + format_number(bin_width) + " gives " + format_number(radial) +
                     " radial bins up to --max-lag " + format_number(max_lag) + "; use at most " +
                     format_number(kMaxRadialBins));
  const double coarse_bins = std::ceil(radial / coarse);
  if (angle_bins * coarse_bins > kMaxSectorBins)
    throw UsageError("option --abs-bin-width: " + format_number(coarse * bin_width) + " gives " +
                     format_number(coarse_bins) + " coarse bins in each of the " + std::to_string(angle_bins) +
                     " --angle-bins, " + format_number(angle_bins * coarse_bins) + " in all; use at most " +
                     format_number(kMaxSectorBins));
  const double map_half = std::ceil(radial * bin_width / map_bin - 1e-9);
  if (2 * map_half > kMaxMapSide)
    throw UsageError("option --map-bin: " + format_number(map_bin) + " gives a map of " + format_number(2 * map_half) +
                     "² bins for --max-lag " + format_number(radial * bin_width) + "; use at most " +
                     format_number(kMaxMapSide) + " bins per axis");
  LagGrid g;
  g.coarse = coarse;
  g.bin_width = bin_width;
  g.radial_bins = int(radial);
  g.angle_bins = angle_bins;
  g.map_bin = map_bin;
  g.map_half = int(map_half);
  return g;
}

double LagGrid::sector_width() const { return M_PI / angle_bins; }

LoadedGrains loaded_grains(const io::Frame& frame) {
  const std::size_t n = frame.position.size();
  const io::ContactRecords& c = frame.contacts;
  std::vector<Vec2> force(n, Vec2::Zero());
  std::vector<char> touched(n, 0);
  for (std::size_t k = 0; k < c.size(); ++k) {
    const auto [i, j] = c.pair[k];
    if (i < 0 || j < 0 || std::size_t(i) >= n || std::size_t(j) >= n || i == j)
      throw UsageError("/contacts/pair: contact " + std::to_string(k) + " joins grains (" + std::to_string(i) + ", " +
                       std::to_string(j) + "), not two distinct grains of " + std::to_string(n));
    const double length = c.branch[k].norm();
    if (!(length > 0) || !std::isfinite(length))
      throw UsageError("/contacts/branch: contact " + std::to_string(k) + " has a zero or non-finite branch vector");
    const Vec2 normal = c.branch[k] / length;
    const Vec2 f = c.normal_force[k] * normal + c.tangential_force[k] * perp(normal);
    force[i] += f;
    force[j] -= f;
    touched[i] = touched[j] = 1;
  }
  LoadedGrains g;
  g.box = frame.box;
  for (std::size_t i = 0; i < n; ++i) {
    if (!touched[i]) continue;
    Vec2 r = frame.position[i], unused_velocity = Vec2::Zero();
    g.box.wrap(r, unused_velocity, 0);
    g.position.push_back(r);
    g.force.push_back(force[i]);
  }
  return g;
}

PairSums::PairSums(const LagGrid& grid)
    : w(grid.radial_bins, 0.0), w_over_lag(grid.radial_bins, 0.0), w_times_lag(grid.radial_bins, 0.0),
      sector(grid.angle_bins, 0.0), sector_w(std::size_t(grid.angle_bins) * std::size_t(grid.coarse_bins()), 0.0),
      sector_w_over_lag(sector_w.size(), 0.0) {}

PairSums& PairSums::operator+=(const PairSums& other) {
  norm += other.norm;
  for (std::size_t b = 0; b < w.size(); ++b) {
    w[b] += other.w[b];
    w_over_lag[b] += other.w_over_lag[b];
    w_times_lag[b] += other.w_times_lag[b];
  }
  for (std::size_t k = 0; k < sector.size(); ++k) sector[k] += other.sector[k];
  for (std::size_t k = 0; k < sector_w.size(); ++k) {
    sector_w[k] += other.sector_w[k];
    sector_w_over_lag[k] += other.sector_w_over_lag[k];
  }
  return *this;
}

Correlator::Correlator(const LagGrid& grid) : grid_(grid), sectors_(std::make_unique<const SectorIndex>(grid)) {}
Correlator::~Correlator() = default;
Correlator::Correlator(Correlator&&) noexcept = default;
Correlator& Correlator::operator=(Correlator&&) noexcept = default;

void Correlator::accumulate(const LoadedGrains& grains, PairSums& sums, std::vector<double>& map) const {
  for (const Vec2& f : grains.force) sums.norm += f.squaredNorm();
  if (grains.position.size() < 2) return;
  const LagGrid& grid = grid_;
  const SectorIndex& sectors = *sectors_;
  const LagPairs pairs(grains.position, grains.box, grid.max_lag());
  std::vector<Vec2> force;  // in the visitor's order, so that a cell's forces are adjacent
  for (int i : pairs.order()) force.push_back(grains.force[i]);
  LagBinner binner(grid, sectors, sums, map);
  pairs.for_each([&](int p, int q, double dx, double dy) {
    const double lag2 = dx * dx + dy * dy;
    if (lag2 == 0) return;  // coincident centres have no direction (and no physical meaning)
    binner.add(dx, dy, lag2, force[p].dot(force[q]));
  });
}

std::vector<double> isotropic_correlation(const PairSums& sums, const LagGrid& grid) {
  std::vector<double> c(sums.w.size(), kNaN);
  if (!(sums.norm > 0)) return c;
  const double d = grid.bin_width;
  for (std::size_t b = 0; b < c.size(); ++b)
    c[b] = sums.w[b] / (sums.norm * M_PI * d * d * double(2 * b + 1));  // annulus π((b+1)² − b²)Δ²
  return c;
}

namespace {

// The per-bin sums of ∫dℓ ℓC and ∫dℓ C (each up to the factor 1/(2πW) of the area reading,
// 1/W of the length reading): (Σw, Σw/ℓ) for C̄ per area, (Σwℓ, Σw) for C_L per length.
struct Moments {
  const std::vector<double>& numerator;
  const std::vector<double>& denominator;
};
Moments moments(const PairSums& sums, Density density) {
  return density == Density::area ? Moments{sums.w, sums.w_over_lag} : Moments{sums.w_times_lag, sums.w};
}

}  // namespace

double correlation_length(const PairSums& sums, Density density) {
  const Moments m = moments(sums, density);
  const double num = std::accumulate(m.numerator.begin(), m.numerator.end(), 0.0);
  const double den = std::accumulate(m.denominator.begin(), m.denominator.end(), 0.0);
  return den != 0 ? num / den : kNaN;
}

std::vector<double> truncated_correlation_length(const PairSums& sums, Density density) {
  const Moments m = moments(sums, density);
  std::vector<double> xi(sums.w.size());
  double num = 0, den = 0;
  for (std::size_t b = 0; b < xi.size(); ++b) {
    num += m.numerator[b];
    den += m.denominator[b];
    xi[b] = den != 0 ? num / den : kNaN;
  }
  return xi;
}

std::vector<double> angular_correlation_length(const PairSums& sums, const LagGrid& grid) {
  const double den = std::accumulate(sums.w_over_lag.begin(), sums.w_over_lag.end(), 0.0);
  std::vector<double> xi(sums.sector.size(), kNaN);
  if (den == 0) return xi;
  for (std::size_t k = 0; k < xi.size(); ++k) xi[k] = sums.sector[k] / (2 * grid.sector_width() * den);
  return xi;
}

std::vector<double> direction_correlation_length(const PairSums& sums, const LagGrid& grid) {
  const std::size_t coarse = std::size_t(grid.coarse_bins());
  std::vector<double> xi(sums.sector.size(), kNaN);
  for (std::size_t k = 0; k < xi.size(); ++k) {
    double num = 0, den = 0;
    for (std::size_t c = k * coarse; c < (k + 1) * coarse; ++c) {
      num += sums.sector_w[c];
      den += sums.sector_w_over_lag[c];
    }
    if (den == 0) continue;
    const double ratio = num / den;
    if (ratio > 0 && ratio <= grid.max_lag()) xi[k] = ratio;
  }
  return xi;
}

std::vector<double> correlation_map(const std::vector<double>& map, double norm, const LagGrid& grid) {
  const int side = grid.map_side(), half = grid.map_half;
  const double h = grid.map_bin, scale = norm > 0 ? 1 / (norm * h * h) : kNaN;
  // Farthest |coordinate| of bin k along an axis.
  auto reach = [&](int k) { return h * std::max(std::abs(k - half), std::abs(k + 1 - half)); };
  std::vector<double> c(map.size());
  for (int iy = 0; iy < side; ++iy)
    for (int ix = 0; ix < side; ++ix) {
      // Each pair was binned at r_ij for one of its two orders: half of it belongs at −r_ij,
      // the mirror bin (bins are symmetric about the origin).
      const double both = 0.5 * (map[iy * side + ix] + map[(side - 1 - iy) * side + (side - 1 - ix)]);
      c[iy * side + ix] = std::hypot(reach(ix), reach(iy)) <= grid.max_lag() ? both * scale : kNaN;
    }
  return c;
}

std::vector<double> radial_centres(const LagGrid& grid) {
  std::vector<double> r(grid.radial_bins);
  for (int b = 0; b < grid.radial_bins; ++b) r[b] = (b + 0.5) * grid.bin_width;
  return r;
}

std::vector<double> sector_centres(const LagGrid& grid) {
  std::vector<double> t(grid.angle_bins);
  for (int k = 0; k < grid.angle_bins; ++k) t[k] = (k + 0.5) * grid.sector_width();
  return t;
}

std::vector<double> map_centres(const LagGrid& grid) {
  std::vector<double> x(grid.map_side());
  for (int k = 0; k < grid.map_side(); ++k) x[k] = (k - grid.map_half + 0.5) * grid.map_bin;
  return x;
}

}  // namespace granflow::correlation
