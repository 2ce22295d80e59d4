// The block jackknife of lib/statistics/jackknife.hpp against the plain standard error of
// independent block means, and its refusal with one block.
#include "statistics/jackknife.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <vector>

#include "core/random.hpp"

namespace granflow {
namespace {

TEST(Jackknife, MeanOfIndependentBlocks) {
  // For a plain mean the block jackknife is the standard error of the block means.
  struct Sums {
    double sum = 0, count = 0;
    Sums& operator+=(const Sums& o) {
      sum += o.sum;
      count += o.count;
      return *this;
    }
  };
  Rng rng(9);
  std::vector<Sums> blocks(16);
  std::vector<double> means;
  for (auto& b : blocks) {
    for (int i = 0; i < 50; ++i) b.sum += rng.normal();
    b.count = 50;
    means.push_back(b.sum / 50);
  }
  const double mean = std::accumulate(means.begin(), means.end(), 0.0) / 16;
  double var = 0;
  for (double m : means) var += (m - mean) * (m - mean) / 15;
  const auto error = jackknife_errors(blocks, [](const Sums& s) { return std::vector<double>{s.sum / s.count}; });
  EXPECT_NEAR(error[0], std::sqrt(var / 16), 1e-12);
  EXPECT_TRUE(std::isnan(
      jackknife_errors(std::vector<Sums>(1, blocks[0]), [](const Sums& s) { return std::vector<double>{s.sum}; })[0]));
}

}  // namespace
}  // namespace granflow
