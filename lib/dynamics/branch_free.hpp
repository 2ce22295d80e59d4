#pragma once
// Branch-free forms of comparisons in the engine's hot loops. Whether a contact bears,
// whether a listed pair is a candidate, the sign of a separation: each is close to a coin
// toss, and GCC compiles the plain forms to compare-and-jump, which then mispredicts about
// every other time. Each function gives exactly the number (every bit) of the plain form
// named beside it, so that the engine's trajectories do not depend on which is used
// (tests/unit/test_branch_free.cpp checks this on special and random values).
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#ifdef __SSE2__
#include <emmintrin.h>
#endif

namespace granflow {

// std::max(0.0, x): x if x > 0, else +0 (also for −0 and NaN).
inline double positive_part(double x) {
#ifdef __SSE2__
  return _mm_cvtsd_f64(_mm_max_sd(_mm_set_sd(x), _mm_setzero_pd()));  // x > 0 ? x : second operand
#else
  return std::max(0.0, x);
#endif
}

// p > 0 ? 1 : 0 for p ≥ +0, as positive_part() returns (not for −0 or negative p).
inline int bearing(double p) {
  const std::uint64_t bits = std::bit_cast<std::uint64_t>(p);
  return int((bits | (0 - bits)) >> 63);
}

// cond ? a : b.
inline double pick(bool cond, double a, double b) {
  const std::uint64_t mask = 0 - std::uint64_t(cond);
  return std::bit_cast<double>((std::bit_cast<std::uint64_t>(a) & mask) | (std::bit_cast<std::uint64_t>(b) & ~mask));
}

// int(x + (x < 0 ? −½ : ½)), i.e. std::round(x) for |x| < 2³¹ except within an ulp of ±½
// (the engine only rounds separations over the box size, far from ½).
inline int round_to_int(double x) { return int(x + std::copysign(0.5, x)); }

}  // namespace granflow
