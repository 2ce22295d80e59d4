// The C ABI of statistics/c_api.h over the C++ functions: every call catches what they
// throw and returns a code, since an exception must not unwind into a foreign caller.
#include "statistics/c_api.h"

#include <algorithm>
#include <new>
#include <span>
#include <stdexcept>
#include <vector>

#include "statistics/blocking.hpp"
#include "statistics/jackknife.hpp"
#include "statistics/python_arithmetic.hpp"
#include "statistics/steady.hpp"

#define GF_STAT_EXPORT __attribute__((visibility("default")))

namespace {

template <class F>
int guarded(F&& f) {
  try {
    f();
    return GF_STAT_OK;
  } catch (const std::invalid_argument&) {
    return GF_STAT_TOO_FEW_SAMPLES;
  } catch (...) {
    return GF_STAT_FAILED;
  }
}

std::span<const double> values(const double* x, std::size_t n) { return {n ? x : nullptr, n}; }

// One block's sums for jackknife_errors(), which needs copy and +=.
struct BlockSums {
  std::vector<double> sums;
  BlockSums& operator+=(const BlockSums& other) {
    for (std::size_t k = 0; k < sums.size(); ++k) sums[k] += other.sums[k];
    return *this;
  }
};

struct EstimatorFailed {};

}  // namespace

extern "C" {

GF_STAT_EXPORT int gf_stat_abi_version(void) { return 2; }

GF_STAT_EXPORT size_t gf_stat_blocking_min_samples(void) { return granflow::kBlockingMinSamples; }

GF_STAT_EXPORT int gf_stat_mser_truncation(const double* x, size_t n, size_t* truncation) {
  if ((n && !x) || !truncation) return GF_STAT_BAD_ARGUMENT;
  return guarded([&] { *truncation = granflow::mser_truncation(values(x, n)); });
}

GF_STAT_EXPORT int gf_stat_mser_first_row(const double* series, size_t count, size_t length, size_t blocks,
                                          size_t* row) {
  if ((count && length && !series) || !row) return GF_STAT_BAD_ARGUMENT;
  return guarded([&] {
    std::vector<std::vector<double>> s(count);
    for (size_t k = 0; k < count; ++k) s[k].assign(series + k * length, series + (k + 1) * length);
    *row = granflow::mser_first_row(s, blocks);
  });
}

GF_STAT_EXPORT int gf_stat_blocking_error(const double* x, size_t n, double* error, size_t* blocks, int* plateau) {
  if ((n && !x) || !error || !blocks || !plateau) return GF_STAT_BAD_ARGUMENT;
  return guarded([&] {
    const granflow::Blocking b = granflow::blocking_error(values(x, n));
    *error = b.error;
    *blocks = b.blocks;
    *plateau = b.plateau ? 1 : 0;
  });
}

GF_STAT_EXPORT int gf_stat_halves_change(const double* x, size_t n, double* change, double* error) {
  if ((n && !x) || !change || !error) return GF_STAT_BAD_ARGUMENT;
  return guarded([&] {
    const granflow::HalvesChange h = granflow::halves_change(values(x, n));
    *change = h.change;
    *error = h.error;
  });
}

GF_STAT_EXPORT int gf_stat_numpy_sum(const double* x, size_t n, double* sum) {
  if ((n && !x) || !sum) return GF_STAT_BAD_ARGUMENT;
  return guarded([&] { *sum = granflow::numpy_sum(values(x, n)); });
}

GF_STAT_EXPORT int gf_stat_jackknife_errors(const double* blocks, size_t count, size_t width, size_t components,
                                            gf_stat_estimator estimate, void* context, double* errors) {
  if (!count || (width && !blocks) || !estimate || (components && !errors)) return GF_STAT_BAD_ARGUMENT;
  return guarded([&] {
    std::vector<BlockSums> b(count);
    for (size_t k = 0; k < count; ++k) b[k].sums.assign(blocks + k * width, blocks + (k + 1) * width);
    const std::vector<double> e = granflow::jackknife_errors(b, [&](const BlockSums& s) {
      std::vector<double> out(components);
      if (estimate(s.sums.data(), width, out.data(), components, context) != 0) throw EstimatorFailed{};
      return out;
    });
    std::copy(e.begin(), e.end(), errors);
  });
}

}  // extern "C"
