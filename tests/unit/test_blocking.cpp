// Flyvbjerg–Petersen blocking with Jonsson's plateau choice (lib/statistics/blocking.hpp)
// on series with known answers: AR(1) against its exact standard error, white noise (the
// plateau at level 0, read at level 1), a constant series, the flag on a series too short
// for its correlation time, the refusal below 32 values; and the numpy summation order
// the errors are computed in (lib/statistics/python_arithmetic.hpp).
#include "statistics/blocking.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "core/random.hpp"
#include "statistics/python_arithmetic.hpp"

namespace granflow {
namespace {

// x_t = φ x_{t−1} + ε_t, ε standard normal, started from the stationary distribution.
std::vector<double> ar1(std::size_t n, double phi, std::uint64_t seed) {
  Rng rng(seed);
  std::vector<double> x(n);
  x[0] = rng.normal() / std::sqrt(1 - phi * phi);
  for (std::size_t i = 1; i < n; ++i) x[i] = phi * x[i - 1] + rng.normal();
  return x;
}

// Exact standard error of the mean of n values of the stationary AR(1):
// Var(x̄) = σ²/n · [1 + 2 Σ_{k<n} (1 − k/n) φ^k], σ² = 1/(1 − φ²).
double ar1_standard_error(std::size_t n, double phi) {
  double sum = 1, power = 1;
  for (std::size_t k = 1; k < n; ++k) {
    power *= phi;
    sum += 2 * (1 - double(k) / double(n)) * power;
  }
  return std::sqrt(sum / (1 - phi * phi) / double(n));
}

// One blocking step by hand: the means of neighbouring pairs (the oldest value of an odd
// count dropped) and the level's σ²/(m − 1).
std::vector<double> pair_means(const std::vector<double>& x) {
  const std::size_t skip = x.size() % 2;
  std::vector<double> y;
  for (std::size_t i = skip; i + 1 < x.size(); i += 2) y.push_back(0.5 * (x[i] + x[i + 1]));
  return y;
}
double squared_error(const std::vector<double>& x) {
  const std::size_t skip = x.size() % 2, m = x.size() - skip;
  double mean = 0, var = 0;
  for (std::size_t i = skip; i < x.size(); ++i) mean += x[i] / double(m);
  for (std::size_t i = skip; i < x.size(); ++i) var += (x[i] - mean) * (x[i] - mean) / double(m);
  return var / double(m - 1);
}

TEST(Blocking, Ar1MatchesItsExactStandardError) {
  // τ_int = (1 + φ)/(2(1 − φ)) ≈ 9.5 steps; 2¹⁶ steps span ~7000 of them, where the
  // estimate is low by ~3 % at most; one series' estimate scatters by a few %.
  for (double phi : {0.5, 0.9}) {
    double ratio_sum = 0;
    for (std::uint64_t seed = 1; seed <= 8; ++seed) {
      const auto x = ar1(1 << 16, phi, seed);
      const Blocking b = blocking_error(x);
      EXPECT_TRUE(b.plateau) << phi << " " << seed;
      const double ratio = b.error / ar1_standard_error(x.size(), phi);
      EXPECT_NEAR(ratio, 1, 0.15) << phi << " " << seed;
      ratio_sum += ratio;
    }
    EXPECT_NEAR(ratio_sum / 8, 1, 0.06) << phi;
  }
}

TEST(Blocking, WhiteNoiseIsReadOneLevelAboveItsPlateauAtLevelZero) {
  // Uncorrelated values pass Jonsson's test at level 0; the error is read at level 1:
  // n/2 blocks and the squared error of the pair means (not of the values, level 0, nor
  // of level 2) — an off-by-one in the level choice changes both.
  Rng rng(3);
  std::vector<double> x(4096);
  for (double& v : x) v = 3 + 2 * rng.normal();
  const Blocking b = blocking_error(x);
  EXPECT_TRUE(b.plateau);
  EXPECT_EQ(b.blocks, 2048u);
  const auto level1 = pair_means(x), level2 = pair_means(level1);
  EXPECT_NEAR(b.error, std::sqrt(squared_error(level1)), 1e-12 * b.error);
  EXPECT_GT(std::fabs(std::sqrt(squared_error(x)) / b.error - 1), 1e-4);
  EXPECT_GT(std::fabs(std::sqrt(squared_error(level2)) / b.error - 1), 1e-4);
  EXPECT_NEAR(b.error, 2 / std::sqrt(4096.0), 0.15 * 2 / std::sqrt(4096.0));
}

TEST(Blocking, OddLengthsDropTheOldestValue) {
  // Prepending a value to an even-length series changes nothing: it is dropped first.
  Rng rng(5);
  std::vector<double> x(1000);
  for (double& v : x) v = rng.normal();
  const Blocking even = blocking_error(x);
  x.insert(x.begin(), 1e9);
  const Blocking odd = blocking_error(x);
  EXPECT_EQ(odd.error, even.error);
  EXPECT_EQ(odd.blocks, even.blocks);
}

TEST(Blocking, ConstantSeriesHasZeroError) {
  const Blocking b = blocking_error(std::vector<double>(100, 2.5));
  EXPECT_EQ(b.error, 0);
  EXPECT_TRUE(b.plateau);
  EXPECT_EQ(b.blocks, 50u);  // level 0 passes (all statistics 0), read at level 1
}

TEST(Blocking, TooShortForItsCorrelationTimeIsFlagged) {
  // A trend is correlated over the whole series: no level with ≥ 16 blocks passes Jonsson's
  // test, the estimate is from the longest such blocks (16) and is flagged as a lower bound.
  Rng rng(7);
  std::vector<double> x(256);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = double(i) / 256 + 0.01 * rng.normal();
  const Blocking b = blocking_error(x);
  EXPECT_FALSE(b.plateau);
  EXPECT_EQ(b.blocks, 16u);
  // The same with AR(1) at φ = 0.999 (τ_int ≈ 1000 steps) over 2000 steps, below its exact error.
  const auto slow = ar1(2000, 0.999, 3);
  const Blocking s = blocking_error(slow);
  EXPECT_FALSE(s.plateau);
  EXPECT_LT(s.error, ar1_standard_error(slow.size(), 0.999));
}

TEST(Blocking, RefusesFewerThan32Values) {
  EXPECT_THROW(blocking_error(std::vector<double>(31, 1.0)), std::invalid_argument);
  try {
    blocking_error(std::vector<double>(5, 1.0));
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "blocking needs at least 32 samples, got 5");
  }
  EXPECT_EQ(blocking_error(std::vector<double>(32, 1.0)).blocks, 16u);
}

TEST(Blocking, ChiSquaredQuantile) {
  // Tabulated 99 % quantiles of χ²: Wilson–Hilferty within 1 % from dof = 1 on.
  const double table[][2] = {{1, 6.635}, {2, 9.210}, {5, 15.086}, {10, 23.209}, {20, 37.566}};
  for (const auto& row : table) EXPECT_NEAR(chi2_quantile_99(std::size_t(row[0])) / row[1], 1, 0.01) << row[0];
}

TEST(NumpySum, PairwiseOrderOfNumpy) {
  // Up to 7 values: in order. 1e16 + 1 + 1 rounds each 1 away.
  EXPECT_EQ(numpy_sum(std::vector<double>{1e16, 1, 1}), 1e16);
  // 8..128 values: eight interleaved partial sums; the one 1 that shares 1e16's partial sum
  // is lost, the other 14 are summed before they meet it (numpy: 1e16 + 14 too).
  std::vector<double> x(16, 1.0);
  x[0] = 1e16;
  EXPECT_EQ(numpy_sum(x), 1e16 + 14);
  double sequential = 0;
  for (double v : x) sequential += v;
  EXPECT_EQ(sequential, 1e16);
  // Past 8192 values: chunks of 8192, each summed pairwise, added in turn (numpy gives the
  // same): the first block of 128 loses the 15 ones that share 1e16's partial sum, the other
  // 8064 ones of the first chunk and the 8 of the second are kept.
  std::vector<double> y(8192 + 8, 1.0);
  y[0] = 1e16;
  EXPECT_EQ(numpy_sum(y), 1e16 + 8184);
  EXPECT_EQ(numpy_sum(std::vector<double>{}), 0.0);
  EXPECT_TRUE(std::isnan(numpy_mean(std::vector<double>{})));
  EXPECT_EQ(numpy_mean(std::vector<double>{1, 2, 3, 4}), 2.5);
}

TEST(PythonHypot, CorrectlyRounded) {
  EXPECT_EQ(python_hypot(3, 4), 5);
  EXPECT_EQ(python_hypot(-3, 4), 5);
  EXPECT_EQ(python_hypot(0, 0), 0);
  EXPECT_TRUE(std::isinf(python_hypot(INFINITY, NAN)));
  EXPECT_EQ(python_hypot(1e300, 1e300), std::sqrt(2.0) * 1e300);
}

}  // namespace
}  // namespace granflow
