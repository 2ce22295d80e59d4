#pragma once
// Non-smooth Gauss–Seidel over the contact rows: sweeps of local solves (contact_law.hpp)
// over a working set, in the parallel order of the tiles (see Tiling), and the residual
// check that decides convergence. The working set holds the contacts active in the warm
// start or at the free velocities and the pairs whose normal constraint is within v_rel of
// binding; the others join it as soon as a check finds them violated. Tiles that have
// settled are skipped, and a check or a cluster solve that changes something wakes only
// the tiles concerned. With friction, within the tiles swept, a row that its last visit
// left settled is skipped as long as no row sharing a grain has made a correction of Υ or
// more since (see sweep()).
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "dynamics/contact_rows.hpp"
#include "dynamics/tiling.hpp"

namespace granflow {

class GaussSeidel {
 public:
  // The step's working set: rows carrying a warm-start impulse and rows whose normal
  // constraint, at the free velocities, is violated or within vrel of binding.
  void select_working_set(const ContactRows& contacts, const Tiling& tiling, double vrel, int threads);
  // One sweep over the working set (forward or backward) with friction coefficient mu;
  // returns the largest correction made and adds the local solves to updates.
  double sweep(ContactRows& contacts, const Tiling& tiling, double mu, bool forward, double upsilon, int threads,
               std::int64_t& updates);
  // Largest correction a local solve would still make, over every row (everywhere) or over
  // the rows outside the working set, which join it if they would change (see
  // gauss_seidel.cpp); full_checks: every row every time. Adds the rows checked to updates.
  double check(const ContactRows& contacts, const Tiling& tiling, double mu, double upsilon, bool everywhere,
               bool full_checks, int threads, std::int64_t& updates);

  // As of the last sweep: rows that changed status (P_n > 0 or not; with friction also
  // sticking, or sliding on one facet of the cone or the other), and rows bearing.
  int status_changes() const { return status_changes_; }
  int active_rows() const { return active_rows_; }
  // For the cluster solves: the working set (rows ascending), the rows' flags (kHot,
  // kBearing) and the tiles' flags, which they update.
  const std::vector<int>& work() const { return work_; }
  std::uint8_t* row_flags() { return row_flags_.data(); }
  std::uint8_t* moved() { return moved_.data(); }
  std::uint8_t* touched() { return touched_.data(); }
  // After impulses changed other than by the sweeps (a cluster or region solve): the next
  // sweep visits every row of the tiles it sweeps.
  void revisit_all() { revisit_all_ = true; }
  // Whether frictional sweeps skip settled rows (SolverSettings::skip_settled_rows).
  void skip_settled_rows(bool on) { skip_settled_rows_ = on; }

  std::size_t bytes() const;

 private:
  void group_working_set(const Tiling& tiling);
  template <bool Friction>
  double sweep(ContactRows& contacts, const Tiling& tiling, double mu, bool forward, double upsilon, int threads,
               std::int64_t& updates);

  // The working set (rows grouped by tile, ascending within a tile; tile t holds
  // work_[work_start_[t]] … work_[work_start_[t + 1] − 1]), its membership, and per row
  // whether the last sweep still corrected it by Υ or more and whether it carries a normal
  // impulse (flags kHot, kBearing).
  std::vector<int> work_, work_start_;
  std::vector<std::uint8_t> in_work_, row_flags_;
  std::vector<std::uint8_t> moved_;    // per tile: corrected by Υ or more when last swept (or since marked)
  std::vector<std::uint8_t> touched_;  // per tile: swept or solved since the last check everywhere
  std::vector<double> tile_residual_;  // per tile: largest residual at its last check everywhere
  int status_changes_ = 0, active_rows_ = 0;
  // With friction: per body, whether a row made a correction of Υ or more on it in the
  // previous sweep and in this one (kicked_[kick_now_]), and whether the next sweep must
  // visit every row.
  std::array<std::vector<std::uint8_t>, 2> kicked_;
  int kick_now_ = 0;
  bool revisit_all_ = true, skip_settled_rows_ = true;
};

}  // namespace granflow
