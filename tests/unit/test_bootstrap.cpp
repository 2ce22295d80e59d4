// The block bootstrap of lib/statistics/bootstrap.hpp: its draws (reproducible from the
// seed, uniform over the blocks), the agreement fraction on a predicate with a known
// probability, and the spread of replicate means against the standard error of the mean.
#include "statistics/bootstrap.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/random.hpp"

namespace granflow {
namespace {

TEST(BlockBootstrap, DrawsComeFromTheSeedInOrder) {
  // The draws are Rng(seed)'s uniforms scaled to the block count, one replicate after the
  // other: gf-correlate's peak confidences depend on exactly this sequence.
  std::vector<std::size_t> all;
  block_bootstrap(7, 3, 42, [&](std::span<const std::size_t> draws) {
    EXPECT_EQ(draws.size(), 7u);
    all.insert(all.end(), draws.begin(), draws.end());
  });
  ASSERT_EQ(all.size(), 21u);
  Rng rng(42);
  for (std::size_t d : all) EXPECT_EQ(d, std::size_t(rng.uniform() * 7));
  int calls = 0;
  block_bootstrap(0, 5, 1, [&](std::span<const std::size_t>) { ++calls; });
  EXPECT_EQ(calls, 0);
}

TEST(BlockBootstrap, DrawsAreUniformOverTheBlocks) {
  const std::size_t blocks = 10;
  std::vector<double> count(blocks, 0);
  block_bootstrap(blocks, 10000, 3, [&](std::span<const std::size_t> draws) {
    for (std::size_t d : draws) {
      ASSERT_LT(d, blocks);
      ++count[d];
    }
  });
  for (double c : count) EXPECT_NEAR(c / 1e5, 0.1, 0.005);  // binomial sd 0.001
}

TEST(BlockBootstrap, AgreementIsTheFractionOfReplicates) {
  // P(block 0 is drawn at least once in n draws) = 1 − (1 − 1/n)^n.
  const std::size_t n = 10;
  const double p = 1 - std::pow(1 - 1.0 / n, double(n));
  const double f = bootstrap_agreement(n, 20000, 5, [](std::span<const std::size_t> draws) {
    for (std::size_t d : draws)
      if (d == 0) return true;
    return false;
  });
  EXPECT_NEAR(f, p, 0.015);  // binomial sd 0.0034
  auto always = [](std::span<const std::size_t>) { return true; };
  EXPECT_EQ(bootstrap_agreement(n, 50, 5, always), 1.0);
  EXPECT_TRUE(std::isnan(bootstrap_agreement(1, 50, 5, always)));  // one block: nothing to resample
  EXPECT_TRUE(std::isnan(bootstrap_agreement(n, 0, 5, always)));
}

TEST(BlockBootstrap, SpreadOfReplicateMeansIsTheStandardError) {
  // The bootstrap variance of the mean of n block values is (n − 1)/n · s²/n.
  Rng rng(8);
  const std::size_t n = 40;
  std::vector<double> value(n);
  double mean = 0;
  for (double& v : value) mean += (v = 2 + rng.normal()) / double(n);
  double s2 = 0;
  for (double v : value) s2 += (v - mean) * (v - mean) / double(n - 1);
  double sum = 0, sum2 = 0;
  const int replicates = 20000;
  block_bootstrap(n, replicates, 9, [&](std::span<const std::size_t> draws) {
    double m = 0;
    for (std::size_t d : draws) m += value[d] / double(n);
    sum += m;
    sum2 += m * m;
  });
  const double var = sum2 / replicates - (sum / replicates) * (sum / replicates);
  EXPECT_NEAR(std::sqrt(var) / std::sqrt(double(n - 1) / double(n) * s2 / double(n)), 1, 0.03);
}

}  // namespace
}  // namespace granflow
