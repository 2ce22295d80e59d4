#pragma once
// Exact solves of the frictional contact problem of a small region, for steps that stall.
// A step that Gauss–Seidel and the cluster passes have not ended after many sweeps is held
// up in a few places: a self-stress whose states no single change of the active-set passes
// fixes, or a near-singular cluster. There the contact problem of the rows around the ones
// still corrected most, with every other impulse held, is solved as one linear
// complementarity problem: with the Coulomb cone's two facets in 2D, per row the normal
// impulse P_n, the tangential impulse split as P_t = β⁺ − β⁻, and the slip rate λ, with
//   0 ≤ P_n ⊥ u_n − b_n ≥ 0,
//   0 ≤ β⁺ ⊥ λ + (u_t − b_t) ≥ 0,   0 ≤ β⁻ ⊥ λ − (u_t − b_t) ≥ 0,
//   0 ≤ λ ⊥ μP_n − β⁺ − β⁻ ≥ 0,
// the laws of contact_law.hpp exactly (λ = 0: sticking, u_t = b_t; λ > 0: sliding against
// the slip at |P_t| = μP_n), and u = u_now + W·(P − P_now) with W the rows' Delassus
// matrix. Its matrix is copositive (W is positive semi-definite), and Lemke's method solves
// it whatever the rank of W (Stewart & Trinkle 1996; Anitescu & Potra 1997), so unlike the
// active-set passes it does not depend on being handed the right states.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Dense>

#include "dynamics/contact_rows.hpp"
#include "dynamics/tiling.hpp"

namespace granflow {

class RegionSolver {
 public:
  struct Outcome {
    int rows = 0;         // rows in the region (0: no hot row, or more than max_rows)
    bool solved = false;  // the impulses were replaced by the region's solution
    int pivots = 0;
  };
  // Solves the region of the working set `work` around its seeds, the rows whose local solve
  // would still correct them by at least `fraction` of the largest such correction and by
  // upsilon: the rows touching a grain of a seed, then those touching a grain of those,
  // depth times. Regions of more than max_rows rows are not solved. On success the region's
  // impulses and its grains' velocities are updated, its rows flagged hot (with kBearing
  // where P_n > 0) and their tiles marked moved and touched, to be swept next. The dense
  // problem is freed after the solve: these solves are rare, and their memory (up to
  // 4·max_rows squared doubles, several times) should not stay with the engine.
  Outcome solve(ContactRows& contacts, const Tiling& tiling, const std::vector<int>& work, std::uint8_t* row_flags,
                std::uint8_t* moved, std::uint8_t* touched, double mu, double upsilon, double fraction, int depth,
                int max_rows);

  std::size_t bytes() const;

 private:
  void gather_region(const ContactRows& contacts, const std::vector<int>& work, double mu, double upsilon,
                     double fraction, int depth);
  // The region's problem: M·z + q with z = (P_n, β⁺, β⁻, λ) per row, impulses as velocities.
  struct Problem {
    Eigen::MatrixXd M;
    Eigen::VectorXd q;
    double scale = 1;  // W_nn of the region's mean row: z holds P·scale
  };
  Problem assemble(const ContactRows& contacts, double mu) const;

  std::vector<int> body_start_, body_rows_;  // rows of the working set per mobile body
  std::vector<int> region_;                  // the region's rows (ascending)
  std::vector<int> mark_;                    // per row: its index in region_ + 1, else 0
  std::vector<int> bodies_;                  // the region's mobile bodies
  std::vector<std::uint8_t> in_region_body_;
  std::vector<double> correction_;  // per row of the working set: its local solve's correction
};

}  // namespace granflow
