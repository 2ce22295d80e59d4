// Force distributions and the peak decision, ν_bc crossings and contact clusters
// (lib/correlation), on synthetic data with known answers. The block jackknife and
// bootstrap they use are tested in test_jackknife.cpp and test_bootstrap.cpp.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.hpp"
#include "core/random.hpp"
#include "correlation/clusters.hpp"
#include "correlation/force_distribution.hpp"
#include "correlation/sweep.hpp"

using namespace granflow;
using namespace granflow::correlation;

namespace {
// Blocks of samples of a distribution with mean `scale` (any positive sampler).
template <class Draw>
BlockSamples blocks_of(int blocks, int per_block, std::uint64_t seed, Draw draw) {
  Rng rng(seed);
  BlockSamples out(blocks);
  for (auto& b : out)
    for (int i = 0; i < per_block; ++i) b.push_back(float(draw(rng)));
  return out;
}
double exponential(Rng& rng) { return -std::log(1 - rng.uniform()); }
double gamma3(Rng& rng) { return exponential(rng) + exponential(rng) + exponential(rng); }  // mode 2/3 of the mean
}  // namespace

TEST(ForceDistribution, NormalisedHistogramOfAnExponential) {
  // F exponential with mean 7: f = F/⟨F⟩ has P(f) = e^{−f}.
  const BlockSamples b = blocks_of(20, 5000, 1, [](Rng& r) { return 7 * exponential(r); });
  const Distribution d = force_distribution(b, 0.1, 8);
  EXPECT_EQ(d.samples, 100000u);
  EXPECT_NEAR(d.mean, 7, 0.1);
  EXPECT_NEAR(d.mean_error, 7 / std::sqrt(1e5), 0.01);
  double integral = 0;
  for (std::size_t k = 0; k < d.centre.size(); ++k) {
    integral += d.density[k] * 0.1;
    // Bin average of e^{−f} over [f − 0.05, f + 0.05].
    const double expected = std::exp(-d.centre[k]) * std::sinh(0.05) / 0.05;
    EXPECT_NEAR(d.density[k], expected, 5 * d.error[k] + 1e-3) << d.centre[k];
    // Independent samples: the jackknife error is near the binomial one.
    const double binomial = std::sqrt(expected * 0.1 * (1 - expected * 0.1) / 1e5) / 0.1;
    if (d.centre[k] < 3) {
      EXPECT_NEAR(d.error[k] / binomial, 1, 0.5) << d.centre[k];
    }
  }
  EXPECT_NEAR(integral, 1 - std::exp(-8.0 * 7 / d.mean), 2e-3);  // the tail beyond f = 8 is missing
}

TEST(ForceDistribution, OneBlockHasNoErrors) {
  const Distribution d = force_distribution(blocks_of(1, 100, 2, exponential), 0.5, 5);
  EXPECT_TRUE(std::isnan(d.error[0]));
  EXPECT_TRUE(std::isnan(d.mean_error));
  const Distribution empty = force_distribution(BlockSamples(3), 0.5, 5);
  EXPECT_TRUE(std::isnan(empty.density[0]));
}

TEST(PeakDecision, PeakedAndMonotonicDistributions) {
  // A gamma distribution of shape 3 peaks at f = 2/3; an exponential and a half-normal are
  // largest at f = 0 (the half-normal with zero slope there, the hardest case).
  const PeakDecision peaked = decide_peak(blocks_of(20, 2000, 3, gamma3), 0.1, 10, 200, 1);
  EXPECT_EQ(peaked.peak, 1);
  EXPECT_NEAR(peaked.mode, 2.0 / 3, 0.1);
  EXPECT_GE(peaked.confidence, 0.95);
  EXPECT_LT(peaked.ratio, 0.5);
  const PeakDecision falling = decide_peak(blocks_of(20, 2000, 4, exponential), 0.1, 10, 200, 1);
  EXPECT_EQ(falling.peak, 0);
  EXPECT_EQ(falling.mode, 0);
  EXPECT_DOUBLE_EQ(falling.ratio, 1);
  EXPECT_GE(falling.confidence, 0.95);
  const PeakDecision flat_top =
      decide_peak(blocks_of(20, 2000, 5, [](Rng& r) { return std::fabs(r.normal()); }), 0.1, 10, 200, 1);
  EXPECT_EQ(flat_top.peak, 0);
  EXPECT_GE(flat_top.confidence, 0.95);
  // A weak peak at f ≈ 0.4 (X + 0.3Y, X, Y exponential: zero density at 0) from few samples
  // is still found, less surely than from many.
  auto weak = [](Rng& r) { return exponential(r) + 0.3 * exponential(r); };
  const PeakDecision many = decide_peak(blocks_of(20, 2000, 6, weak), 0.1, 10, 200, 1);
  EXPECT_EQ(many.peak, 1);
  EXPECT_EQ(many.confidence, 1);
  EXPECT_NEAR(many.mode, 0.4, 0.1);
}

TEST(PeakDecision, ModeErrorIsTheSpreadOfTheModeOverIndependentSamples) {
  // The bootstrap error of the mode against the spread of the modes of 40 independent
  // samples of the same gamma(3) (20 blocks of 500): the two agree within the roughness of a
  // bootstrap of a maximum (a factor 1.6 either way); a distribution largest at 0 has a mode
  // error of 0 (every replicate's mode is 0).
  double sum = 0, sum2 = 0, error = 0;
  const int samples = 40;
  for (int s = 0; s < samples; ++s) {
    const PeakDecision d = decide_peak(blocks_of(20, 500, 100 + s, gamma3), 0.1, 10, 200, 1);
    sum += d.mode;
    sum2 += d.mode * d.mode;
    error += d.mode_error / samples;
  }
  const double spread = std::sqrt((sum2 - sum * sum / samples) / (samples - 1));
  EXPECT_GT(spread, 0.01);
  EXPECT_GT(error, spread / 1.6);
  EXPECT_LT(error, spread * 1.6);
  EXPECT_EQ(decide_peak(blocks_of(20, 2000, 4, exponential), 0.1, 10, 200, 1).mode_error, 0);
  EXPECT_TRUE(std::isnan(decide_peak(blocks_of(1, 1000, 7, gamma3), 0.1, 10, 200, 1).mode_error));
}

TEST(PeakDecision, Degenerate) {
  EXPECT_TRUE(std::isnan(decide_peak(blocks_of(1, 1000, 7, gamma3), 0.1, 10, 200, 1).confidence));
  EXPECT_EQ(decide_peak(BlockSamples(4), 0.1, 10, 200, 1).peak, -1);
}

TEST(Sweep, CrossingInterpolatedWithPropagatedError) {
  const double xi_el = 1.0, xi_el_error = 0.01, c = 1.25;
  std::vector<SweepPoint> points = {
      {0.60, 0.5, 0, 1.00, 0.02},   {0.70, 0.5, 0, 1.20, 0.02},   {0.80, 0.5, 0, 1.50, 0.03},  // crosses
      {0.60, 0.9, 0, 1.30, 0.02},   {0.70, 0.9, 0, 1.40, 0.02},                                // all above
      {0.60, 0.0, 0.4, 1.10, 0.02}, {0.80, 0.0, 0.4, 1.20, 0.02},                              // all below
      {0.70, 0.2, 0, 1.00, 0.02},                                                              // one ν
      {0.60, 0.25, 0, 1.40, 0.02},  {0.70, 0.25, 0, 1.10, 0.02},                               // downward
      {0.70, 0.5, 0, 1.20, 0.02},  // a second run at ν = 0.7, e = 0.5: merged
  };
  const std::vector<Crossing> out = binary_collision_crossings(points, xi_el, xi_el_error, c);
  ASSERT_EQ(out.size(), 5u);  // one per (e, μ)
  const Crossing* e05 = nullptr;
  for (const auto& x : out)
    if (x.restitution == 0.5) e05 = &x;
  ASSERT_NE(e05, nullptr);
  EXPECT_EQ(e05->status, CrossingStatus::bracketed);
  EXPECT_EQ(e05->runs, 4);
  EXPECT_EQ(e05->sign_changes, 1);
  EXPECT_NEAR(e05->nu_bc, 0.70 + 0.05 / 0.30 * 0.10, 1e-12);
  EXPECT_DOUBLE_EQ(e05->nu_below, 0.70);
  EXPECT_DOUBLE_EQ(e05->nu_above, 0.80);
  // Error by finite differences of the interpolation formula (merged ν = 0.7: σ = 0.02/√2).
  auto nu = [&](double x1, double x2, double el) { return 0.70 + (c * el - x1) * 0.10 / (x2 - x1); };
  const double h = 1e-7, s1 = 0.02 / std::sqrt(2.0), s2 = 0.03;
  const double d1 = (nu(1.2 + h, 1.5, 1) - nu(1.2 - h, 1.5, 1)) / (2 * h);
  const double d2 = (nu(1.2, 1.5 + h, 1) - nu(1.2, 1.5 - h, 1)) / (2 * h);
  const double de = (nu(1.2, 1.5, 1 + h) - nu(1.2, 1.5, 1 - h)) / (2 * h);
  EXPECT_NEAR(e05->nu_bc_error, std::sqrt(d1 * d1 * s1 * s1 + d2 * d2 * s2 * s2 + de * de * xi_el_error * xi_el_error),
              1e-6);
  for (const auto& x : out) {
    if (x.restitution == 0.9) {
      EXPECT_EQ(x.status, CrossingStatus::all_above);
    }
    if (x.restitution == 0.0) {
      EXPECT_EQ(x.status, CrossingStatus::all_below);
    }
    if (x.restitution == 0.2) {
      EXPECT_EQ(x.status, CrossingStatus::too_few);
    }
    if (x.restitution == 0.25) {
      EXPECT_EQ(x.status, CrossingStatus::only_downward);
    }
    if (x.status != CrossingStatus::bracketed) {
      EXPECT_TRUE(std::isnan(x.nu_bc));
    }
  }
}

TEST(ContactClusters, ConnectedComponentsBySize) {
  // Grains 0-1-2 (a chain), 5-6, 7-8-9-4 (a star through 7), 3 alone.
  const std::vector<std::array<std::int32_t, 2>> pairs = {{0, 1}, {2, 1}, {5, 6}, {7, 8}, {9, 7}, {4, 7}, {1, 0}};
  const std::vector<std::int32_t> label = contact_clusters(10, pairs);
  const std::vector<std::int32_t> expected = {2, 2, 2, 0, 1, 3, 3, 1, 1, 1};
  EXPECT_EQ(label, expected);
  EXPECT_THROW(contact_clusters(5, {{0, 5}}), UsageError);
  EXPECT_EQ(contact_clusters(3, {}), std::vector<std::int32_t>(3, 0));
}
