#pragma once
// Contact Dynamics engine for rigid disks (thesis §4.1, App. A; Moreau–Jean time stepping).
//
// One step, from the state at time t (positions r, lab velocities v, ω):
//  1. candidate pairs (found at the end of the previous step): gap g = |d| − R_i − R_j
//     below the alert distance, d = minimum image of r_i − r_j, n̂ = d/|d| (from j to i),
//     t̂ = perp(n̂) = ẑ × n̂. A pair seen through the Lees–Edwards image k rows up
//     (k = round((y_i − y_j)/Ly)) meets j's image moving at v_j + k·γ̇·Ly·x̂.
//  2. free velocities v_free = v + dt·g for mobile grains.
//  3. impulses P = P_n n̂ + P_t t̂ (on i; −P on j, both at the contact point) by
//     non-smooth Gauss–Seidel on the relative contact-point velocity
//        u = v_i − v_j − k·γ̇·Ly·x̂ − (R_i ω_i + R_j ω_j)·t̂,  u_n = u·n̂, u_t = u·t̂.
//     Normal law (Moreau's activation, decided once per step from the pre-step u_n⁻):
//        touching or predicted to touch (g ≤ 0 or g + dt·u_n⁻ ≤ 0):
//            u_n⁺ ≥ −e·u_n⁻ if u_n⁻ < 0, else u_n⁺ ≥ 0 (an overlap never grows);
//        otherwise (speculative): u_n⁺ ≥ −g/dt (the gap may close, never below zero);
//        P_n ≥ 0, P_n > 0 only where the bound is tight.
//     (SolverSettings::activation = overlap: the thesis' rule instead, contact_law.hpp.)
//     Tangential law (eq. 4.1, A.7): u_t⁺ = e_t·u_t⁻ with |P_t| ≤ μ·P_n.
//     A binary collision thus obeys u_n⁺ = −e·u_n⁻ exactly and never overlaps.
//  4. v⁺ = v_free + P/m, ω⁺ = ω − R·P_t/I for both grains of a contact (the torque of
//     P at the contact point −R_i n̂ of i is −R_i P_t; on j, −P at +R_j n̂ gives −R_j P_t).
//  5. r += dt·v⁺, θ += dt·ω⁺, Lees–Edwards offset += γ̇·Ly·dt, wrap into the box;
//     then the next step's candidates are found and the largest overlap is reported.
//
// Convergence: a contact's residual is the largest velocity correction its local
// solve would still make (|ΔP_n|·W_nn, |ΔP_t|·W_tt); the iteration stops when every
// residual is below Υ = tolerance/dt (the thesis' Υ = 10⁻¹⁰/dt), i.e. a fixed
// penetration per step, which keeps the dynamics invariant under γ̇ → Aγ̇, dt → dt/A.
// Steps that reach max_iterations are completed anyway, reported and counted.
//
// Work per step (none of it changes the converged solution, which the residual test
// above decides on every candidate):
//  - candidates come from a pair list with a skin, rebuilt only when the accumulated
//    worst-case relative displacement could have brought an unlisted pair within the
//    alert distance; the candidates are exactly those a fresh search would find;
//  - sweeps visit a working set: contacts active in the warm start or at the free
//    velocities, and pairs whose normal constraint is within v_rel of binding; the
//    others join it as soon as a residual check finds them violated;
//  - grains are numbered internally in a spatial order (recomputed every step, so
//    that the arithmetic depends on the state only and restarts stay bit-identical);
//  - sweeps go through horizontal strips at least one contact reach high, even strips
//    first, then odd ones: no two contacts of different strips of one parity share a
//    grain, so threads sweep them at once (SolverSettings::threads), and the order of
//    the updates, hence every bit of the result, is the same for any number of threads;
//    each strip is cut into tiles (≈ 8 diameters wide; grains and contacts are stored
//    tile by tile), and tiles that have settled (all corrections below Υ there and in the
//    eight tiles around the last time round) are skipped: a residual check or a cluster
//    solve that changes something wakes only the tiles concerned, so the late sweeps of a
//    large system cost what its few unsettled places cost, not what the system costs;
//  - once a sweep leaves the state of the contacts nearly unchanged (active or not, and
//    with friction sticking or sliding on either facet of the cone), the clusters of
//    active contacts still above the tolerance are solved exactly for that state (sparse
//    LDLᵀ without friction, LDU with it); Gauss–Seidel then corrects the state if it was
//    wrong. This replaces the slow linear tail of Gauss–Seidel on large clusters. Small
//    clusters go to the threads whole; large ones (the percolating one) are factorised by
//    all threads together, by subtrees of the elimination tree, with the same result;
//  - with friction, a step still unconverged after SolverSettings::region_solve_after sweeps
//    solves the regions around its largest corrections exactly, states included (a linear
//    complementarity problem, by Lemke's method; see RegionSolver).
//
// The parts of a step, each in its own file: BroadPhase (candidates), Tiling (internal order,
// strips and tiles), ContactRows (rows, warm start, records), contact_law.hpp (the local
// laws), GaussSeidel (working set, sweeps, checks), ClusterSolver (exact cluster solves),
// RegionSolver (exact solves of stalled regions, with friction) and
// parallel.hpp (the OpenMP helpers); Engine owns them and runs step() through them.
//
// The engine assumes disks with I = mR²/2 (W_tt = 3·W_nn) and a box at least two
// search cutoffs (2·R_max + alert) wide, so that each pair has a single nearest image.
#include <array>
#include <cstdint>
#include <vector>

#include "core/contact_records.hpp"
#include "core/vec.hpp"
#include "dynamics/broad_phase.hpp"
#include "dynamics/cluster_solver.hpp"
#include "dynamics/contact_rows.hpp"
#include "dynamics/gauss_seidel.hpp"
#include "dynamics/region_solver.hpp"
#include "dynamics/grains.hpp"
#include "dynamics/tiling.hpp"
#include "geometry/box.hpp"

namespace granflow {

// The programs' default sweep caps (--max-iterations). With friction a step near jamming can
// stall for 10⁴–10⁵ sweeps and still converge: its cluster passes succeed only once the
// Gauss–Seidel iterate's contact states are nearly right (docs/method/solver.md).
constexpr int kMaxIterations = 10000;
constexpr int kMaxIterationsWithFriction = 100000;

struct SolverSettings {
  double tolerance = 1e-10;             // Υ·dt: a length per step
  Activation activation = Activation::predicted_gap;
  int max_iterations = kMaxIterations;  // Gauss–Seidel sweeps per step
  // Smallest alert gap (a length); 0 selects 0.01 × the mean diameter. Each step uses
  // max(this, 2·dt·v_rel,max), a safe bound on the relative displacement in one step:
  // pairs farther apart can neither touch nor bind, so a larger floor adds rows that never
  // take an impulse (it also enters v_rel's shear term, hence the trajectories' round-off).
  double alert_distance = 0;
  // Extra gap (a length) of the reusable pair list; 0 selects 0.3 × the mean diameter.
  // Only the cost depends on it: a larger skin means longer lists, rebuilt less often.
  double skin = 0;
  // Exact solves of contact clusters (see above); false: Gauss–Seidel only.
  // Both reach the same converged solution.
  bool cluster_solves = true;
  // With friction: a step still unconverged after this many sweeps solves the regions around
  // the rows still corrected exactly (see RegionSolver), then again every 500 sweeps over a
  // wider region; 0: never. Both reach a solution within the tolerance; only the cost and,
  // where the solution is not unique, the trajectory depend on it.
  int region_solve_after = 1000;
  // With friction, sweeps skip the rows that their last visit left settled while no
  // neighbouring row has corrected them by Υ or more since (see GaussSeidel::sweep());
  // false: every row of the tiles swept. Both reach a solution within the tolerance; the
  // trajectories differ in round-off and, where the solution is not unique, within it.
  bool skip_settled_rows = true;
  // Residual checks over every row every time, instead of only where something changed
  // since the last one: the same trajectory, bit for bit (a reference for the tests).
  bool full_checks = false;
  // OpenMP threads for a step. The work is split so that the arithmetic does not depend on
  // it: any thread count gives the same trajectory, bit for bit.
  int threads = 1;
};

struct StepReport {
  std::int64_t step = 0;  // steps taken so far (1 after the first)
  int iterations = 0;     // Gauss–Seidel sweeps
  double residual = 0;    // final largest residual × dt (a length)
  bool converged = true;
  int candidates = 0;                // pairs handed to the solver
  int contacts = 0;                  // pairs with P_n > 0
  std::int64_t contact_updates = 0;  // local contact solves: working-set sweeps plus residual checks
  int cluster_solves = 0;            // passes of exact solves of frictionless clusters
  int largest_cluster = 0;           // active rows of the largest cluster solved exactly
  int region_solves = 0;             // exact solves of stalled regions (with friction)
  bool pairs_rebuilt = false;        // the pair list was rebuilt for the next step
  double max_overlap = 0;            // max(0, −g) over all pairs after the position update
  // Collisions: contacts born in this step (P_n > 0 now, none the step before: age 1).
  int collisions = 0;
  // Σ over those collisions of (V_i·n)(V_j·n), the product of the two grains' pre-collisional
  // normal peculiar velocities (their pre_normal_velocity record; the sign of n cancels). The
  // numerator of the velocity correlation C_v (thesis eq. 6.11).
  double collision_velocity_product = 0;
  // Kinetic energy (translational plus rotational) the contact impulses removed in this step:
  // −Σ_contacts P·ū, ū the relative contact-point velocity (image shift included) at the mean of
  // each grain's free and post-step velocities. It is exactly the kinetic energy the impulses take
  // out minus the work of the Lees–Edwards images (Σ P_x·k·γ̇·Ly), hence the same in the lab and the
  // sheared frame; (1 − e²)·m_red·u_n²/2 for a binary collision, 0 up to the solver tolerance when
  // e = 1 without friction.
  double dissipated_energy = 0;
};

// What a step passes to the next one: the contacts' forces (warm start P = F·dt) and
// ages. Part of the dynamical state: a restart is bit-identical only if this is
// restored too. It holds exactly the normal_force, tangential_force and age columns
// of ContactRecords, so a stored trajectory frame is a complete restart point.
struct ContactMemory {
  std::vector<std::array<int, 2>> pair;  // (i, j), i < j, sorted
  std::vector<double> normal_force;
  std::vector<double> tangential_force;
  std::vector<int> age;
};

class Engine {
 public:
  // rate: γ̇ (0 without shear; must be 0 for a box open in y). gravity: acceleration of
  // mobile grains. Throws UsageError on inconsistent or non-physical input.
  Engine(GrainState state, Box box, double rate, Material material, SolverSettings settings, double dt,
         Vec2 gravity = Vec2::Zero());

  // Advances by dt; the report stays valid until the next step.
  const StepReport& step();

  const GrainState& state() const { return state_; }
  const Box& box() const { return box_; }
  const ContactRecords& contacts() const { return contacts_.records(); }
  const StepReport& last_report() const { return report_; }
  double rate() const { return rate_; }
  double dt() const { return dt_; }
  const Material& material() const { return material_; }
  const SolverSettings& settings() const { return settings_; }
  const Vec2& gravity() const { return gravity_; }
  std::int64_t step_count() const { return steps_; }
  double time() const { return double(steps_) * dt_; }
  double alert_distance() const { return alert_; }
  std::int64_t unconverged_steps() const { return unconverged_; }

  // Threads for the following steps: any count gives the same trajectory, bit for bit.
  void set_threads(int threads);

  // Heap bytes held by the engine (grain state, pair list, solver, records).
  std::size_t allocated_bytes() const;

  ContactMemory memory() const;
  // Continues a run from a checkpoint: step counter and the memory of its last step.
  void restore(std::int64_t step, const ContactMemory& memory);

 private:
  void detect(bool moved);
  void solve();
  void advance();

  GrainState state_;
  Box box_;
  double rate_, dt_;
  Material material_;
  SolverSettings settings_;
  Vec2 gravity_;
  double alert_min_ = 0, alert_ = 0, max_radius_ = 0, vrel_ = 0;
  std::int64_t steps_ = 0, unconverged_ = 0;

  BroadPhase broad_;
  Tiling tiling_;
  ContactRows contacts_;

  GaussSeidel gauss_seidel_;
  ClusterSolver clusters_;
  RegionSolver regions_;

  StepReport report_;
};

}  // namespace granflow
