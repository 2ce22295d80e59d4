#include "dynamics/sparse_ldl.hpp"

#include "dynamics/capacity.hpp"

#include <algorithm>
#include <cmath>

#include <omp.h>

namespace granflow {

bool SparseLdl::factor(int n, const std::vector<int>& start, const std::vector<int>& row,
                       const std::vector<double>& value, double drop, std::size_t max_fill, int threads) {
  return factor_any(n, start, row, value, nullptr, drop, max_fill, threads);
}

bool SparseLdl::factor(int n, const std::vector<int>& start, const std::vector<int>& row,
                       const std::vector<double>& upper, const std::vector<double>& lower, double drop,
                       std::size_t max_fill, int threads) {
  return factor_any(n, start, row, upper, lower.data(), drop, max_fill, threads);
}

bool SparseLdl::factor_any(int n, const std::vector<int>& start, const std::vector<int>& row,
                           const std::vector<double>& value, const double* lower, double drop, std::size_t max_fill,
                           int threads) {
  unsymmetric_ = lower != nullptr;
  // Symbolic: elimination tree (parent_) and the nonzero count of each column of L.
  // Gives up as soon as the fill exceeds max_fill, so that a refusal costs no more than that.
  parent_.assign(n, -1);
  flag_.assign(n, -1);
  count_.assign(n, 0);
  std::size_t fill = 0;
  for (int k = 0; k < n; ++k) {
    flag_[k] = k;
    for (int p = start[k]; p < start[k + 1]; ++p)
      for (int i = row[p]; i < k && flag_[i] != k; i = parent_[i]) {
        if (parent_[i] == -1) parent_[i] = k;
        ++count_[i];
        flag_[i] = k;
        ++fill;
      }
    if (fill > max_fill) return false;
  }
  start_.assign(n + 1, 0);
  for (int k = 0; k < n; ++k) start_[k + 1] = start_[k] + count_[k];

  // Numeric, row by row: row k of L solves a triangular system with the rows above,
  // whose nonzero pattern is the union of the tree paths from A's entries in column k.
  fit_capacity(index_, start_[n]);
  fit_capacity(value_, start_[n]);
  index_.resize(start_[n]);
  value_.resize(start_[n]);
  diagonal_.assign(n, 0.0);
  work_.assign(n, 0.0);
  if (unsymmetric_) {
    fit_capacity(upper_value_, start_[n]);
    upper_value_.resize(start_[n]);
    lower_work_.assign(n, 0.0);
  } else {
    upper_value_.clear();
    lower_work_.clear();
  }
  // One instantiation per kind: the symmetric rows keep exactly their operations.
  auto factor_row_any = [&](int k, int* pattern, int size) {
    return unsymmetric_ ? factor_row<true>(k, start.data(), row.data(), value.data(), lower, drop, pattern, size)
                        : factor_row<false>(k, start.data(), row.data(), value.data(), lower, drop, pattern, size);
  };
  pinned_flag_.assign(n, 0);
  pinned_ = 0;
  shared_rows_ = 0;
  // Below this size a parallel factorisation does not pay for its set-up.
  constexpr int kParallelRows = 2000;
  if (threads <= 1 || n < kParallelRows) {
    pattern_.resize(n);
    for (int k = 0; k < n; ++k) pinned_ += factor_row_any(k, pattern_.data(), n);
    return true;
  }
  // Each thread computes the rows of its subtrees in increasing order (all a row reads lies
  // in its own subtree), then one thread the rows above them, in increasing order.
  // A row's pattern lies in its subtree: a thread's scratch need not exceed its share.
  share_out(n, threads);
  std::vector<std::size_t> offset(threads + 1, 0);
  for (int k = 0; k < n; ++k)
    if (bin_[k] >= 0) ++offset[bin_[k] + 1];
  for (int t = 0; t < threads; ++t) {
    shared_rows_ += int(offset[t + 1]);
    offset[t + 1] += offset[t];
  }
  pattern_.resize(std::max<std::size_t>(n, offset[threads]));
  int pinned = 0;
#pragma omp parallel num_threads(threads) reduction(+ : pinned)
  {
    const int t = omp_get_thread_num();
    const int size = int(offset[t + 1] - offset[t]);
    int* pattern = pattern_.data() + offset[t];
    for (int k = 0; k < n; ++k)
      if (bin_[k] == t) pinned += factor_row_any(k, pattern, size);
  }
  for (int k = 0; k < n; ++k)
    if (bin_[k] < 0) pinned += factor_row_any(k, pattern_.data(), n);
  pinned_ = pinned;
  return true;
}

// Row k: y = L⁻¹·A(0:k, k) (the upper column) gives D·U(0:k, k) and, for LDU,
// z = U⁻ᵀ·A(k, 0:k)ᵀ (the lower row) gives L(k, 0:k)·D; the pivot is A(k, k) − Σ z_i·y_i/d_i.
// Both solves follow the same pattern: the union of the tree paths from the column's entries.
template <bool Unsymmetric>
bool SparseLdl::factor_row(int k, const int* start, const int* row, const double* value, const double* lower,
                           double drop, int* pattern, int size) {
  const int last = size;  // the pattern fills pattern[top, last); paths are built from 0 up
  int top = last;
  flag_[k] = k;
  count_[k] = 0;
  double diagonal = 0;
  for (int p = start[k]; p < start[k + 1]; ++p) {
    int i = row[p];
    if (pinned_flag_[i]) continue;  // a pinned unknown's column is zero
    if (i == k) diagonal += value[p];
    work_[i] += value[p];
    if constexpr (Unsymmetric) lower_work_[i] += lower[p];
    int length = 0;
    for (; flag_[i] != k; i = parent_[i]) {
      pattern[length++] = i;
      flag_[i] = k;
    }
    while (length > 0) pattern[--top] = pattern[--length];
  }
  diagonal_[k] = work_[k];
  work_[k] = 0;
  if constexpr (Unsymmetric) lower_work_[k] = 0;
  const int first = top;
  for (; top < last; ++top) {
    const int i = pattern[top];
    const double yi = work_[i];
    work_[i] = 0;
    const int end = start_[i] + count_[i];
    if constexpr (Unsymmetric) {
      const double zi = lower_work_[i];
      lower_work_[i] = 0;
      for (int p = start_[i]; p < end; ++p) {
        work_[index_[p]] -= value_[p] * yi;
        lower_work_[index_[p]] -= upper_value_[p] * zi;
      }
      const double l = zi / diagonal_[i];
      diagonal_[k] -= l * yi;
      index_[end] = k;
      value_[end] = l;
      upper_value_[end] = yi / diagonal_[i];
    } else {
      for (int p = start_[i]; p < end; ++p) work_[index_[p]] -= value_[p] * yi;
      const double l = yi / diagonal_[i];
      diagonal_[k] -= l * yi;
      index_[end] = k;
      value_[end] = l;
    }
    ++count_[i];
  }
  // A pivot that is (nearly) zero marks a dependent unknown: pin it, i.e. make row
  // and column k of the factor those of the identity.
  if constexpr (Unsymmetric) {
    if (std::fabs(diagonal_[k]) > drop * std::fabs(diagonal)) return false;
  } else {
    if (diagonal_[k] > drop * diagonal) return false;
  }
  for (int t = first; t < last; ++t) {
    const int q = start_[pattern[t]] + count_[pattern[t]] - 1;
    value_[q] = 0;
    if constexpr (Unsymmetric) upper_value_[q] = 0;
  }
  diagonal_[k] = 1;
  pinned_flag_[k] = 1;
  return true;
}

void SparseLdl::share_out(int n, int threads) {
  // Work of each subtree, with row k's cost estimated from its column count (the entries
  // later rows read), and the children of each node.
  std::vector<double> work(n);
  std::vector<int> head(n, -1), next(n, -1);
  for (int k = 0; k < n; ++k) work[k] = 1 + 0.5 * double(count_[k]) * double(count_[k]);
  std::vector<int> roots;
  for (int k = 0; k < n; ++k) {
    const int p = parent_[k];
    if (p < 0) {
      roots.push_back(k);
      continue;
    }
    work[p] += work[k];
    next[k] = head[p];
    head[p] = k;
  }
  // Open the heaviest subtree (its root goes to the rows computed last) until no subtree holds
  // more than a thread's share of what is left; then deal them out heaviest first to the
  // least loaded thread.
  bin_.assign(n, -1);
  auto lighter = [&](int a, int b) { return work[a] < work[b] || (work[a] == work[b] && a < b); };
  std::vector<int> open = roots;
  double total = 0;
  for (int r : roots) total += work[r];
  std::make_heap(open.begin(), open.end(), lighter);
  while (!open.empty() && work[open.front()] * threads > total) {
    std::pop_heap(open.begin(), open.end(), lighter);
    const int v = open.back();
    open.pop_back();
    total -= work[v];
    for (int c = head[v]; c >= 0; c = next[c]) {
      open.push_back(c);
      std::push_heap(open.begin(), open.end(), lighter);
      total += work[c];
    }
  }
  std::sort_heap(open.begin(), open.end(), lighter);  // ascending
  std::vector<double> load(threads, 0.0);
  for (auto it = open.rbegin(); it != open.rend(); ++it) {
    const int t = int(std::min_element(load.begin(), load.end()) - load.begin());
    load[t] += work[*it];
    bin_[*it] = t;
  }
  // Every row under a dealt-out root goes with it (parents are numbered after children).
  for (int k = n - 1; k >= 0; --k)
    if (bin_[k] < 0 && parent_[k] >= 0 && bin_[parent_[k]] >= 0) bin_[k] = bin_[parent_[k]];
}

// L·D·U x = b: L (unit lower) by columns in value_, U (unit upper) by rows in upper; for Aᵀ
// the roles of the two arrays swap.
void SparseLdl::substitute(const std::vector<double>& lower, const std::vector<double>& upper,
                           std::vector<double>& x) const {
  const int n = int(diagonal_.size());
  for (int k = 0; k < n; ++k)
    if (pinned_flag_[k]) x[k] = 0;
  for (int j = 0; j < n; ++j)
    for (int p = start_[j]; p < start_[j] + count_[j]; ++p) x[index_[p]] -= lower[p] * x[j];
  for (int j = 0; j < n; ++j) x[j] /= diagonal_[j];
  for (int j = n - 1; j >= 0; --j)
    for (int p = start_[j]; p < start_[j] + count_[j]; ++p) x[j] -= upper[p] * x[index_[p]];
}

void SparseLdl::solve(std::vector<double>& x) const { substitute(value_, unsymmetric_ ? upper_value_ : value_, x); }

void SparseLdl::solve_transposed(std::vector<double>& x) const {
  substitute(unsymmetric_ ? upper_value_ : value_, value_, x);
}

std::size_t SparseLdl::allocated_bytes() const {
  return sizeof(int) * (parent_.capacity() + flag_.capacity() + count_.capacity() + start_.capacity() +
                        index_.capacity() + pattern_.capacity() + bin_.capacity()) +
         sizeof(double) * (value_.capacity() + diagonal_.capacity() + work_.capacity() + upper_value_.capacity() +
                           lower_work_.capacity()) +
         pinned_flag_.capacity();
}

}  // namespace granflow
