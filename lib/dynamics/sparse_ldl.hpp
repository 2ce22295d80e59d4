#pragma once
// Sparse LDLᵀ factorisation of a symmetric positive semi-definite matrix, by Davis'
// up-looking algorithm (T. A. Davis, "Algorithm 849: a concise sparse Cholesky
// factorization package", ACM TOMS 31, 2005), in the order the unknowns are given:
// the caller orders them so that the fill-in stays small.
//
// The same algorithm also gives A = L·D·U (L unit lower, U unit upper triangular) of a
// matrix whose nonzero pattern is symmetric but whose values are not (frictional contact
// clusters: a sliding contact's tangential equation ties its impulse to the Coulomb facet
// instead of fixing its velocity). Row k of L and column k of U come from the two
// triangular solves against the rows above; there is no pivoting: the caller's order is
// kept, and the pivots of such matrices stay close to those of the symmetric ones.
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

  // The LDU factorisation of a matrix with a symmetric pattern: for the entries p of column k
  // (rows row[p] ≤ k), upper[p] = A(row[p], k) and lower[p] = A(k, row[p]). An unknown is pinned
  // when |pivot| falls below drop × |A(k, k)|.
  bool factor(int n, const std::vector<int>& start, const std::vector<int>& row, const std::vector<double>& upper,
              const std::vector<double>& lower, double drop, std::size_t max_fill, int threads = 1);

  // Solves A x = b in place (x holds b on entry); pinned unknowns come out 0.
  void solve(std::vector<double>& x) const;
  // Solves Aᵀ x = b the same way (the same factor: Aᵀ = Uᵀ·D·Lᵀ).
  void solve_transposed(std::vector<double>& x) const;

  int pinned() const { return pinned_; }
  bool pinned(int k) const { return pinned_flag_[k] != 0; }
  // Rows of the last factorisation computed by the threads in parallel (0 when serial).
  int shared_rows() const { return shared_rows_; }
  std::size_t allocated_bytes() const;

 private:
  // Row k of L and D (numeric phase); `pattern` is a thread's scratch of `size` ints, at
  // least the rows of k's subtree. Returns whether row k was pinned.
  template <bool Unsymmetric>
  bool factor_row(int k, const int* start, const int* row, const double* value, const double* lower, double drop,
                  int* pattern, int size);
  bool factor_any(int n, const std::vector<int>& start, const std::vector<int>& row, const std::vector<double>& value,
                  const double* lower, double drop, std::size_t max_fill, int threads);
  void substitute(const std::vector<double>& lower, const std::vector<double>& upper, std::vector<double>& x) const;
  // Sets bin_[k]: the thread that computes row k, or −1 for rows computed after all
  // threads are done (ancestors of the subtrees shared out).
  void share_out(int n, int threads);

  std::vector<int> parent_, flag_, count_, start_, index_, pattern_, bin_;
  std::vector<double> value_, diagonal_, work_;
  std::vector<double> upper_value_, lower_work_;  // U by rows and the second solve's scratch (LDU only)
  bool unsymmetric_ = false;
  std::vector<char> pinned_flag_;
  int pinned_ = 0, shared_rows_ = 0;
};

}  // namespace granflow
