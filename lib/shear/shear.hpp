#pragma once
// Simple shear in a Lees–Edwards cell (thesis §4.2): the start state of a run and the
// bulk observables recorded at every observed step.
#include <cstdint>

#include "dynamics/engine.hpp"
#include "io/trajectory.hpp"

namespace granflow {

struct ShearStart {
  GrainState grains;
  Box box;
  // Contacts of the stored frame (forces rescaled with the rate; empty for a packing):
  // the warm start of the first step, and the contacts of the run's first frame.
  io::ContactRecords contacts;
  bool fresh = false;  // the input was at rest: affine flow or random velocities were set
};

// The start of a shear run at rate γ̇ from frame `frame` (negative: from the end) of
// a packing or trajectory:
// - a frame at rest (a packing) gets the affine flow v_x = γ̇(y − Ly/2), ω = −γ̇/2, or,
//   at γ̇ = 0, Gaussian velocities with zero total momentum scaled to granular
//   temperature `temperature` (eq. 4.5; seeded);
// - a moving frame keeps its velocities; if it was sheared at γ̇₀ ≠ γ̇ (both non-zero),
//   velocities and ω are scaled by γ̇/γ̇₀ and the contact forces by (γ̇/γ̇₀)²: the
//   Bagnold invariance (§3.2) maps the stored state onto the new rate exactly.
// UsageError for a box open in y, fixed grains, or a rate change from or to 0.
ShearStart shear_start(const io::TrajectoryReader& input, long long frame, double rate, double temperature,
                       std::uint64_t seed);

// The engine's per-step collision count, collision velocity product and dissipated energy
// (StepReport), accumulated
// between observable rows, so that the rows sum to the run's totals whatever
// --observe-every is. Part of a run's state: a checkpoint holds it, a resume restores it.
struct ShearTally {
  std::int64_t collisions = 0;            // contacts born (age 1) since the previous row
  double collision_velocity_product = 0;  // Σ (V_i·n)(V_j·n) over those collisions
  double dissipated_energy = 0;           // kinetic energy the contact impulses took out since then
  std::int64_t steps = 0;                 // steps since then
  void add(const StepReport& report);
  void write(io::TrajectoryWriter& checkpoint) const;
  // UsageError naming the file if the checkpoint holds no tally.
  void restore(const io::TrajectoryReader& checkpoint);
};

// strain, pressure, shear_stress (−Σ_xy), normal_stress_difference, temperature and
// the kinetic, static (contact) and collisional stress tensors of the current step;
// collisions, collision_velocity_product and dissipated_energy from the tally, which is then reset (a row covers the
// steps after the previous row's, from step 0 for the first).
void record_shear_observables(const Engine& engine, io::TrajectoryWriter& writer, ShearTally& tally);

}  // namespace granflow
