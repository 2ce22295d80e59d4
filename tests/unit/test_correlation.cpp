// The force correlation of eq. 5.1–5.3 (lib/correlation/force_correlation): constructed
// configurations with known answers, and the fast pair sums against a brute-force double
// loop over all pairs with the Lees–Edwards minimum image found by searching images.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "core/error.hpp"
#include "core/random.hpp"
#include "correlation/force_correlation.hpp"

using namespace granflow;
using namespace granflow::correlation;

namespace {

void add_contact(io::Frame& f, int i, int j, const Vec2& branch, double fn, double ft) {
  f.contacts.pair.push_back({i, j});
  f.contacts.branch.push_back(branch);
  f.contacts.normal_force.push_back(fn);
  f.contacts.tangential_force.push_back(ft);
  f.contacts.binary_force.push_back(0);
  f.contacts.pre_normal_velocity.push_back({0, 0});
  f.contacts.age.push_back(1);
}

// Shortest r_i − r_j among the images k_x·(Lx, 0) + k_y·(δ, Ly), |k| ≤ 3.
Vec2 brute_image(const Box& box, const Vec2& d) {
  Vec2 best(1e300, 1e300);
  for (int ky = -3; ky <= 3; ++ky)
    for (int kx = -3; kx <= 3; ++kx) {
      const Vec2 image = d - Vec2(kx * box.lx + ky * box.offset, ky * box.ly);
      if (image.squaredNorm() < best.squaredNorm()) best = image;
    }
  return best;
}

struct Reference {
  PairSums sums;
  std::vector<double> map;  // symmetrised density, as correlation_map gives it
};

// Eq. 5.1 by the book: forces summed over contacts, every pair i > j of grains with a
// contact, lags by image search, angles by atan2.
Reference brute_force(const io::Frame& f, const LagGrid& grid) {
  const std::size_t n = f.position.size();
  std::vector<Vec2> force(n, Vec2::Zero());
  std::vector<bool> loaded(n, false);
  for (std::size_t c = 0; c < f.contacts.size(); ++c) {
    const auto [i, j] = f.contacts.pair[c];
    const Vec2 normal = f.contacts.branch[c].normalized();
    const Vec2 tangent(-normal.y(), normal.x());
    const Vec2 fc = f.contacts.normal_force[c] * normal + f.contacts.tangential_force[c] * tangent;
    force[i] += fc;
    force[j] -= fc;
    loaded[i] = loaded[j] = true;
  }
  Reference ref{PairSums(grid), std::vector<double>(std::size_t(grid.map_side()) * grid.map_side(), 0.0)};
  const int side = grid.map_side();
  auto bin = [&](double x) { return int(std::floor(x / grid.map_bin)) + grid.map_half; };
  for (std::size_t i = 0; i < n; ++i) {
    if (!loaded[i]) continue;
    ref.sums.norm += force[i].squaredNorm();
    for (std::size_t j = 0; j < i; ++j) {
      if (!loaded[j]) continue;
      const Vec2 d = brute_image(f.box, f.position[i] - f.position[j]);
      const double lag = d.norm();
      if (lag >= grid.max_lag()) continue;
      const double w = force[i].dot(force[j]);
      const int b = int(lag / grid.bin_width);
      ref.sums.w[b] += w;
      ref.sums.w_over_lag[b] += w / lag;
      ref.sums.w_times_lag[b] += w * lag;
      double theta = std::atan2(d.y(), d.x());
      if (theta < 0) theta += M_PI;
      if (theta >= M_PI) theta -= M_PI;
      const int k = std::min(int(theta / grid.sector_width()), grid.angle_bins - 1);
      ref.sums.sector[k] += w;
      ref.sums.sector_w[std::size_t(k) * grid.coarse_bins() + b / grid.coarse] += w;
      ref.sums.sector_w_over_lag[std::size_t(k) * grid.coarse_bins() + b / grid.coarse] += w / lag;
      ref.map[bin(d.y()) * side + bin(d.x())] += 0.5 * w;
      ref.map[bin(-d.y()) * side + bin(-d.x())] += 0.5 * w;
    }
  }
  for (double& m : ref.map) m /= ref.sums.norm * grid.map_bin * grid.map_bin;
  return ref;
}

double max_abs(const std::vector<double>& v) {
  double m = 0;
  for (double x : v)
    if (std::isfinite(x)) m = std::max(m, std::fabs(x));
  return m;
}

void expect_close(const std::vector<double>& fast, const std::vector<double>& ref, double scale, const char* what) {
  ASSERT_EQ(fast.size(), ref.size()) << what;
  for (std::size_t k = 0; k < fast.size(); ++k) ASSERT_NEAR(fast[k], ref[k], 1e-10 * scale) << what << " bin " << k;
}

// Random grains in a Lees–Edwards box (positions partly outside the primary cell, as
// unwrapped input), contacts between pairs closer than 1.6 with random forces.
io::Frame random_frame(std::uint64_t seed, const Box& box, int n) {
  Rng rng(seed);
  io::Frame f;
  f.box = box;
  for (int i = 0; i < n; ++i)
    f.position.push_back(Vec2(rng.uniform(-0.3, 1.3) * box.lx, rng.uniform(-0.2, 1.2) * box.ly));
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      const Vec2 d = brute_image(box, f.position[i] - f.position[j]);
      if (d.norm() < 1.6 && rng.uniform() < 0.7) add_contact(f, i, j, d, rng.uniform(0, 2), rng.uniform(-0.5, 0.5));
    }
  return f;
}

}  // namespace

TEST(ForceCorrelation, PairSumsEqualBruteForceWithLeesEdwardsOffsets) {
  int compared = 0;
  for (double offset : {0.0, 7.3, 29.999})
    for (double max_lag : {11.9, 2.5}) {
      const Box box{30, 24, true, offset};
      const io::Frame f = random_frame(std::uint64_t(offset * 10 + max_lag), box, 260);
      const LagGrid grid = LagGrid::make(0.05, max_lag, 24, 0.4, 3);  // coarse bins: 3 radial bins each
      PairSums sums(grid);
      std::vector<double> map(std::size_t(grid.map_side()) * grid.map_side(), 0.0);
      Correlator(grid).accumulate(loaded_grains(f), sums, map);
      const Reference ref = brute_force(f, grid);
      ASSERT_GT(sums.norm, 0);
      EXPECT_NEAR(sums.norm, ref.sums.norm, 1e-12 * ref.sums.norm);
      const double scale = ref.sums.norm;
      expect_close(sums.w, ref.sums.w, scale, "sum w");
      expect_close(sums.w_over_lag, ref.sums.w_over_lag, scale, "sum w/l");
      expect_close(sums.w_times_lag, ref.sums.w_times_lag, scale * max_lag, "sum w l");
      expect_close(sums.sector, ref.sums.sector, scale, "sector");
      expect_close(sums.sector_w, ref.sums.sector_w, scale, "sector x coarse bin, w");
      expect_close(sums.sector_w_over_lag, ref.sums.sector_w_over_lag, scale, "sector x coarse bin, w/l");
      const std::vector<double> c = correlation_map(map, sums.norm, grid);
      for (std::size_t k = 0; k < c.size(); ++k)
        if (std::isfinite(c[k])) {
          ASSERT_NEAR(c[k], ref.map[k], 1e-10 * max_abs(ref.map)) << "map bin " << k;
          ++compared;
        }
      // Every pair closer than ℓ_max was found: the sums are not trivially empty.
      EXPECT_GT(std::count_if(sums.w.begin(), sums.w.end(), [](double x) { return x != 0; }), 20);
    }
  EXPECT_GT(compared, 1000);
}

TEST(ForceCorrelation, IsolatedBinaryContacts) {
  // Pairs far apart (> ℓ_max): each grain feels ±(F_n n̂ + F_t t̂), so w = −(F_n² + F_t²)
  // at the contact distance d and nothing else. Eq. 5.2 then gives exactly
  //   ξ = Σ w / Σ w/d = Σ (F_n² + F_t²) / Σ (F_n² + F_t²)/d,
  // the force²-weighted harmonic mean of the contact distances (the angle-averaged C̄
  // carries 1/(2πℓ), so ∫dℓ C̄ weighs each pair with 1/d and ∫dℓ ℓC̄ with 1).
  Rng rng(11);
  const Box box{300, 300, true, 123.4};
  const LagGrid grid = LagGrid::make(0.04, 10, 12, 0.5);
  io::Frame f;
  f.box = box;
  double sum_w2 = 0, sum_w2_over_d = 0, sum_w2_d = 0;
  std::vector<double> expected_w(grid.radial_bins, 0.0), expected_sector(grid.angle_bins, 0.0);
  for (int a = 0; a < 9; ++a)
    for (int b = 0; b < 9; ++b) {
      // The first pair straddles the bottom/top boundary and is wrapped by the correlator.
      const Vec2 centre = a + b == 0 ? Vec2(150, 0.1) : Vec2(15 + 33 * a, 15 + 33 * b);
      const double d = rng.uniform(1.0, 1.8), phi = rng.uniform(0, 2 * M_PI);
      const Vec2 branch = d * Vec2(std::cos(phi), std::sin(phi));
      const int i = int(f.position.size());
      f.position.push_back(centre + 0.5 * branch);
      f.position.push_back(centre - 0.5 * branch);
      const double fn = rng.uniform(0.5, 2), ft = rng.uniform(-0.3, 0.3), w2 = fn * fn + ft * ft;
      add_contact(f, i, i + 1, branch, fn, ft);
      sum_w2 += w2;
      sum_w2_over_d += w2 / d;
      sum_w2_d += w2 * d;
      expected_w[int(d / grid.bin_width)] -= w2;
      double theta = std::fmod(phi, M_PI);
      expected_sector[int(theta / grid.sector_width())] -= w2;
    }
  PairSums sums(grid);
  std::vector<double> map;
  Correlator(grid).accumulate(loaded_grains(f), sums, map);
  EXPECT_NEAR(sums.norm, 2 * sum_w2, 1e-12 * sum_w2);
  EXPECT_NEAR(correlation_length(sums), sum_w2 / sum_w2_over_d, 1e-12);
  // C per unit length weighs each pair with 1 in ∫dℓ C_L and with d in ∫dℓ ℓC_L: the
  // F²-weighted arithmetic mean of d, and ξ_length/ξ = ⟨d⟩·⟨1/d⟩ (weights F²), > 1 here.
  const double xi_area = correlation_length(sums, Density::area), xi_length = correlation_length(sums, Density::length);
  EXPECT_NEAR(xi_length, sum_w2_d / sum_w2, 1e-12);
  EXPECT_NEAR(xi_length / xi_area, sum_w2_d * sum_w2_over_d / (sum_w2 * sum_w2), 1e-12);
  EXPECT_GT(xi_length / xi_area, 1.001);
  EXPECT_NEAR(truncated_correlation_length(sums, Density::length).back(), xi_length, 1e-12);
  expect_close(sums.w, expected_w, sum_w2, "sum w");
  const std::vector<double> c = isotropic_correlation(sums, grid);
  for (int b = 0; b < grid.radial_bins; ++b) {
    const double annulus = M_PI * (std::pow((b + 1) * grid.bin_width, 2) - std::pow(b * grid.bin_width, 2));
    EXPECT_NEAR(c[b], expected_w[b] / (2 * sum_w2 * annulus), 1e-9) << b;
    if (b * grid.bin_width > 1.85 || (b + 1) * grid.bin_width < 0.99) {
      EXPECT_EQ(c[b], 0) << b;
    }
  }
  const std::vector<double> xi_theta = angular_correlation_length(sums, grid);
  double integral = 0;
  for (int k = 0; k < grid.angle_bins; ++k) {
    EXPECT_NEAR(xi_theta[k], expected_sector[k] / (2 * grid.sector_width() * -sum_w2_over_d), 1e-12) << k;
    integral += 2 * xi_theta[k] * grid.sector_width();  // over [0, 2π): twice [0, π)
  }
  EXPECT_NEAR(integral, correlation_length(sums), 1e-12);  // eq. 5.3's normalisation
}

TEST(ForceCorrelation, StraightChainAcrossTheShearedBoundary) {
  // n grains in a straight line, equal normal forces F between neighbours: interior grains
  // feel +F and −F (total 0), the two ends ∓F û. So W = 2F², the only correlated pair is
  // the two ends, w = −F² at ℓ = (n − 1)d, and ξ = (n − 1)d. The chains cross the top of
  // the cell, where the Lees–Edwards image is shifted by δ, or the side (along x).
  for (double angle_deg : {33.0, 95.0, 0.0}) {
    const Box box{40, 30, true, 5.5};
    const int n = 8;
    const double d = 1.33, force = 2.5, angle = angle_deg * M_PI / 180;  // (n − 1)d clear of bin edges
    const Vec2 u(std::cos(angle), std::sin(angle));
    io::Frame f;
    f.box = box;
    for (int k = 0; k < n; ++k) {
      Vec2 r = Vec2(angle_deg == 0 ? 35 : 20, 26) + k * d * u, v = Vec2::Zero();
      box.wrap(r, v, 0);
      f.position.push_back(r);
    }
    for (int k = 0; k + 1 < n; ++k) add_contact(f, k + 1, k, d * u, force, 0);
    const LagGrid grid = LagGrid::make(0.05, 12, 24, 0.5);
    PairSums sums(grid);
    std::vector<double> map(std::size_t(grid.map_side()) * grid.map_side(), 0.0);
    Correlator(grid).accumulate(loaded_grains(f), sums, map);
    EXPECT_NEAR(sums.norm, 2 * force * force, 1e-12) << angle_deg;
    EXPECT_NEAR(correlation_length(sums), (n - 1) * d, 1e-12) << angle_deg;
    // One correlated pair: every reading of eq. 5.2 is its distance.
    EXPECT_NEAR(correlation_length(sums, Density::length), (n - 1) * d, 1e-12) << angle_deg;
    const int end_bin = int((n - 1) * d / grid.bin_width);
    for (int b = 0; b < grid.radial_bins; ++b)
      EXPECT_NEAR(sums.w[b], b == end_bin ? -force * force : 0.0, 1e-12) << angle_deg << " bin " << b;
    // Sum rule: Σ_{i>j} F^i·F^j = −W/2 when every pair is within ℓ_max.
    EXPECT_NEAR(std::accumulate(sums.w.begin(), sums.w.end(), 0.0), -0.5 * sums.norm, 1e-12);
    const int sector = int(angle_deg / 7.5);  // sectors of 7.5°
    for (int k = 0; k < grid.angle_bins; ++k)
      EXPECT_NEAR(sums.sector[k], k == sector ? -force * force : 0.0, 1e-12) << angle_deg << " sector " << k;
  }
}

TEST(ForceCorrelation, SumRuleForACompactCluster) {
  // Contact forces are internal: Σ_i F^i = 0, so over all pairs Σ_{i>j} F^i·F^j = −W/2.
  Rng rng(5);
  io::Frame f;
  f.box = Box{50, 50, true, 17};
  for (int i = 0; i < 80; ++i) f.position.push_back(Vec2(rng.uniform(0, 6), rng.uniform(48, 54)));  // across the top
  for (int i = 0; i < 80; ++i)
    for (int j = 0; j < i; ++j)
      if ((f.position[i] - f.position[j]).norm() < 1.5)
        add_contact(f, i, j, f.position[i] - f.position[j], rng.uniform(0, 3), rng.uniform(-1, 1));
  const LagGrid grid = LagGrid::make(0.1, 20, 24, 1);
  PairSums sums(grid);
  std::vector<double> map;
  Correlator(grid).accumulate(loaded_grains(f), sums, map);
  EXPECT_NEAR(std::accumulate(sums.w.begin(), sums.w.end(), 0.0), -0.5 * sums.norm, 1e-10 * sums.norm);
  EXPECT_NEAR(std::accumulate(sums.sector.begin(), sums.sector.end(), 0.0), -0.5 * sums.norm, 1e-10 * sums.norm);
}

TEST(ForceCorrelation, TruncatedLengthEndsAtXi) {
  const Box box{30, 24, true, 3};
  const io::Frame f = random_frame(3, box, 200);
  const LagGrid grid = LagGrid::make(0.1, 11, 24, 0.5);
  PairSums sums(grid);
  std::vector<double> map;
  Correlator(grid).accumulate(loaded_grains(f), sums, map);
  EXPECT_DOUBLE_EQ(truncated_correlation_length(sums).back(), correlation_length(sums));
}

TEST(ForceCorrelation, BadContactsAndGridsAreUsageErrors) {
  io::Frame f;
  f.box = Box{10, 10, true, 0};
  f.position = {Vec2(1, 1), Vec2(2, 1)};
  add_contact(f, 0, 2, Vec2(1, 0), 1, 0);
  EXPECT_THROW(loaded_grains(f), UsageError);
  f.contacts.pair[0] = {0, 0};
  EXPECT_THROW(loaded_grains(f), UsageError);
  f.contacts.pair[0] = {0, 1};
  f.contacts.branch[0] = Vec2::Zero();
  EXPECT_THROW(loaded_grains(f), UsageError);
  EXPECT_THROW(LagGrid::make(0, 5, 24, 0.5), UsageError);
  EXPECT_THROW(LagGrid::make(0.1, 0.05, 24, 0.5), UsageError);
  EXPECT_THROW(LagGrid::make(0.1, 5, 2, 0.5), UsageError);
  EXPECT_THROW(LagGrid::make(0.1, 5, 24, 0.001), UsageError);
}

// The two densities on a constructed profile with closed forms: pair sums per radial bin of
// C̄(ℓ) = A e^{−ℓ/λ} per unit area, filled exactly (Σw = 2πW∫_b ℓC̄, Σw/ℓ = 2πW∫_b C̄,
// Σwℓ = 2πW∫_b ℓ²C̄), ℓ_max = 40λ. Per area ξ = ∫ℓC̄/∫C̄ = λ; per unit length, C_L = 2πℓC̄,
// ξ_length = ∫ℓ²C̄/∫ℓC̄ = 2λ: the ratio is 2. A contact peak of weight −P at ℓ = 1 added to
// it changes both by known amounts.
TEST(ForceCorrelation, LengthDensityOfAnExponential) {
  const double lambda = 0.75, amplitude = 0.3, norm = 2.0;
  const LagGrid grid = LagGrid::make(0.05, 40 * lambda, 12, 0.5);
  // ∫_lo^hi ℓ^k e^{−ℓ/λ} dℓ for k = 0, 1, 2 (antiderivatives −λ e^{−ℓ/λ}·poly_k(ℓ)).
  auto moment = [&](int k, double lo, double hi) {
    auto f = [&](double l) {
      const double e = -lambda * std::exp(-l / lambda);
      if (k == 0) return e;
      if (k == 1) return e * (l + lambda);
      return e * (l * l + 2 * lambda * l + 2 * lambda * lambda);
    };
    return f(hi) - f(lo);
  };
  PairSums sums(grid);
  sums.norm = norm;
  for (int b = 0; b < grid.radial_bins; ++b) {
    const double lo = b * grid.bin_width, hi = lo + grid.bin_width, scale = 2 * M_PI * norm * amplitude;
    sums.w_over_lag[std::size_t(b)] = scale * moment(0, lo, hi);
    sums.w[std::size_t(b)] = scale * moment(1, lo, hi);
    sums.w_times_lag[std::size_t(b)] = scale * moment(2, lo, hi);
  }
  const double xi_area = correlation_length(sums, Density::area), xi_length = correlation_length(sums, Density::length);
  EXPECT_NEAR(xi_area, lambda, 1e-12);
  EXPECT_NEAR(xi_length, 2 * lambda, 1e-12);
  EXPECT_NEAR(xi_length / xi_area, 2, 1e-12);
  // Truncated at ℓ: ξ_length(ℓ) = ∫_0^ℓ ℓ'²e / ∫_0^ℓ ℓ'e.
  const std::vector<double> truncated = truncated_correlation_length(sums, Density::length);
  for (int b : {3, 20, 100}) {
    const double edge = (b + 1) * grid.bin_width;
    EXPECT_NEAR(truncated[std::size_t(b)], moment(2, 0, edge) / moment(1, 0, edge), 1e-12) << b;
  }
  // A negative contact peak −P at ℓ = 1 (one pair sum: w = −P, w/ℓ = −P, wℓ = −P):
  // ξ = (I1 − P)/(I0 − P), ξ_length = (I2 − P)/(I1 − P), I_k = 2πWA∫ℓ^k e^{−ℓ/λ}.
  const double peak = 1.5, i0 = 2 * M_PI * norm * amplitude * moment(0, 0, grid.max_lag()),
               i1 = 2 * M_PI * norm * amplitude * moment(1, 0, grid.max_lag()),
               i2 = 2 * M_PI * norm * amplitude * moment(2, 0, grid.max_lag());
  const std::size_t at = std::size_t(1 / grid.bin_width);
  sums.w[at] -= peak;
  sums.w_over_lag[at] -= peak;
  sums.w_times_lag[at] -= peak;
  EXPECT_NEAR(correlation_length(sums, Density::area), (i1 - peak) / (i0 - peak), 1e-12);
  EXPECT_NEAR(correlation_length(sums, Density::length), (i2 - peak) / (i1 - peak), 1e-12);
}
