// ξ_dir(θ), eq. 5.2 applied per direction (force_correlation.hpp, direction_length in
// analysis.hpp), on the pair sums of a synthetic anisotropic C(ℓ, θ) = exp(−ℓ/λ(θ)) with
// λ(θ) = λ0 (1 − a sin 2(θ − θ0)): ∫ℓC dℓ / ∫C dℓ = λ(θ) pointwise (up to e^{−ℓmax/λ}), so the
// fit of eq. 5.3's shape about the mean must return a and θ0. On the same sums, ξ(θ) normalised
// by the isotropic ∫C̄ keeps its own value, ∫ℓC(ℓ, θ)dℓ / (2π∫C̄dℓ).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/random.hpp"
#include "correlation/analysis.hpp"

using namespace granflow;
using namespace granflow::correlation;

namespace {

constexpr double kLambda0 = 1.0, kA = 0.3, kTheta0 = 0.37;
constexpr int kSectors = 24;
constexpr int kSubAngles = 16;  // quadrature points per sector
constexpr double kStep = 0.01;  // radial quadrature step
constexpr double kMaxLag = 40;  // e^{−40/1.3}·(1 + 40/1.3) ≈ 10⁻¹² of the integrals lies beyond

double lambda(double theta) { return kLambda0 * (1 - kA * std::sin(2 * (theta - kTheta0))); }

LagGrid grid() { return LagGrid::make(0.05, kMaxLag, kSectors, 1.0, 5); }

// The pair sums that pairs with C(ℓ, θ) as density would give: for a lag element at (ℓ, θ),
// θ ∈ [0, π), of area ℓ dℓ dθ, the pairs there and at −ℓ carry Σw = 2W·C·ℓ dℓ dθ (each pair
// counts half at +r and half at −r). Midpoint rule in ℓ and θ; `scale(k)` multiplies λ in
// sector k (1: the exact C).
template <class Scale>
PairSums synthetic_sums(const LagGrid& g, Scale scale) {
  PairSums s(g);
  s.norm = 1;
  const double dtheta = g.sector_width() / kSubAngles;
  const int radial = int(std::lround(g.max_lag() / kStep));
  const std::size_t nc = std::size_t(g.coarse_bins());
  for (int k = 0; k < g.angle_bins; ++k) {
    const double l_theta_scale = scale(k);
    for (int m = 0; m < kSubAngles; ++m) {
      const double theta = (k + (m + 0.5) / kSubAngles) * g.sector_width();
      const double l = lambda(theta) * l_theta_scale;
      for (int j = 0; j < radial; ++j) {
        const double lag = (j + 0.5) * kStep;
        const double w = 2 * s.norm * std::exp(-lag / l) * lag * kStep * dtheta;
        const int b = std::min(int(lag / g.bin_width), g.radial_bins - 1);
        const std::size_t kc = std::size_t(k) * nc + std::size_t(b / g.coarse);
        s.w[std::size_t(b)] += w;
        s.w_over_lag[std::size_t(b)] += w / lag;
        s.sector[std::size_t(k)] += w;
        s.sector_w[kc] += w;
        s.sector_w_over_lag[kc] += w / lag;
      }
    }
  }
  return s;
}

PairSums exact_sums(const LagGrid& g) {
  return synthetic_sums(g, [](int) { return 1.0; });
}

// Closed forms of ∫₀^L ℓ e^{−ℓ/λ} dℓ and ∫₀^L e^{−ℓ/λ} dℓ.
double moment(double l) { return l * l * (1 - std::exp(-kMaxLag / l) * (1 + kMaxLag / l)); }
double integral(double l) { return l * (1 - std::exp(-kMaxLag / l)); }

// ∫ f(λ(θ)) dθ over [lo, hi) by a midpoint rule 50 times finer than the sums'.
template <class F>
double over_angle(double lo, double hi, F f) {
  const int n = 50 * kSubAngles;
  double sum = 0;
  for (int m = 0; m < n; ++m) sum += f(lambda(lo + (m + 0.5) * (hi - lo) / n));
  return sum * (hi - lo) / n;
}

double angle_difference(double a, double b) {  // modulo π, into [−π/2, π/2)
  double d = std::fmod(a - b + M_PI / 2, M_PI);
  if (d < 0) d += M_PI;
  return d - M_PI / 2;
}

}  // namespace

// ξ_dir per sector against its exact value ∫_sector dθ ∫ℓC dℓ / ∫_sector dθ ∫C dℓ (numerator
// and denominator averaged over the sector, as the pair sums do), to 10⁻⁴: the sums' midpoint
// rules err by ≈ (dℓ/λ)²/24 ≈ 10⁻⁵ in ℓ and less in θ. The fit of eq. 5.3's shape about the
// mean then returns a and θ0 to 10⁻³: sector averaging makes ξ_dir = ⟨λ²⟩/⟨λ⟩ = ⟨λ⟩ + Var λ/⟨λ⟩
// rather than ⟨λ⟩, which raises the mean by ≈ a²Δθ²/6 ≈ 3·10⁻⁴ (a0 low by a times that, 10⁻⁴)
// and adds harmonics in 4θ and 6θ, orthogonal to sin 2θ and cos 2θ over equal sectors.
TEST(DirectionLength, ExponentialWithAnisotropicDecayLength) {
  const LagGrid g = grid();
  const PairSums s = exact_sums(g);
  const std::vector<double> xi = direction_correlation_length(s, g), theta = sector_centres(g);
  ASSERT_EQ(xi.size(), std::size_t(kSectors));
  const double width = g.sector_width();
  const double all_integral = over_angle(0, M_PI, integral);
  const std::vector<double> xi_theta = angular_correlation_length(s, g);
  for (int k = 0; k < kSectors; ++k) {
    const double lo = k * width, hi = lo + width;
    const double expected = over_angle(lo, hi, moment) / over_angle(lo, hi, integral);
    EXPECT_NEAR(xi[k], expected, 1e-4 * expected) << "sector " << k;
    EXPECT_NEAR(xi[k], lambda(theta[k]), 3e-3 * lambda(theta[k])) << "sector " << k;
    // The reading normalised by the isotropic ∫C̄ on the same sums: sector mean of
    // ∫ℓC(ℓ, θ)dℓ / (2π∫C̄dℓ), 2π∫C̄dℓ = 2∫₀^π dθ ∫C dℓ.
    const double expected_theta = over_angle(lo, hi, moment) / width / (2 * all_integral);
    EXPECT_NEAR(xi_theta[k], expected_theta, 1e-4 * expected_theta) << "sector " << k;
  }
  const DirectionLength d = direction_length({s}, g);
  ASSERT_EQ(d.xi_theta, xi);
  ASSERT_TRUE(d.fit.converged);
  EXPECT_FALSE(d.fit.weighted) << "one block: no errors, an unweighted fit";
  std::printf("a0_direction - a = %.2e, theta0_direction - theta0 = %.2e\n", d.fit.a0 - kA,
              angle_difference(d.fit.theta0, kTheta0));
  EXPECT_NEAR(d.fit.a0, kA, 1e-3);
  EXPECT_NEAR(angle_difference(d.fit.theta0, kTheta0), 0, 1e-3);
}

// The reading normalised by the isotropic ∫C̄ on the same input keeps its normalisation
// ∫₀^{2π} ξ(θ) dθ = ξ and its own eq. 5.3 fit: ξ(θ) ∝ ∫ℓC dℓ = λ(θ)², whose sin 2θ amplitude
// relative to its mean is 2a/(1 + a²/2) (the sin² term adds a²/2 to the mean and a 4θ
// harmonic, orthogonal over equal sectors), not a.
TEST(DirectionLength, IsotropicNormalisationKeepsItsOwnAnswer) {
  const LagGrid g = grid();
  const PairSums s = exact_sums(g);
  const std::vector<double> xi_theta = angular_correlation_length(s, g);
  double total = 0;
  for (double x : xi_theta) total += 2 * g.sector_width() * x;
  EXPECT_NEAR(total, correlation_length(s), 1e-12 * correlation_length(s));
  const AnisotropyFit fit = fit_anisotropy(sector_centres(g), xi_theta, {}, correlation_length(s), g.sector_width());
  ASSERT_TRUE(fit.converged);
  EXPECT_NEAR(fit.a0, 2 * kA / (1 + kA * kA / 2), 1e-3);
  EXPECT_NEAR(angle_difference(fit.theta0, kTheta0), 0, 1e-3);
}

// Blocks whose decay lengths scatter by 2 % per sector (independently per block): the
// jackknife errors of ξ_dir come out near 2 %·λ/√B, the fit is weighted, and the truth lies
// within a few of its errors.
TEST(DirectionLength, JackknifeErrorsOverBlocks) {
  const LagGrid g = grid();
  const int blocks = 8;
  Rng rng(7);
  std::vector<PairSums> sums;
  for (int b = 0; b < blocks; ++b) {
    std::vector<double> scale;
    for (int k = 0; k < kSectors; ++k) scale.push_back(1 + 0.02 * rng.normal());
    sums.push_back(synthetic_sums(g, [&](int k) { return scale[std::size_t(k)]; }));
  }
  const DirectionLength d = direction_length(sums, g);
  const std::vector<double> theta = sector_centres(g);
  double ratio = 0;
  for (int k = 0; k < kSectors; ++k) {
    ASSERT_TRUE(std::isfinite(d.xi_theta_error[k]) && d.xi_theta_error[k] > 0) << k;
    ratio += d.xi_theta_error[k] / (0.02 * lambda(theta[k]) / std::sqrt(blocks)) / kSectors;
  }
  std::printf("mean jackknife error / (0.02 lambda / sqrt(B)) = %.3f\n", ratio);
  EXPECT_GT(ratio, 0.7);
  EXPECT_LT(ratio, 1.3);
  ASSERT_TRUE(d.fit.converged);
  EXPECT_TRUE(d.fit.weighted);
  EXPECT_LT(std::fabs(d.fit.a0 - kA), 4 * d.fit.a0_error);
  EXPECT_LT(std::fabs(angle_difference(d.fit.theta0, kTheta0)), 4 * d.fit.theta0_error);
}

// NaN sectors: no pairs (∫C dℓ = 0), ∫ℓC and ∫C of opposite signs, and a ratio beyond ℓ_max
// (∫C dℓ nearly cancelled). The fit uses the finite sectors: with two opposite sectors
// (θ and θ + π/2) missing, the mean is still λ0's and a, θ0 come back; with two sectors left,
// no fit.
TEST(DirectionLength, MeaninglessSectorsAreNaNAndLeftOutOfTheFit) {
  const LagGrid g = grid();
  PairSums s = exact_sums(g);
  const std::size_t nc = std::size_t(g.coarse_bins());
  auto set_sector = [&](int k, double w_near, double w_far) {  // w in the first and last coarse bins
    for (std::size_t c = 0; c < nc; ++c)
      s.sector_w[std::size_t(k) * nc + c] = s.sector_w_over_lag[std::size_t(k) * nc + c] = 0;
    const double near = 0.5 * g.coarse * g.bin_width, far = g.max_lag() - 0.01;
    s.sector_w[std::size_t(k) * nc] = w_near;
    s.sector_w_over_lag[std::size_t(k) * nc] = w_near / near;
    s.sector_w[std::size_t(k) * nc + nc - 1] = w_far;
    s.sector_w_over_lag[std::size_t(k) * nc + nc - 1] = w_far / far;
  };
  set_sector(3, 0, 0);                  // empty
  set_sector(3 + kSectors / 2, -1, 2);  // Σw/ℓ < 0 < Σw
  std::vector<double> xi = direction_correlation_length(s, g);
  EXPECT_TRUE(std::isnan(xi[3]));
  EXPECT_TRUE(std::isnan(xi[3 + kSectors / 2]));
  {
    const DirectionLength d = direction_length({s}, g);
    ASSERT_TRUE(d.fit.converged);
    EXPECT_NEAR(d.fit.a0, kA, 1e-3);
    EXPECT_NEAR(angle_difference(d.fit.theta0, kTheta0), 0, 1e-3);
  }
  // Σw = 1 − 1.001·far/near and Σw/ℓ = −0.001/near, both negative: a ratio near 4·10⁴ > ℓ_max.
  const double near = 0.5 * g.coarse * g.bin_width, far = g.max_lag() - 0.01;
  set_sector(5, 1, -(1 / near) * far * (1 + 1e-3));
  xi = direction_correlation_length(s, g);
  EXPECT_TRUE(std::isnan(xi[5]));
  // A lone pair: the ratio is its lag.
  set_sector(7, -2, 0);
  xi = direction_correlation_length(s, g);
  EXPECT_NEAR(xi[7], near, 1e-15);
  // Only two finite sectors: no fit.
  for (int k = 2; k < kSectors; ++k) set_sector(k, 0, 0);
  const DirectionLength d = direction_length({s}, g);
  EXPECT_FALSE(d.fit.converged);
  EXPECT_TRUE(std::isnan(d.fit.a0) && std::isnan(d.fit.theta0));
}
