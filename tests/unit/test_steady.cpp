// The steady-state rule of lib/statistics/steady.hpp on synthetic series with known
// answers: MSER cuts a decaying transient, the halves check keeps a stationary series and
// flags a drift, mser_first_row() is MSER on block means scaled to rows, a chosen start is
// checked too, and halves_change() is the halves' difference with blocking errors.
#include "statistics/steady.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "core/random.hpp"
#include "statistics/blocking.hpp"

namespace granflow {
namespace {

std::vector<double> noisy(std::size_t n, double transient, double decay, double sigma, double drift,
                          std::uint64_t seed) {
  Rng rng(seed);
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i)
    x[i] = 5 + transient * std::exp(-double(i) / decay) + drift * double(i) + sigma * rng.normal();
  return x;
}

TEST(SteadyDetection, MserCutsTheTransient) {
  int steady = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const auto x = noisy(200, 10, 8, 0.5, 0, seed);
    const std::size_t d = mser_truncation(x);
    // The transient falls below the noise after 8·ln 20 ≈ 24 blocks.
    EXPECT_GE(d, 15u) << seed;
    EXPECT_LE(d, 60u) << seed;
    const SteadyState s = detect_steady({x, noisy(200, -3, 4, 0.1, 0, seed + 100)});
    EXPECT_EQ(s.first, std::max(s.truncation[0], s.truncation[1]));
    steady += s.steady;
  }
  // MSER trades the transient's bias against noise, so what it keeps can still hold a
  // residue of about a standard error, which the 3σ halves test sometimes sees.
  EXPECT_GE(steady, 16);
}

TEST(SteadyDetection, StationarySeriesIsKeptAndDriftIsFlagged) {
  const auto stationary = noisy(100, 0, 1, 1, 0, 7);
  EXPECT_LE(mser_truncation(stationary), 50u);
  EXPECT_TRUE(detect_steady({stationary}).steady);
  // A drift of several standard errors between the halves of whatever MSER keeps.
  const auto drifting = noisy(100, 0, 1, 1, 0.06, 7);
  EXPECT_FALSE(detect_steady({stationary, drifting}).steady);
  EXPECT_LE(mser_truncation(drifting), 50u);
  // Too short to judge.
  EXPECT_FALSE(detect_steady({{1.0, 1.1, 0.9}}).steady);
  EXPECT_EQ(mser_truncation(std::vector<double>{3.0}), 0u);
}

// mser_first_row: MSER on block means of per-row series, the latest truncation, as a row.
TEST(SteadyDetection, FirstRowOfPerRowSeriesIsTheLatestBlockTruncation) {
  // 1000 rows in 100 blocks of 10: a ramp over the first 300 rows, then constant plus a
  // small wiggle; a second series steady from the start.
  std::vector<double> ramp(1000), flat(1000);
  for (std::size_t i = 0; i < 1000; ++i) {
    ramp[i] = std::min(1.0, double(i) / 300.0) + 1e-3 * std::sin(0.7 * double(i));
    flat[i] = 2 + 1e-3 * std::cos(0.3 * double(i));
  }
  const std::size_t row = mser_first_row({ramp, flat});
  EXPECT_EQ(row % 10, 0u);
  EXPECT_GE(row, 280u);
  EXPECT_LE(row, 310u);
  // It is MSER of the block means, times the block length, and the later series wins.
  std::vector<double> means(100);
  for (std::size_t b = 0; b < 100; ++b)
    for (std::size_t r = 0; r < 10; ++r) means[b] += ramp[10 * b + r] / 10;
  EXPECT_EQ(row, 10 * mser_truncation(means));
  EXPECT_EQ(mser_first_row({flat, ramp}), row);
  // Rows left over past the last whole block belong to none: 1009 rows, the same blocks.
  ramp.resize(1009, 1.0);
  flat.resize(1009, 2.0);
  EXPECT_EQ(mser_first_row({ramp, flat}), row);
  // Fewer rows than blocks: a block per row.
  EXPECT_EQ(mser_first_row({{0.0, 1.0, 1.1, 0.9, 1.05, 0.95}}), 1u);
  EXPECT_EQ(mser_first_row({}), 0u);
}

TEST(SteadyDetection, ChosenStartIsCheckedToo) {
  const auto x = noisy(200, 10, 8, 0.5, 0, 3);
  EXPECT_FALSE(steady_from({x}, 0).steady);  // the transient is in the first half
  EXPECT_TRUE(steady_from({x}, 80).steady);
  EXPECT_EQ(steady_from({x}, 80).first, 80u);
}

TEST(HalvesChange, DifferenceOfTheHalvesWithBlockingErrors) {
  // 201 values: the middle one (index 100) belongs to neither half.
  std::vector<double> x(201);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = (i < 100 ? 1.0 : 3.0) + 0.25 * std::sin(0.37 * double(i));
  x[100] = 1e6;
  const HalvesChange h = halves_change(x);
  double first = 0, second = 0;
  for (std::size_t i = 0; i < 100; ++i) {
    first += x[i] / 100;
    second += x[101 + i] / 100;
  }
  EXPECT_NEAR(h.change, second - first, 1e-12);
  const double e1 = blocking_error(std::span<const double>(x).first(100)).error;
  const double e2 = blocking_error(std::span<const double>(x).last(100)).error;
  EXPECT_GT(e1, 0);
  EXPECT_NEAR(h.error, std::hypot(e1, e2), 1e-15);
}

TEST(HalvesChange, StationaryNoiseIsWithinItsErrorsAndADriftIsNot) {
  const auto stationary = noisy(4000, 0, 1, 1, 0, 11);
  const HalvesChange s = halves_change(stationary);
  EXPECT_LT(std::fabs(s.change), 3 * s.error);
  // The white-noise error of each half's mean is 1/√2000.
  EXPECT_NEAR(s.error, std::sqrt(2.0 / 2000), 0.2 * std::sqrt(2.0 / 2000));
  const HalvesChange d = halves_change(noisy(4000, 0, 1, 1, 2e-4, 11));
  EXPECT_NEAR(d.change, 2e-4 * 2000, 6 * d.error);  // the drift times the distance of the halves
  EXPECT_GT(std::fabs(d.change), 3 * d.error);
}

TEST(HalvesChange, TooShortHalvesAreRefused) {
  EXPECT_THROW(halves_change(std::vector<double>(63, 1.0)), std::invalid_argument);
  EXPECT_NO_THROW(halves_change(std::vector<double>(64, 1.0)));
}

}  // namespace
}  // namespace granflow
