// gf-kinetic's χ(ν) interpolation (kinetic/table.hpp: exact at the nodes, monotone, its error
// propagation, refusal or extrapolation outside) and its window errors (delta method).
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "core/random.hpp"
#include "kinetic/kinetic.hpp"
#include "kinetic/table.hpp"
#include "statistics/blocking.hpp"

using namespace granflow;
using namespace granflow::kinetic;

namespace {
// Henderson's χ at a few ν with 1 % and 2 % errors, given out of order.
ChiTable henderson_nodes() {
  return ChiTable({{0.5, henderson_chi(0.5), 0.02 * henderson_chi(0.5)},
                   {0.1, henderson_chi(0.1), 0.01 * henderson_chi(0.1)},
                   {0.3, henderson_chi(0.3), 0.01 * henderson_chi(0.3)}});
}
}  // namespace

TEST(KineticTable, InterpolationIsExactAtTheNodes) {
  const ChiTable t = henderson_nodes();
  EXPECT_EQ(t.min_nu(), 0.1);
  EXPECT_EQ(t.max_nu(), 0.5);
  for (double nu : {0.1, 0.3, 0.5}) {
    const ChiValue v = t.at(nu);
    EXPECT_NEAR(v.chi, henderson_chi(nu), 1e-14 * henderson_chi(nu)) << nu;
    const double rel = nu == 0.5 ? 0.02 : 0.01;
    EXPECT_NEAR(v.error, rel * henderson_chi(nu), 1e-14) << nu;
  }
}

TEST(KineticTable, InterpolationIsMonotoneAndLinearInLogChi) {
  const ChiTable t = henderson_nodes();
  double previous = 0;
  for (double nu = 0.1; nu <= 0.5; nu += 0.001) {
    const double chi = t.at(nu).chi;
    EXPECT_GT(chi, previous) << nu;
    previous = chi;
  }
  // Halfway between two nodes: the geometric mean.
  EXPECT_NEAR(t.at(0.2).chi, std::sqrt(henderson_chi(0.1) * henderson_chi(0.3)), 1e-12);
  // Between nodes within the bounds of its neighbours, and close to the smooth curve.
  EXPECT_NEAR(t.at(0.4).chi, henderson_chi(0.4), 0.03 * henderson_chi(0.4));
}

TEST(KineticTable, ErrorCombinesTheNeighboursAsIndependent) {
  const ChiTable t = henderson_nodes();
  // At w = 1/2 between 0.3 (1 %) and 0.5 (2 %): δlnχ = √((0.5·0.01)² + (0.5·0.02)²).
  const ChiValue v = t.at(0.4);
  EXPECT_NEAR(v.error / v.chi, std::hypot(0.005, 0.01), 1e-12);
  // At w = 1/4: √((0.75·0.01)² + (0.25·0.02)²).
  const ChiValue q = t.at(0.35);
  EXPECT_NEAR(q.error / q.chi, std::hypot(0.0075, 0.005), 1e-12);
}

TEST(KineticTable, OutsideTheRangeIsRefusedUnlessExtrapolating) {
  const ChiTable t = henderson_nodes();
  EXPECT_TRUE(t.covers(0.1));
  EXPECT_TRUE(t.covers(0.5));
  EXPECT_FALSE(t.covers(0.09));
  EXPECT_FALSE(t.covers(0.6));
  EXPECT_THROW(t.at(0.6), std::out_of_range);
  EXPECT_THROW(t.at(0.05), std::out_of_range);
  // Extrapolated: the end segment's line in ln χ, with the end node's relative error.
  const ChiValue v = t.at(0.6, true);
  const double slope = (std::log(henderson_chi(0.5)) - std::log(henderson_chi(0.3))) / 0.2;
  EXPECT_NEAR(std::log(v.chi), std::log(henderson_chi(0.5)) + 0.1 * slope, 1e-12);
  EXPECT_NEAR(v.error / v.chi, 0.02, 1e-12);
  // One node: scaled by Henderson's shape.
  const ChiTable one({{0.3, 2.0, 0.1}});
  EXPECT_NEAR(one.at(0.5, true).chi, 2.0 * henderson_chi(0.5) / henderson_chi(0.3), 1e-12);
  EXPECT_THROW(one.at(0.5), std::out_of_range);
}

TEST(KineticTable, NodesAtTheSameNuAreMergedByInverseVariance) {
  const ChiTable t({{0.3, 2.0, 0.02}, {0.3, 2.2, 0.044}, {0.5, 3.0, 0.03}});
  ASSERT_EQ(t.nodes().size(), 2u);
  // Relative errors 1 % and 2 %: weights 4:1 on ln χ.
  const double expected = std::exp((4 * std::log(2.0) + std::log(2.2)) / 5);
  EXPECT_NEAR(t.at(0.3).chi, expected, 1e-12);
  EXPECT_NEAR(t.at(0.3).error / t.at(0.3).chi, 1 / std::sqrt(1e4 + 2.5e3), 1e-12);
}

TEST(KineticTable, BadNodesAreRejected) {
  EXPECT_THROW(ChiTable({}), std::invalid_argument);
  EXPECT_THROW(ChiTable({{0.3, 0.0, 0.1}}), std::invalid_argument);
  EXPECT_THROW(ChiTable({{0.3, NAN, 0.1}}), std::invalid_argument);
}

TEST(KineticTable, DeltaErrorOfARatioMatchesTheScatterOfIndependentRatios) {
  // 400 independent experiments, each the ratio of the means of 64 (a, b) pairs with
  // correlated a and b: the delta method's error of one experiment's ratio against the
  // scatter of the ratios across experiments.
  Rng rng(7);
  std::vector<double> ratios, errors;
  for (int k = 0; k < 400; ++k) {
    std::vector<double> a(64), b(64);
    for (int r = 0; r < 64; ++r) {
      const double x = rng.normal(), y = rng.normal();
      a[r] = 3 + 0.5 * x;
      b[r] = 2 + 0.3 * x + 0.2 * y;
    }
    const double ma = mean(a), mb = mean(b), ratio = ma / mb;
    ratios.push_back(ratio);
    errors.push_back(delta_error({{a, 1 / mb}, {b, -ratio / mb}}));
  }
  const double m = mean(ratios);
  double ss = 0;
  for (double r : ratios) ss += (r - m) * (r - m);
  const double scatter = std::sqrt(ss / double(ratios.size() - 1));
  EXPECT_NEAR(mean(errors), scatter, 0.12 * scatter);
}

TEST(KineticTable, MeanErrorIsBlockingForLongSeriesAndPlainForShortOnes) {
  std::vector<double> x;
  for (int k = 0; k < 10; ++k) x.push_back(k % 2);
  // Plain standard error: sd = √(10·0.25/9), /√10.
  EXPECT_NEAR(mean_error(x), std::sqrt(10 * 0.25 / 9) / std::sqrt(10.0), 1e-12);
  EXPECT_TRUE(std::isnan(mean_error(std::vector<double>{1.0})));
  std::vector<double> y;
  Rng rng(3);
  for (int k = 0; k < 256; ++k) y.push_back(rng.normal());
  EXPECT_EQ(mean_error(y), blocking_error(y).error);
}
