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
// The engine assumes disks with I = mR²/2 (W_tt = 3·W_nn) and a box at least two
// search cutoffs (2·R_max + alert) wide, so that each pair has a single nearest image.
#include <array>
#include <cstdint>
#include <vector>

#include "core/vec.hpp"
#include "dynamics/grains.hpp"
#include "geometry/box.hpp"
#include "neighbours/cell_list.hpp"

namespace granflow {

struct SolverSettings {
  double tolerance = 1e-10;    // Υ·dt: a length per step
  int max_iterations = 10000;  // Gauss–Seidel sweeps per step
  // Smallest alert gap (a length); 0 selects 0.1 × the mean diameter. Each step uses
  // max(this, 2·dt·v_rel,max), a safe bound on the relative displacement in one step.
  double alert_distance = 0;
};

struct StepReport {
  std::int64_t step = 0;       // steps taken so far (1 after the first)
  int iterations = 0;          // Gauss–Seidel sweeps
  double residual = 0;         // final largest residual × dt (a length)
  bool converged = true;
  int candidates = 0;          // pairs handed to the solver
  int contacts = 0;            // pairs with P_n > 0
  std::int64_t contact_updates = 0;  // local contact solves (sweeps × candidates)
  double max_overlap = 0;      // max(0, −g) over all pairs after the position update
};

// The contacts (P_n > 0) of the last step, one row each, sorted by (i, j).
struct ContactRecords {
  std::vector<std::array<int, 2>> pair;          // (i, j) with i < j
  std::vector<double> normal_force;              // P_n/dt ≥ 0, on i along n̂
  std::vector<double> tangential_force;          // P_t/dt, on i along t̂ = perp(n̂)
  std::vector<Vec2> branch;                      // r_i − r_j (minimum image), n̂ = branch/|branch|
  // Force of the same pair as an isolated binary collision (eq. 5.4, A.5):
  // (1 + e)·m_ij·max(0, −u_n⁻)/dt, m_ij the reduced mass (m_i for a fixed partner).
  std::vector<double> binary_force;
  std::vector<std::array<double, 2>> pre_normal_velocity;  // ṽ_i·n̂, ṽ_j·n̂ before the step
  // Consecutive steps, this one included, in which the pair had P_n > 0 (1: new contact;
  // ≥ 2: "long-lived" in the sense of §6.2.2).
  std::vector<int> age;

  std::size_t size() const { return pair.size(); }
  void clear();
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
  Engine(GrainState state, Box box, double rate, Material material, SolverSettings settings,
         double dt, Vec2 gravity = Vec2::Zero());

  // Advances by dt; the report stays valid until the next step.
  const StepReport& step();

  const GrainState& state() const { return state_; }
  const Box& box() const { return box_; }
  const ContactRecords& contacts() const { return records_; }
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

  ContactMemory memory() const;
  // Continues a run from a checkpoint: step counter and the memory of its last step.
  void restore(std::int64_t step, const ContactMemory& memory);

 private:
  // Hot data of the Gauss–Seidel loop, one cache line per contact; bodies hold
  // s = R·ω so that u_t needs no radii (ΔS = −2·P_t/m for I = mR²/2).
  struct alignas(32) Body {
    double vx, vy, spin, inv_mass;
  };
  struct alignas(64) Row {
    int i, j;
    double nx, ny;
    double bn, bt;  // bounds on the raw (v_i − v_j)·n̂ and (v_i − v_j)·t̂ − s_i − s_j
    double inv_w;   // 1/W_nn = reduced mass; 1/W_tt = inv_w/3
    double pn, pt;
  };
  struct Candidate {
    int i, j, image;  // i < j; image = k
    double dx, dy;    // r_i − r_j (minimum image)
  };

  void detect();
  void build_rows();
  void load_bodies();
  void solve();
  double sweep(bool forward);
  double residual() const;
  void record_contacts();
  void store_bodies();
  void advance();

  GrainState state_;
  Box box_;
  double rate_, dt_;
  Material material_;
  SolverSettings settings_;
  Vec2 gravity_;
  double alert_min_ = 0, alert_ = 0, max_radius_ = 0;
  std::int64_t steps_ = 0, unconverged_ = 0;

  CellList cells_;
  std::vector<Candidate> found_, candidates_;
  std::vector<int> bucket_;
  std::vector<Body> bodies_;
  std::vector<Row> rows_;
  std::vector<int> row_age_;  // age of the matched contact of the previous step, else 0
  // Memory of the previous step, sorted by key = (i << 32) | j.
  std::vector<std::uint64_t> prev_key_;
  std::vector<double> prev_fn_, prev_ft_;  // forces, as recorded
  std::vector<int> prev_age_;

  ContactRecords records_;
  StepReport report_;
  double overlap_ = 0;
};

}  // namespace granflow
