// The fit of eq. 5.3 (a0, θ0) on synthetic ξ(θ) with known parameters: exact recovery
// without noise, and error bars that cover the truth as often as they should with noise.
#include <gtest/gtest.h>

#include <cmath>

#include "core/random.hpp"
#include "correlation/anisotropy_fit.hpp"

using namespace granflow;
using namespace granflow::correlation;

namespace {
constexpr int kSectors = 24;
constexpr double kWidth = M_PI / kSectors;

std::vector<double> centres() {
  std::vector<double> t;
  for (int k = 0; k < kSectors; ++k) t.push_back((k + 0.5) * kWidth);
  return t;
}

// Sector averages of ξ/(2π)(1 − a0 sin 2(θ − θ0)) over [θ_k − Δθ/2, θ_k + Δθ/2], in closed form.
std::vector<double> sector_averages(double xi, double a0, double theta0) {
  std::vector<double> y;
  for (double t : centres()) {
    const double lo = t - kWidth / 2, hi = t + kWidth / 2;
    const double mean_sin = (std::cos(2 * (lo - theta0)) - std::cos(2 * (hi - theta0))) / (2 * kWidth);
    y.push_back(xi / (2 * M_PI) * (1 - a0 * mean_sin));
  }
  return y;
}

double angle_difference(double a, double b) {  // modulo π, into [−π/2, π/2)
  double d = std::fmod(a - b + M_PI / 2, M_PI);
  if (d < 0) d += M_PI;
  return d - M_PI / 2;
}
}  // namespace

TEST(AnisotropyFit, RecoversExactParameters) {
  for (double theta0 : {0.013, -1.2, 1.5, 0.7})
    for (double a0 : {0.21, 0.6}) {
      const AnisotropyFit fit = fit_anisotropy(centres(), sector_averages(3.0, a0, theta0), {}, 3.0, kWidth);
      ASSERT_TRUE(fit.converged);
      EXPECT_NEAR(fit.a0, a0, 1e-9);
      EXPECT_NEAR(angle_difference(fit.theta0, theta0), 0, 1e-9);
      EXPECT_GE(fit.theta0, -M_PI / 2);
      EXPECT_LT(fit.theta0, M_PI / 2);
    }
}

TEST(AnisotropyFit, PointValuesWithoutSectorWidth) {
  std::vector<double> y;
  for (double t : centres()) y.push_back(2.0 / (2 * M_PI) * (1 - 0.3 * std::sin(2 * (t - 0.4))));
  const AnisotropyFit fit = fit_anisotropy(centres(), y, {}, 2.0, 0);
  EXPECT_NEAR(fit.a0, 0.3, 1e-9);
  EXPECT_NEAR(fit.theta0, 0.4, 1e-9);
}

TEST(AnisotropyFit, ErrorsCoverTheTruth) {
  // 400 noisy data sets (Gaussian noise of known σ_k, given to the fit): the truth should
  // lie within one reported error about 68 % of the time, within two about 95 %. Unequal
  // σ_k (as along the dilational axis, where the thesis notes poor statistics) make the
  // weighted fit iterate rather than start at its minimum.
  const double xi = 2.5, a0 = 0.21, theta0 = 0.013, base = 0.03 * xi / (2 * M_PI);
  const std::vector<double> truth = sector_averages(xi, a0, theta0);
  std::vector<double> sigma;
  for (double t : centres()) sigma.push_back(base * (1 + 2 * std::pow(std::sin(t - M_PI / 4), 2)));
  int within1_a = 0, within1_t = 0, within2_a = 0, within2_t = 0, unweighted_within1_a = 0;
  const int trials = 400;
  for (int seed = 0; seed < trials; ++seed) {
    Rng rng(std::uint64_t(seed) + 100);
    std::vector<double> y = truth;
    for (int k = 0; k < kSectors; ++k) y[k] += sigma[k] * rng.normal();
    const AnisotropyFit fit = fit_anisotropy(centres(), y, sigma, xi, kWidth);
    ASSERT_TRUE(fit.converged) << seed;
    ASSERT_TRUE(fit.weighted);
    const double da = std::fabs(fit.a0 - a0), dt = std::fabs(angle_difference(fit.theta0, theta0));
    within1_a += da <= fit.a0_error;
    within2_a += da <= 2 * fit.a0_error;
    within1_t += dt <= fit.theta0_error;
    within2_t += dt <= 2 * fit.theta0_error;
    // Without given errors the scatter about the fit sets them.
    const AnisotropyFit plain = fit_anisotropy(centres(), y, {}, xi, kWidth);
    EXPECT_FALSE(plain.weighted);
    unweighted_within1_a += std::fabs(plain.a0 - a0) <= plain.a0_error;
  }
  // Binomial spread of a 68 % rate over 400 trials is 2.3 %; the max(1, √χ²) scaling
  // can only widen the errors, so allow a little more above than below.
  EXPECT_GE(within1_a, 0.60 * trials);
  EXPECT_LE(within1_a, 0.80 * trials);
  EXPECT_GE(within1_t, 0.60 * trials);
  EXPECT_LE(within1_t, 0.80 * trials);
  EXPECT_GE(within2_a, 0.91 * trials);
  EXPECT_GE(within2_t, 0.91 * trials);
  EXPECT_GE(unweighted_within1_a, 0.58 * trials);
  EXPECT_LE(unweighted_within1_a, 0.78 * trials);
}

TEST(AnisotropyFit, NoFitWithoutData) {
  EXPECT_FALSE(fit_anisotropy({0.1, 0.2}, {1, 1}, {}, 1, 0).converged);
  std::vector<double> y = sector_averages(1, 0.2, 0);
  y[3] = std::nan("");
  EXPECT_FALSE(fit_anisotropy(centres(), y, {}, 1, kWidth).converged);
  EXPECT_FALSE(fit_anisotropy(centres(), sector_averages(1, 0.2, 0), {}, std::nan(""), kWidth).converged);
}
