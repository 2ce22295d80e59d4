#pragma once
// Sparse LDLᵀ factorisation of a symmetric positive semi-definite matrix, by Davis'
// up-looking algorithm (T. A. Davis, "Algorithm 849: a concise sparse Cholesky
// factorization package", ACM TOMS 31, 2005), in the order the unknowns are given:
// the caller orders them so that the fill-in stays small.
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
              double drop, std::size_t max_fill);

  // Solves A x = b in place (x holds b on entry); pinned unknowns come out 0.
  void solve(std::vector<double>& x) const;

  int pinned() const { return pinned_; }
  std::size_t allocated_bytes() const;

 private:
  std::vector<int> parent_, flag_, count_, start_, index_, pattern_;
  std::vector<double> value_, diagonal_, work_;
  std::vector<char> pinned_flag_;
  int pinned_ = 0;
};

}  // namespace granflow
