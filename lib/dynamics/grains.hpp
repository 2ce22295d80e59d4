#pragma once
// The state of a collection of rigid disks and the material law of their contacts.
//
// Disks have areal density 1: m = πR², I = mR²/2 (the engine relies on I = mR²/2).
// Velocities are stored in the lab frame. In a Lees–Edwards cell the mean (streaming)
// flow is v_x = γ̇·(y − Ly/2): positions live in [0, Lx)×[0, Ly) and the thesis puts the
// origin at the cell centre, so the streaming velocity vanishes at y = Ly/2. The
// fluctuating velocity is ṽ = v − γ̇·(y − Ly/2)·x̂. Rotation of the mean flow is
// −γ̇/2 (counter-clockwise positive; v_x = γ̇y has vorticity −γ̇).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/vec.hpp"
#include "geometry/box.hpp"

namespace granflow {

struct Material {
  double restitution = 0.5;           // e: u_n⁺ = −e·u_n⁻ on colliding pairs, in [0, 1]
  double tangential_restitution = 0;  // e_t: u_t⁺ = e_t·u_t⁻ on sticking contacts, in [−1, 1]
  double friction = 0;                // μ: |P_t| ≤ μ·P_n
};

struct GrainState {
  std::vector<Vec2> position;            // wrapped into the box by the engine
  std::vector<Vec2> velocity;            // lab frame
  std::vector<double> orientation;       // θ (radians, unbounded)
  std::vector<double> angular_velocity;  // ω, counter-clockwise positive
  std::vector<double> radius;
  std::vector<double> mass;
  // 1: immobile (infinite mass and inertia): feels neither contacts nor gravity and keeps
  // its velocity, normally zero.
  std::vector<std::uint8_t> fixed;

  std::size_t size() const { return position.size(); }
};

// Mass of a disk of areal density 1.
double disk_mass(double radius);

// N disks at the given positions with the given radii, at rest, θ = 0, m = πR², none fixed.
GrainState make_grains(std::vector<Vec2> positions, const std::vector<double>& radii);

// Mean (streaming) velocity of simple shear at height y: γ̇·(y − Ly/2)·x̂.
inline Vec2 streaming_velocity(const Box& box, double rate, double y) { return Vec2(rate * (y - 0.5 * box.ly), 0.0); }

// Adds the affine shear start (SLLOD initial condition, eq. 4.3): v_x += γ̇(y − Ly/2),
// ω += −γ̇/2, to every mobile grain.
void add_affine_flow(GrainState& state, const Box& box, double rate);

// ṽ_i = v_i − γ̇(y_i − Ly/2)·x̂.
inline Vec2 fluctuating_velocity(const GrainState& state, const Box& box, double rate, std::size_t i) {
  return state.velocity[i] - streaming_velocity(box, rate, state.position[i].y());
}

// Leaves every mobile grain with its fluctuation about the affine flow of rate γ̇:
// v ← ṽ = fluctuating_velocity(), ω ← ω + γ̇/2. The inverse of add_affine_flow up to round-off.
void remove_affine_flow(GrainState& state, const Box& box, double rate);

}  // namespace granflow
