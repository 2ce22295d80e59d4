#pragma once
// Simple shear in a Lees–Edwards cell (thesis §4.2): the start state of a run and the
// bulk observables recorded at every observed step.
#include <cstdint>
#include <optional>
#include <string>

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

// What a branch from a moving frame, sheared at γ̇₀, does with the velocities and spins
// at rate γ̇ (gf-shear --branch-velocities; docs/programs/gf-shear.md):
enum class BranchVelocities {
  scale,  // v ← (γ̇/γ̇₀)·v, ω ← (γ̇/γ̇₀)·ω: the Bagnold map (§3.2), the same trajectory at the new speed
  keep,  // the fluctuations about the mean flow kept: v ← ṽ + γ̇(y − Ly/2)·x̂, ω ← (ω + γ̇₀/2) − γ̇/2
  reset,  // no fluctuations: v ← γ̇(y − Ly/2)·x̂, ω ← −γ̇/2 (the affine start of a packing)
};
// "scale", "keep" or "reset"; UsageError naming --branch-velocities otherwise.
BranchVelocities branch_velocities_named(const std::string& name);

// Applies `mode` to the velocities and spins of the mobile grains of a frame sheared at
// source_rate, for a run at rate. scale and keep leave the state as it is when the rates
// are equal; reset does not. Contacts are not touched (see shear_start).
void branch_velocities(GrainState& state, const Box& box, double source_rate, double rate, BranchVelocities mode);

// The start of a shear run at rate γ̇ from frame `frame` (negative: from the end) of
// a packing or trajectory:
// - a frame at rest (a packing) gets the affine flow v_x = γ̇(y − Ly/2), ω = −γ̇/2, or,
//   at γ̇ = 0, Gaussian velocities with zero total momentum scaled to granular
//   temperature `temperature` (eq. 4.5; seeded); `mode` must then be nullopt;
// - a moving frame sheared at γ̇₀ gets branch_velocities(γ̇₀ → γ̇, mode, scale when
//   nullopt). With scale and γ̇₀ ≠ γ̇ (both non-zero) the Bagnold invariance (§3.2) maps
//   the stored state onto the new rate exactly. In every mode the frame's contacts (the
//   warm start and the first frame's records) keep their pairs and ages, their force
//   columns are scaled by (γ̇/γ̇₀)² and their pre-step normal velocities by γ̇/γ̇₀: only
//   the warm start of the first solve, which re-solves them.
// UsageError for a box open in y, fixed grains, a rate change from or to 0, a mode with a
// frame at rest (naming --branch-velocities), or reset at γ̇ = 0 (every grain at rest).
ShearStart shear_start(const io::TrajectoryReader& input, long long frame, double rate, double temperature,
                       std::uint64_t seed, std::optional<BranchVelocities> mode = std::nullopt);

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

// Kinetic energy about the mean flow of simple shear at rate γ̇: Σ ½m|ṽ|² + ½I(ω + γ̇/2)²
// over the mobile grains, ṽ the fluctuating velocity, −γ̇/2 the spin of the affine flow,
// I = ½mR² (disks).
double kinetic_energy_about_mean_flow(const GrainState& state, const Box& box, double rate);

// The kinetic energy change of a run's first step, which must not grow without shear: a
// start that violates this (a gf-pack packing's network of exactly touching pairs, on which
// Newton's restitution law applied to simultaneous contacts injects energy) must not pass
// silently.
struct FirstStepEnergy {
  double before = 0;  // kinetic_energy_about_mean_flow at step 0
  double after = 0;   // and after step 1
  // As attributes of /run: first_step_kinetic_energy_before, _after and, when before > 0,
  // _ratio (after/before).
  void write(io::TrajectoryWriter& writer) const;
  // The warning line (without the program's name), or "" if none applies. Only at γ̇ = 0,
  // where no work is done on the grains: the energy grows beyond round-off (relative
  // 10⁻⁹) for any e, or, at e = 1 without friction, where it must not change, it changes
  // by more than 1 %. With shear the images' work changes the energy legitimately.
  std::string warning(double rate, const Material& material) const;
};

}  // namespace granflow
