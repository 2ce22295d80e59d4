// The engine's branch-free helpers give every bit of the plain forms they replace: the
// engine's trajectories must not depend on which is used.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "dynamics/branch_free.hpp"

namespace granflow {
namespace {

std::uint64_t bits(double x) { return std::bit_cast<std::uint64_t>(x); }

// Special values (signed zeros, subnormals, infinities, NaN, ±½ and around) and random
// values over many orders of magnitude, both signs.
std::vector<double> samples() {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> v = {0.0,
                           -0.0,
                           1.0,
                           -1.0,
                           0.5,
                           -0.5,
                           1.5,
                           -1.5,
                           2.5,
                           -2.5,
                           std::nextafter(0.5, 0.0),
                           std::nextafter(-0.5, 0.0),
                           std::numeric_limits<double>::denorm_min(),
                           -std::numeric_limits<double>::denorm_min(),
                           std::numeric_limits<double>::min(),
                           std::numeric_limits<double>::max(),
                           inf,
                           -inf,
                           std::numeric_limits<double>::quiet_NaN()};
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> exponent(-300, 300), unit(-1, 1);
  for (int k = 0; k < 20000; ++k) v.push_back(unit(rng) * std::pow(10.0, exponent(rng)));
  for (int k = 0; k < 20000; ++k) v.push_back(unit(rng) * 1000);  // image indices' range
  return v;
}

TEST(BranchFree, PositivePartIsStdMaxWithZero) {
  for (double x : samples()) EXPECT_EQ(bits(positive_part(x)), bits(std::max(0.0, x))) << x;
}

TEST(BranchFree, BearingTellsPositiveImpulses) {
  for (double x : samples()) {
    const double p = positive_part(x);  // what the engine passes: +0 or positive (or +inf)
    EXPECT_EQ(bearing(p), p > 0 ? 1 : 0) << x;
  }
}

TEST(BranchFree, PickIsTheConditional) {
  const std::vector<double> v = samples();
  for (std::size_t k = 0; k + 1 < v.size(); ++k) {
    EXPECT_EQ(bits(pick(true, v[k], v[k + 1])), bits(v[k]));
    EXPECT_EQ(bits(pick(false, v[k], v[k + 1])), bits(v[k + 1]));
  }
}

TEST(BranchFree, RoundToIntRoundsHalfAwayFromZero) {
  for (double x : samples()) {
    if (!(std::fabs(x) < 1e9)) continue;  // the engine's range: separations over a box size
    EXPECT_EQ(round_to_int(x), int(x + (x < 0 ? -0.5 : 0.5))) << x;
    if (std::fabs(std::fabs(x - std::trunc(x)) - 0.5) > 1e-9) {
      EXPECT_EQ(round_to_int(x), int(std::round(x))) << x;
    }
  }
}

}  // namespace
}  // namespace granflow
