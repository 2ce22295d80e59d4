#include "statistics/python_arithmetic.hpp"

#include <math.h>  // sqrtf128: glibc's square root in IEEE binary128

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#if !(defined(__GLIBC__) && __HAVE_FLOAT128 && __GLIBC_USE(IEC_60559_TYPES_EXT))
#error "python_hypot() needs glibc's _Float128 functions (sqrtf128)"
#endif

namespace granflow {

namespace {

constexpr std::size_t kChunk = 8192;         // numpy's default buffer size (np.getbufsize())
constexpr std::size_t kPairwiseBlock = 128;  // numpy's PW_BLOCKSIZE

double pairwise(const double* a, std::size_t n) {
  if (n < 8) {
    double sum = 0.0;
    for (std::size_t i = 0; i < n; ++i) sum += a[i];
    return sum;
  }
  if (n <= kPairwiseBlock) {
    double r[8];
    for (int j = 0; j < 8; ++j) r[j] = a[j];
    std::size_t i = 8;
    for (; i < n - n % 8; i += 8)
      for (int j = 0; j < 8; ++j) r[j] += a[i + j];
    double sum = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]));
    for (; i < n; ++i) sum += a[i];
    return sum;
  }
  std::size_t half = n / 2;
  half -= half % 8;
  return pairwise(a, half) + pairwise(a + half, n - half);
}

}  // namespace

double numpy_sum(std::span<const double> x) {
  double sum = 0.0;
  for (std::size_t start = 0; start < x.size(); start += kChunk)
    sum += pairwise(x.data() + start, std::min(kChunk, x.size() - start));
  return sum;
}

double numpy_mean(std::span<const double> x) {
  if (x.empty()) return std::numeric_limits<double>::quiet_NaN();
  return numpy_sum(x) / double(x.size());
}

double python_hypot(double a, double b) {
  if (std::isinf(a) || std::isinf(b)) return std::numeric_limits<double>::infinity();
  // The squares are exact in binary128 (2 × 53 ≤ 113 bits) and their sum is rounded once,
  // 60 bits below a double's; rounding the binary128 root to a double can then differ from
  // the correctly rounded result only when the exact root lies within 2⁻¹¹² (relative) of a
  // midpoint between doubles without being one.
  const _Float128 qa = a, qb = b;
  return double(sqrtf128(qa * qa + qb * qb));
}

}  // namespace granflow
