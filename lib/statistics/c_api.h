/* C ABI of the statistics (statistics/steady.hpp, statistics/blocking.hpp,
 * statistics/jackknife.hpp) for callers in other languages: python/granflow/statistics.py
 * loads it with ctypes from the shared library libgranflow_statistics.so (<build>/lib, or the
 * copy `pip install ./python` builds into the package). Every function returns a GF_STAT_*
 * code and writes its results through the pointers only on GF_STAT_OK; no C++ exception
 * crosses it. */
#ifndef GRANFLOW_STATISTICS_C_API_H
#define GRANFLOW_STATISTICS_C_API_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

enum {
  GF_STAT_OK = 0,
  GF_STAT_TOO_FEW_SAMPLES = 1, /* blocking: fewer than gf_stat_blocking_min_samples() values */
  GF_STAT_BAD_ARGUMENT = 2,    /* a null pointer where values are needed */
  GF_STAT_FAILED = 3           /* anything else (out of memory) */
};

/* Version of this interface: changes whenever a signature or a return code does, or a
 * function is added (2: gf_stat_jackknife_errors). */
int gf_stat_abi_version(void);
size_t gf_stat_blocking_min_samples(void);

/* mser_truncation() of x[0..n). */
int gf_stat_mser_truncation(const double* x, size_t n, size_t* truncation);

/* mser_first_row() of `count` series of `length` rows each, stored one after the other
 * (row-major count × length). */
int gf_stat_mser_first_row(const double* series, size_t count, size_t length, size_t blocks, size_t* row);

/* blocking_error() of x[0..n): the standard error, the blocks at the level read, and
 * whether the plateau was found (1) or the error is a lower bound (0). */
int gf_stat_blocking_error(const double* x, size_t n, double* error, size_t* blocks, int* plateau);

/* halves_change() of x[0..n). */
int gf_stat_halves_change(const double* x, size_t n, double* change, double* error);

/* numpy_sum() of x[0..n): the summation order of the means above. */
int gf_stat_numpy_sum(const double* x, size_t n, double* sum);

/* The estimator of gf_stat_jackknife_errors(): from the `width` sums `sums`, writes
 * `components` estimates to `estimates` and returns 0; any other value stops the jackknife
 * (which then returns GF_STAT_FAILED). `context` is the caller's, passed through. */
typedef int (*gf_stat_estimator)(const double* sums, size_t width, double* estimates, size_t components,
                                 void* context);

/* jackknife_errors() of `count` blocks of `width` sums each, stored one after the other
 * (row-major count × width; blocks are added element-wise): the `components` standard
 * errors of estimate() over the blocks left out one at a time, NaN with a single block.
 * GF_STAT_BAD_ARGUMENT for no block. */
int gf_stat_jackknife_errors(const double* blocks, size_t count, size_t width, size_t components,
                             gf_stat_estimator estimate, void* context, double* errors);

#ifdef __cplusplus
}
#endif

#endif
