#pragma once
// Exact solves of clusters of active contacts. Once Gauss–Seidel leaves the set of active
// contacts (P_n > 0) nearly unchanged, each cluster of them (joined through mobile grains)
// still above the tolerance is solved exactly for that set: the cluster's Delassus system,
// assembled row by row, factorised by a sparse LDLᵀ after peeling its tree-like parts and
// ordering its loops; Gauss–Seidel then corrects the set if it was wrong. This replaces the
// slow linear tail of Gauss–Seidel on large, tree-like clusters.
//
// With friction the Coulomb cone has two facets in 2D, so for a given state of each contact
// the local laws are linear: a bearing row meets its normal bound; a sliding row (|P_t| = μP_n
// in the current iterate) keeps to its facet, P_t = sμP_n, and has ΔP_n as its only unknown
// (its impulse acts along n̂ + sμt̂); a sticking one also has ΔP_t, and meets its tangential
// target. The matrix is then unsymmetric (the sliding rows' impulse directions differ from
// their constraint directions) with a symmetric pattern, factorised as LDU in the same order.
// A wrong state shows as a clamped or undone solve, which Gauss–Seidel corrects before the
// next pass: an active-set method with Gauss–Seidel between its steps. A cluster with more
// impulse unknowns than its grains' degrees of freedom (a grain wedged between two fixed ones,
// a hyperstatic loop) has a self-stress, along which its solve moves into the cones, or, if
// no impulses in the current states meet its equations, to the state change they call for,
// which Gauss–Seidel alone only creeps towards (see step_along_self_stress()).
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "dynamics/contact_rows.hpp"
#include "dynamics/sparse_ldl.hpp"
#include "dynamics/tiling.hpp"

namespace granflow {

class ClusterSolver {
 public:
  // Before the passes of a step over `rows` rows.
  void reset(std::size_t rows) { unknown_.assign(rows, -1); }
  // One pass: solves each cluster of the bearing rows of the working set `work` (row_flags:
  // kBearing) that holds a hot row (kHot), updating the impulses, the bodies' velocities and
  // the bearing flags, and flags the tiles of the rows it solved in moved and touched.
  // Returns the number of active rows of the largest cluster.
  // With mu > 0 the rows' tangential impulses are solved too (see above); upsilon is the
  // tolerance on a velocity residual.
  int solve(ContactRows& contacts, const Tiling& tiling, const std::vector<int>& work, std::uint8_t* row_flags,
            std::uint8_t* moved, std::uint8_t* touched, double mu, double upsilon, int threads);

  std::size_t bytes() const;

 private:
  // Per thread: a cluster's numbering (unknown → row), peeling queue, matrix (upper triangle
  // by columns), right-hand side and factor.
  // With friction also the lower triangle's values (value holds the upper one), each row's
  // facet (0 sticking, ±1 sliding with P_t = ±μP_n), its first unknown, the impulses kept
  // for an undo, and for the pinned unknowns (unmet equations first) the right-hand side, then
  // the residual, the self-stress, its velocity change (A·z, round-off) and left null vector,
  // and the rows stepped onto a boundary.
  struct Scratch {
    std::vector<int> order, peel, start, row, first, stepped, pinned;
    std::vector<double> value, rhs, lower, old, b, stress, left, change;
    std::vector<std::int8_t> facet;
    std::vector<Body> saved;       // the cluster's mobile bodies before a solve is applied
    std::vector<int> saved_index;  // and their indices
    SparseLdl ldl;
  };
  bool solve_cluster(int k, Scratch& w, int threads);
  void assemble_cluster(Scratch& w, int threads) const;
  void assemble_frictional_cluster(Scratch& w) const;
  bool apply_normal_solution(Scratch& w, int threads);
  bool apply_frictional_solution(Scratch& w, int threads);
  void step_along_self_stress(Scratch& w);
  void order_loops(Scratch& w, int first);
  double cluster_residual(const Scratch& w, int threads) const;
  void apply_normal_impulse(const Row& r, double dpn);
  void apply_impulse(const Row& r, double dpn, double dpt);
  void save_bodies(Scratch& w) const;
  void restore_bodies(const Scratch& w);

  // The rows, bodies and flags of the pass under way (see solve()).
  Row* rows_ = nullptr;
  Body* bodies_ = nullptr;
  Tangent* tangents_ = nullptr;  // with friction only
  double mu_ = 0, upsilon_ = 0;
  const std::array<int, 2>* row_bodies_ = nullptr;
  std::uint8_t* row_flags_ = nullptr;

  // The active rows, union–find over bodies, the hot clusters' rows by cluster and by body,
  // rows per body left to peel, and each row's unknown in its cluster (−1 if none).
  struct ActiveRow {
    int c, i, j;  // row, its mobile bodies (−1: fixed)
    int cluster;  // root of its cluster, then the cluster's number
  };
  std::vector<ActiveRow> active_;
  std::vector<int> large_;                // clusters solved with all threads
  std::vector<int> cluster_order_;        // the others, in the order the threads take them
  std::vector<std::size_t> chunk_start_;  // first row of each chunk of the working set
  std::vector<int> cluster_, cluster_id_, cluster_start_, cluster_rows_, body_start_, body_rows_;
  std::vector<int> degree_, unknown_;
  std::vector<Scratch> scratch_;
};

}  // namespace granflow
