#pragma once
// Arithmetic in the order and rounding of numpy 1.24 and CPython 3.11, so that the
// statistics the Python tables take from this library (blocking errors, the halves
// change) equal bit for bit the same algorithm written with numpy (np.mean, math.hypot):
// a table does not depend on which side computes it.
#include <span>

namespace granflow {

// Σ x in the order of np.add.reduce (np.sum, np.mean) on a contiguous float64 array: the
// array in chunks of 8192 values (the size of numpy's iterator buffer), each chunk's sum
// added in turn to 0.0; within a chunk, pairwise summation: fewer than 8 values in order;
// up to 128 in 8 interleaved partial sums, combined as ((r0 + r1) + (r2 + r3)) +
// ((r4 + r5) + (r6 + r7)), then the values past the last multiple of 8 in order; a longer
// chunk split at half its length rounded down to a multiple of 8, each part summed so.
// Checked against numpy for every length up to 1000 and lengths past 8192, 16384, 10⁵.
double numpy_sum(std::span<const double> x);

// np.mean: numpy_sum(x) / n (NaN for an empty x, as numpy's 0/0).
double numpy_mean(std::span<const double> x);

// √(a² + b²) correctly rounded, as CPython's math.hypot returns it (the C library's hypot
// is off by an ulp in about 1 case in 400). Infinite when either is infinite.
double python_hypot(double a, double b);

}  // namespace granflow
