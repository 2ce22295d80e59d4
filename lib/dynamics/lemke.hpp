#pragma once
// Dense linear complementarity problems, w = M·z + q, z ≥ 0, w ≥ 0, zᵀw = 0, by Lemke's complementary
// pivoting (covering vector (1, …, 1), one artificial variable z0). The minimum-ratio test is
// lexicographic on the rows of [B⁻¹q | B⁻¹], so that degenerate problems (many q_i = 0 and a rank-deficient
// M, as frictional contacts give) cannot cycle. Lemke reaches a solution when M is copositive-plus and the
// problem is feasible, or when M is copositive and q lies in the dual cone of the solutions of the
// homogeneous problem (q = 0): the friction LCP of Stewart & Trinkle (1996) and Anitescu & Potra (1997);
// otherwise it may end on a secondary ray, which is reported, not hidden.
//
// The pivots run on D_r·M·D_c and D_r·q, rows and columns equilibrated by powers of two (exact): the same
// problem with z = D_c·z', but with entries of comparable size, so that relative tolerances mean the same
// in every row (the friction LCP puts W, of any size the units give, next to entries 1 and μ). For the
// original problem this is Lemke with the covering vector d = D_r⁻¹·(1, …, 1), and the first pivot leaves
// the row of the most negative D_r·q.
// A z that is returned has been re-solved from M and q on the final basis, not taken from the tableau,
// and checked to 1e-9 relative, in the caller's units and in the equilibrated ones.
#include <cstddef>
#include <vector>

#include <Eigen/Dense>

namespace granflow {

class Lemke {
 public:
  // Solves w = M·z + q, z ≥ 0, w ≥ 0, zᵀw = 0 (M dense, n×n). Returns true with z set when it
  // finds a solution; false on a secondary ray (no solution reachable) or after max_pivots
  // pivots (z then undefined).
  bool solve(const Eigen::MatrixXd& M, const Eigen::VectorXd& q, Eigen::VectorXd& z, int max_pivots);
  int pivots() const { return pivots_; }  // pivots of the last solve
  std::size_t bytes() const;              // heap bytes of the scratch kept between solves

 private:
  // Variables are numbered w_i = i, z_i = n + i, z0 = 2n.
  void equilibrate(const Eigen::MatrixXd& M, const Eigen::VectorXd& q);
  void pivot(int r);
  // The row leaving the basis for the entering column in column_, or −1 on a secondary ray.
  int leaving_row(int n);
  // z from the final basis, re-solved from M and q and checked against them.
  bool polish(const Eigen::MatrixXd& M, const Eigen::VectorXd& q, Eigen::VectorXd& z);
  bool complementary(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, Eigen::VectorXd& z);

  Eigen::MatrixXd scaled_;                    // D_r·M·D_c
  Eigen::VectorXd scaled_q_;                  // D_r·q
  Eigen::VectorXd row_scale_, column_scale_;  // D_r's and D_c's diagonals
  Eigen::MatrixXd inverse_;                   // B⁻¹ of the current basis; M[S, S] in the polish
  Eigen::VectorXd value_;                     // B⁻¹·D_r·q: the value of each row's basic variable
  Eigen::VectorXd column_;                    // a = B⁻¹·A_j for the entering variable j
  Eigen::VectorXd entering_column_;           // A_j: e_j for w_j, −(D_r·M·D_c)_j for z_j
  Eigen::VectorXd update_;                    // the previous a − e_r, while B⁻¹ is updated
  Eigen::VectorXd pivot_row_;                 // the pivot row of B⁻¹ divided by the pivot
  // By row, the sizes of the terms summed into the value, into a, and into the row of B⁻¹:
  // |B⁻¹|·|D_r·q|, |B⁻¹|·|A_j|, |B⁻¹|·1 (the last for tied rows only). The ratio test judges ties
  // against their roundings.
  Eigen::VectorXd value_size_, column_size_, row_size_;
  Eigen::VectorXd residual_;  // A·z + b in complementary()
  std::vector<int> basic_;    // the basic variable of each row
  std::vector<int> row_of_;   // the row of each basic variable, −1 when nonbasic
  std::vector<int> tied_;     // rows tied in the ratio test
  std::vector<int> support_;  // S: the indices i with z_i basic
  int pivots_ = 0;
};

}  // namespace granflow
