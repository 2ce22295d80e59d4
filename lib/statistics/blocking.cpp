#include "statistics/blocking.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "statistics/python_arithmetic.hpp"

namespace granflow {

double chi2_quantile_99(std::size_t dof) {
  constexpr double z = 2.3263478740408408;  // 99 % quantile of the standard normal
  const double a = 2.0 / (9.0 * double(dof));
  // pow(·, 3.0), not a product: the cube rounded as Python's ** 3 rounds it.
  return double(dof) * std::pow(1.0 - a + z * std::sqrt(a), 3.0);
}

Blocking blocking_error(std::span<const double> samples) {
  if (samples.size() < kBlockingMinSamples)
    throw std::invalid_argument("blocking needs at least " + std::to_string(kBlockingMinSamples) + " samples, got " +
                                std::to_string(samples.size()));
  std::vector<double> x(samples.begin(), samples.end()), d, product;
  std::vector<double> se2, stat;
  std::vector<std::size_t> count;
  std::size_t offset = 0, m = x.size();  // the level's values are x[offset, offset + m)
  while (m >= 2) {
    if (m % 2) {  // drop the oldest value so that the pairs stay aligned
      ++offset;
      --m;
    }
    const std::span<const double> level(x.data() + offset, m);
    const double mean = numpy_mean(level);
    d.resize(m);
    product.resize(m);
    for (std::size_t i = 0; i < m; ++i) d[i] = level[i] - mean;
    for (std::size_t i = 0; i < m; ++i) product[i] = d[i] * d[i];
    const double var = numpy_mean(product);
    se2.push_back(var / double(m - 1));
    count.push_back(m);
    for (std::size_t i = 0; i + 1 < m; ++i) product[i] = d[i] * d[i + 1];
    const double lag = numpy_mean(std::span<const double>(product.data(), m - 1));
    const double dm = double(m);
    const double gamma = double(m - 1) * var / (dm * dm) + lag;
    stat.push_back(var == 0 ? 0.0 : dm * (gamma * gamma) / (var * var));
    for (std::size_t i = 0; i < m / 2; ++i) x[i] = 0.5 * (level[2 * i] + level[2 * i + 1]);
    offset = 0;
    m /= 2;
  }
  const std::size_t levels = se2.size();
  // tail[j]: Σ of the statistics over levels ≥ j, summed from the last level down.
  std::vector<double> tail(levels);
  double sum = 0;
  for (std::size_t j = levels; j-- > 0;) tail[j] = sum += stat[j];
  std::size_t usable = 0;
  for (std::size_t j = 0; j < levels; ++j)
    if (count[j] >= kBlockingMinBlocks) usable = j;
  for (std::size_t j = 0; j <= usable; ++j)
    if (tail[j] < chi2_quantile_99(levels - j)) {
      const std::size_t k = std::min(j + 1, usable);
      return {std::sqrt(se2[k]), count[k], true};
    }
  return {std::sqrt(se2[usable]), count[usable], false};
}

}  // namespace granflow
