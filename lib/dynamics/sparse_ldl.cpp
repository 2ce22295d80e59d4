#include "dynamics/sparse_ldl.hpp"

#include "dynamics/capacity.hpp"

namespace granflow {

bool SparseLdl::factor(int n, const std::vector<int>& start, const std::vector<int>& row,
                       const std::vector<double>& value, double drop, std::size_t max_fill) {
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
  pattern_.resize(n);
  pinned_flag_.assign(n, 0);
  pinned_ = 0;
  for (int k = 0; k < n; ++k) {
    int top = n;
    flag_[k] = k;
    count_[k] = 0;
    double diagonal = 0;
    for (int p = start[k]; p < start[k + 1]; ++p) {
      int i = row[p];
      if (pinned_flag_[i]) continue;  // a pinned unknown's column is zero
      if (i == k) diagonal += value[p];
      work_[i] += value[p];
      int length = 0;
      for (; flag_[i] != k; i = parent_[i]) {
        pattern_[length++] = i;
        flag_[i] = k;
      }
      while (length > 0) pattern_[--top] = pattern_[--length];
    }
    diagonal_[k] = work_[k];
    work_[k] = 0;
    const int first = top;
    for (; top < n; ++top) {
      const int i = pattern_[top];
      const double yi = work_[i];
      work_[i] = 0;
      const int end = start_[i] + count_[i];
      for (int p = start_[i]; p < end; ++p) work_[index_[p]] -= value_[p] * yi;
      const double l = yi / diagonal_[i];
      diagonal_[k] -= l * yi;
      index_[end] = k;
      value_[end] = l;
      ++count_[i];
    }
    // A pivot that is (nearly) zero marks a dependent unknown: pin it, i.e. make row
    // and column k of the factor those of the identity.
    if (!(diagonal_[k] > drop * diagonal)) {
      for (int t = first; t < n; ++t) value_[start_[pattern_[t]] + count_[pattern_[t]] - 1] = 0;
      diagonal_[k] = 1;
      pinned_flag_[k] = 1;
      ++pinned_;
    }
  }
  return true;
}

void SparseLdl::solve(std::vector<double>& x) const {
  const int n = int(diagonal_.size());
  for (int k = 0; k < n; ++k)
    if (pinned_flag_[k]) x[k] = 0;
  for (int j = 0; j < n; ++j)
    for (int p = start_[j]; p < start_[j] + count_[j]; ++p) x[index_[p]] -= value_[p] * x[j];
  for (int j = 0; j < n; ++j) x[j] /= diagonal_[j];
  for (int j = n - 1; j >= 0; --j)
    for (int p = start_[j]; p < start_[j] + count_[j]; ++p) x[j] -= value_[p] * x[index_[p]];
}

std::size_t SparseLdl::allocated_bytes() const {
  return sizeof(int) * (parent_.capacity() + flag_.capacity() + count_.capacity() + start_.capacity() +
                        index_.capacity() + pattern_.capacity()) +
         sizeof(double) * (value_.capacity() + diagonal_.capacity() + work_.capacity()) + pinned_flag_.capacity();
}

}  // namespace granflow
