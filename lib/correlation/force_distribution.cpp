#include "correlation/force_distribution.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "core/error.hpp"
#include "correlation/force_correlation.hpp"
#include "statistics/bootstrap.hpp"

namespace granflow::correlation {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Histogram of F/mean over all blocks but `skip` (−1: none), as a density normalised by
// the number of samples counted (those beyond the last bin included).
std::vector<double> density(const BlockSamples& blocks, double mean, double width, int bins, std::ptrdiff_t skip) {
  std::vector<double> counts(bins, 0.0);
  double samples = 0;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    if (std::ptrdiff_t(b) == skip) continue;
    samples += double(blocks[b].size());
    for (float force : blocks[b]) {
      const double f = force / mean;
      if (f >= 0 && f < bins * width) ++counts[std::min(int(f / width), bins - 1)];
    }
  }
  if (!(samples > 0) || !(mean > 0)) return std::vector<double>(bins, kNaN);
  for (double& c : counts) c /= samples * width;
  return counts;
}

// The reflected kernel density estimate of the header, on the grid m·δ, from a histogram
// with bins [kδ, (k+1)δ).
class ReflectedKde {
 public:
  ReflectedKde(double bandwidth, double delta) : reach_(int(std::ceil(6 * bandwidth / delta))) {
    // kernel_[j + reach_ + 1] = φ((j + ½)δ/h) for j in [−reach−1, reach].
    for (int j = -reach_ - 1; j <= reach_; ++j) {
      const double u = (j + 0.5) * delta / bandwidth;
      kernel_.push_back(std::fabs(u) < 6 ? std::exp(-0.5 * u * u) : 0.0);
    }
  }

  // P̂ at grid point m (unnormalised).
  double at(const std::vector<double>& counts, int m) const {
    const int cells = int(counts.size());
    double p = 0;
    // Kernel at f_i: offset of grid point m from bin centre (k + ½)δ is (j + ½)δ, j = m − k − 1.
    for (int k = std::max(0, m - 1 - reach_); k <= std::min(cells - 1, m + reach_); ++k)
      p += counts[k] * kernel_[m - k - 1 + reach_ + 1];
    // Mirror image at −f_i: offset (m + k + ½)δ, j = m + k.
    for (int k = 0; k <= std::min(cells - 1, reach_ - m); ++k) p += counts[k] * kernel_[m + k + reach_ + 1];
    return p;
  }

 private:
  int reach_;
  std::vector<double> kernel_;
};

}  // namespace

void check_force_bins(double bin_width, double max_f, double bandwidth) {
  auto number = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return std::string(buf);
  };
  const double bins = std::floor(max_f / bin_width + 1e-9), cells = std::floor(max_f / (bandwidth / 10));
  if (!(bins <= kMaxForceBins))
    throw UsageError("option --force-bin-width: " + number(bin_width) + " gives " + number(bins) +
                     " bins of P(f) up to --force-max " + number(max_f) + "; use at most " + number(kMaxForceBins));
  if (!(cells <= kMaxForceBins))
    throw UsageError("option --kde-bandwidth: " + number(bandwidth) + " gives " + number(cells) +
                     " grid points of the density estimate (10 per bandwidth) up to --force-max " + number(max_f) +
                     "; use at most " + number(kMaxForceBins));
}

Distribution force_distribution(const BlockSamples& blocks, double bin_width, double max_f) {
  const int bins = std::max(1, int(std::floor(max_f / bin_width + 1e-9)));
  Distribution d;
  for (int k = 0; k < bins; ++k) d.centre.push_back((k + 0.5) * bin_width);
  std::vector<double> sum(blocks.size(), 0.0), count(blocks.size(), 0.0);
  double total = 0, n = 0;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    for (float force : blocks[b]) sum[b] += force;
    count[b] = double(blocks[b].size());
    total += sum[b];
    n += count[b];
  }
  d.samples = std::size_t(n);
  d.mean = n > 0 ? total / n : kNaN;
  d.density = density(blocks, d.mean, bin_width, bins, -1);
  d.error.assign(bins, kNaN);
  const std::size_t nb = blocks.size();
  if (nb < 2) return d;
  std::vector<std::vector<double>> left_out;
  std::vector<double> means;
  for (std::size_t b = 0; b < nb; ++b) {
    const double mean = n - count[b] > 0 ? (total - sum[b]) / (n - count[b]) : kNaN;
    means.push_back(mean);
    left_out.push_back(density(blocks, mean, bin_width, bins, std::ptrdiff_t(b)));
  }
  auto spread = [&](auto value) {
    double mean = 0, sum2 = 0;
    for (std::size_t b = 0; b < nb; ++b) mean += value(b) / double(nb);
    for (std::size_t b = 0; b < nb; ++b) sum2 += (value(b) - mean) * (value(b) - mean);
    return std::sqrt(double(nb - 1) / double(nb) * sum2);
  };
  for (int k = 0; k < bins; ++k) d.error[k] = spread([&](std::size_t b) { return left_out[b][k]; });
  d.mean_error = spread([&](std::size_t b) { return means[b]; });
  return d;
}

PeakDecision decide_peak(const BlockSamples& blocks, double bandwidth, double max_f, int replicates,
                         std::uint64_t seed) {
  PeakDecision decision;
  double total = 0, n = 0;
  for (const auto& block : blocks) {
    for (float force : block) total += force;
    n += double(block.size());
  }
  if (!(n > 0) || !(total > 0)) return decision;
  const double mean = total / n, delta = bandwidth / 10;
  const int cells = std::max(1, int(std::floor(max_f / delta)));
  std::vector<std::vector<double>> counts(blocks.size(), std::vector<double>(cells, 0.0));
  for (std::size_t b = 0; b < blocks.size(); ++b)
    for (float force : blocks[b]) {
      const double f = force / mean;
      if (f >= 0 && f < cells * delta) ++counts[b][std::min(int(f / delta), cells - 1)];
    }
  const ReflectedKde kde(bandwidth, delta);
  const int probe = std::min(30, cells - 1);  // the grid point f = 3h
  auto rises = [&](const std::vector<double>& c) { return kde.at(c, probe) > kde.at(c, 0); };
  std::vector<double> pooled(cells, 0.0);
  for (const auto& c : counts)
    for (int k = 0; k < cells; ++k) pooled[k] += c[k];
  decision.peak = rises(pooled) ? 1 : 0;
  auto mode_cell = [&](const std::vector<double>& c) {
    int best = 0;
    double best_value = -1;
    for (int m = 0; m < cells; ++m)
      if (const double p = kde.at(c, m); p > best_value) {
        best_value = p;
        best = m;
      }
    return best;
  };
  const int mode = mode_cell(pooled);
  const double mode_value = kde.at(pooled, mode);
  decision.mode = mode * delta;
  decision.ratio = mode_value > 0 ? kde.at(pooled, 0) / mode_value : PeakDecision::kNaN;
  // The bootstrap over blocks: pooled histograms of blocks drawn with replacement.
  auto pool = [&](std::span<const std::size_t> draws) {
    std::fill(pooled.begin(), pooled.end(), 0.0);
    for (std::size_t b : draws)
      for (int k = 0; k < cells; ++k) pooled[k] += counts[b][k];
  };
  decision.confidence = bootstrap_agreement(blocks.size(), replicates, seed, [&](std::span<const std::size_t> draws) {
    pool(draws);
    return (rises(pooled) ? 1 : 0) == decision.peak;
  });
  if (blocks.size() < 2 || replicates < 2) return decision;
  double mode_sum = 0, mode_sum2 = 0;
  block_bootstrap(blocks.size(), replicates, seed, [&](std::span<const std::size_t> draws) {
    pool(draws);
    const double f = mode_cell(pooled) * delta;
    mode_sum += f;
    mode_sum2 += f * f;
  });
  const double mean_mode = mode_sum / replicates;
  decision.mode_error = std::sqrt(std::max(0.0, (mode_sum2 - replicates * mean_mode * mean_mode) / (replicates - 1)));
  return decision;
}

}  // namespace granflow::correlation
