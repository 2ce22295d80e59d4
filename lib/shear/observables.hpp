#pragma once
// Bulk observables of a shear cell (thesis §4.2.2): granular temperature (eq. 4.5) and
// stress tensor (eq. 4.6) split into kinetic, contact ("static", eq. 2.8) and
// collisional (eq. 6.2) parts. Sums run over mobile grains; A = Lx·Ly.
//
// Sign convention (the thesis'): Σ_αβ·A = Σ m ṽ_α ṽ_β + Σ_contacts σ_α F_β with σ = r_i − r_j
// and F the force on i, so compression is positive (p > 0). In simple shear with
// γ̇ > 0 contacts align with the compressive axis (1, −1) and ṽ_x ṽ_y < 0 on average,
// hence s = Σ_xy < 0: the shear stress resisting the flow is −Σ_xy.
#include "core/vec.hpp"
#include "dynamics/engine.hpp"
#include "dynamics/grains.hpp"
#include "geometry/box.hpp"

namespace granflow {

struct StressTensors {
  Mat2 kinetic = Mat2::Zero();      // Σ m (ṽ − V)⊗(ṽ − V) / A, V the mass-weighted mean ṽ (eq. 2.6)
  Mat2 contact = Mat2::Zero();      // Σ over contacts, each once, of σ⊗F / A (static stress)
  Mat2 collisional = Mat2::Zero();  // Σ over contacts of n̂⊗n̂ |σ| F_bc / A (eq. 6.2)

  Mat2 total() const { return kinetic + contact; }
};

// T of eq. 4.5: N·T = Σ |ṽ − V|² + ½ Σ R²(ω − Ω)², with V and Ω the plain means of the
// fluctuating velocity ṽ = v − γ̇(y − Ly/2)x̂ and of ω, over the N mobile grains.
double granular_temperature(const GrainState& state, const Box& box, double rate);

// Stress of a state and the contacts of the step that produced it (Engine::contacts()).
StressTensors stress(const GrainState& state, const Box& box, double rate, const ContactRecords& contacts);

inline double pressure(const Mat2& s) { return 0.5 * (s(0, 0) + s(1, 1)); }
inline double shear_stress(const Mat2& s) { return s(0, 1); }
// N1 = (Σ_xx − Σ_yy)/2p.
inline double normal_stress_difference(const Mat2& s) { return (s(0, 0) - s(1, 1)) / (2 * pressure(s)); }

}  // namespace granflow
