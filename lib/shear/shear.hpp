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

// strain, pressure, shear_stress (−Σ_xy), normal_stress_difference, temperature and
// the kinetic, static (contact) and collisional stress tensors of the current step.
void record_shear_observables(const Engine& engine, io::TrajectoryWriter& writer);

}  // namespace granflow
