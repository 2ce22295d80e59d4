#include "statistics/steady.hpp"

#include <algorithm>
#include <cmath>

#include "statistics/blocking.hpp"
#include "statistics/python_arithmetic.hpp"

namespace granflow {

namespace {

struct MeanError {
  double mean, error;
};

// Mean and standard error of independent values (n ≥ 2).
MeanError mean_error(std::span<const double> x) {
  const double n = double(x.size());
  double mean = 0;
  for (double v : x) mean += v;
  mean /= n;
  double ss = 0;
  for (double v : x) ss += (v - mean) * (v - mean);
  return {mean, std::sqrt(ss / (n - 1) / n)};
}

}  // namespace

std::size_t mser_truncation(std::span<const double> x) {
  const std::size_t n = x.size();
  if (n < 2) return 0;
  // Suffix sums give every candidate's statistic in O(n); about the overall mean, so
  // that a small scatter on a large mean does not cancel away.
  double mean = 0;
  for (double v : x) mean += v;
  mean /= double(n);
  std::vector<double> sum(n + 1, 0.0), sum2(n + 1, 0.0);
  for (std::size_t i = n; i-- > 0;) {
    sum[i] = sum[i + 1] + (x[i] - mean);
    sum2[i] = sum2[i + 1] + (x[i] - mean) * (x[i] - mean);
  }
  std::size_t best = 0;
  double best_value = INFINITY;
  for (std::size_t d = 0; d <= n / 2; ++d) {
    const double m = double(n - d);
    const double ss = std::max(0.0, sum2[d] - sum[d] * sum[d] / m);
    const double value = ss / (m * m);
    if (value < best_value) {
      best_value = value;
      best = d;
    }
  }
  return best;
}

bool halves_agree(std::span<const double> x, double sigmas) {
  const std::size_t half = x.size() / 2;
  if (half < 2) return false;
  const MeanError a = mean_error(x.first(half)), b = mean_error(x.last(half));
  return std::fabs(a.mean - b.mean) <= sigmas * std::hypot(a.error, b.error);
}

HalvesChange halves_change(std::span<const double> x) {
  const std::size_t half = x.size() / 2;
  const std::span<const double> first = x.first(half), second = x.last(half);
  const double change = numpy_mean(second) - numpy_mean(first);
  return {change, python_hypot(blocking_error(first).error, blocking_error(second).error)};
}

SteadyState steady_from(const std::vector<std::vector<double>>& series, std::size_t first) {
  SteadyState s;
  s.first = first;
  s.steady = true;
  for (const auto& x : series)
    s.steady = s.steady && first <= x.size() && halves_agree(std::span<const double>(x).subspan(first));
  return s;
}

std::size_t mser_first_row(const std::vector<std::vector<double>>& series, std::size_t blocks) {
  if (series.empty() || series.front().empty() || blocks == 0) return 0;
  const std::size_t rows = std::max<std::size_t>(1, series.front().size() / blocks);
  const std::size_t count = series.front().size() / rows;
  std::size_t first = 0;
  std::vector<double> means(count);
  for (const auto& x : series) {
    for (std::size_t b = 0; b < count; ++b) {
      double sum = 0;
      for (std::size_t r = 0; r < rows; ++r) sum += x[b * rows + r];
      means[b] = sum / double(rows);
    }
    first = std::max(first, mser_truncation(means) * rows);
  }
  return first;
}

SteadyState detect_steady(const std::vector<std::vector<double>>& series) {
  std::vector<std::size_t> truncation;
  std::size_t first = 0;
  for (const auto& x : series) {
    truncation.push_back(mser_truncation(x));
    first = std::max(first, truncation.back());
  }
  SteadyState s = steady_from(series, first);
  s.truncation = std::move(truncation);
  return s;
}

}  // namespace granflow
