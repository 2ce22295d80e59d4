#pragma once
// Sparse LDLᵀ factorisation of a symmetric positive semi-definite matrix, by Davis'
// up-looking algorithm (T. A. Davis, "Algorithm 849: a concise sparse Cholesky
// factorization package", ACM TOMS 31, 2005), in the order the unknowns are given:
// the caller orders them so that the fill-in stays small.
//
// With threads > 1 the numeric factorisation is shared out by subtrees of the elimination
// tree (rows of disjoint subtrees read and write disjoint parts of L); every row is computed
// with the same operations in the same order as serially, so the factor is bit-identical
// for any thread count.
//
// A singular matrix is handled by pinning: an unknown whose pivot falls below
// `drop` × its diagonal is a combination of earlier ones (a redundant contact of a
// hyperstatic cluster), so it is fixed at 0 and its equation is left out. A consistent
// singular system thus still gets one of its solutions.
#include <cstddef>
#include <vector>

namespace granflow {

class SparseLdl {
 public:
  // The upper triangle of the n × n matrix by columns: column k holds the values
  // value[p] at rows row[p] ≤ k for p in [start[k], start[k + 1]); repeated entries are
  // summed. Returns false, with no usable factor, when L would hold more than max_fill
  // nonzeros.
  bool factor(int n, const std::vector<int>& start, const std::vector<int>& row, const std::vector<double>& value,
              double drop, std::size_t max_fill, int threads = 1);

  // Solves A x = b in place (x holds b on entry); pinned unknowns come out 0.
  void solve(std::vector<double>& x) const;

  int pinned() const { return pinned_; }
  // Rows of the last factorisation computed by the threads in parallel (0 when serial).
  int shared_rows() const { return shared_rows_; }
  std::size_t allocated_bytes() const;

 private:
  // Row k of L and D (numeric phase); `pattern` is a thread's scratch of `size` ints, at
  // least the rows of k's subtree. Returns whether row k was pinned.
  bool factor_row(int k, const int* start, const int* row, const double* value, double drop, int* pattern, int size);
  // Sets bin_[k]: the thread that computes row k, or −1 for rows computed after all
  // threads are done (ancestors of the subtrees shared out).
  void share_out(int n, int threads);

  std::vector<int> parent_, flag_, count_, start_, index_, pattern_, bin_;
  std::vector<double> value_, diagonal_, work_;
  std::vector<char> pinned_flag_;
  int pinned_ = 0, shared_rows_ = 0;
};

}  // namespace granflow
