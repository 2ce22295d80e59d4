#pragma once
// The force-network model of thesis §6.2 (eqs. 6.12–6.29): what gf-network measures on the
// contacts of stored frames, and the model's prediction of the static stress from it. Plain
// functions and one reusable per-frame analyser, no I/O. Definitions: docs/method/network.md.
//
// Conventions:
// - Contact: a row of ContactRecords (P_n > 0). n̂ = branch/|branch|, branch = r_i − r_j
//   (minimum image). θ = angle of n̂ to the x axis (flow along x, gradient y). Only the 2θ
//   and 4θ harmonics are used: sin2θ = 2 n_x n_y, cos2θ = n_x² − n_y² (no atan2 in the sums).
// - Long-lived contact: age ≥ 2 (P_n > 0 in this step and the previous one). Pairs are
//   stored once (i < j), so a contact across the Lees–Edwards boundary counts once.
// - Deflection x through grain I between two distinct long-lived partners m, J:
//   cos x = −u_{I→m}·u_{I→J}, u_{I→m} the unit vector from I to m (−n̂ at i, +n̂ at j);
//   a straight chain has x = 0.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/contact_records.hpp"

namespace granflow::network {

// Per-frame sums over one frame's contacts (all doubles so series can be averaged).
struct FrameSums {
  double grains = 0, contacts = 0, long_lived = 0, active_grains = 0;
  // Over unordered pairs of distinct long-lived contacts of one grain: count, Σcos x, Σcos x cos2x.
  double deflection_pairs = 0, sum_cos = 0, sum_cos_cos2 = 0;
  double sum_sin2 = 0, sum_cos2 = 0;                    // over all contacts
  double sum_f = 0, sum_f_sin2 = 0, sum_f_cos2 = 0;     // F_bc-weighted, all contacts
  double sum_b = 0, sum_b_sin2 = 0, sum_b_cos2 = 0;     // |branch|-weighted
  double sum_bf = 0, sum_bf_sin2 = 0, sum_bf_cos2 = 0;  // |branch|·F_bc-weighted
};

// Pooled angular and deflection histograms (add frames into it; K, D bins fixed at construction).
// θ is folded into [0, π), K bins of width π/K; |x| in [0, π], D bins of width π/D.
struct Histograms {
  Histograms(std::size_t angle_bins, std::size_t deflection_bins);
  std::vector<double> angle_count, angle_force, angle_branch;  // K: counts, Σ F_bc, Σ |b| per θ bin
  std::vector<double> deflection_count;                        // D: pairs per |x| bin over [0, π]
  void add(const Histograms& other);                           // same sizes
};

// Reusable buffers (one per thread/run): cost O(N + contacts + Σk²) per frame, k the number
// of long-lived contacts of a grain (a per-grain list by counting sort, never an N² loop).
class FrameAnalyser {
 public:
  // Sums of one frame; adds into h when non-null. std::invalid_argument on a pair index ≥ grains,
  // a pair (i, i), a zero branch, or columns of different lengths.
  FrameSums analyse(const ContactRecords& contacts, std::size_t grains, Histograms* h = nullptr);

 private:
  std::vector<std::size_t> start_;  // CSR offsets of each grain's long-lived partners, grains + 1
  std::vector<std::size_t> fill_;   // next free slot per grain while filling
  std::vector<double> ux_, uy_;     // unit vectors from the grain to its long-lived partners
};

// The window's ingredients from window means of FrameSums fields (a FrameSums whose fields are
// means, so every ratio is a ratio of window means):
//   z = 2·long_lived/grains, z_active = 2·long_lived/active_grains,
//   mean_cos = sum_cos/deflection_pairs, mean_cos_cos2 = sum_cos_cos2/deflection_pairs,
//   Phi = 2·mean_cos, Psi = 2·mean_cos_cos2 (the thesis' normalisation, eq. 6.23),
//   φ_αβ = ⟨n_α n_β⟩ and χ_αβ = ⟨F_bc n_α n_β⟩/⟨F_bc⟩ over all contacts (contact-weighted),
//   a_c = 4φ12, a′_c = 2(φ11 − φ22), a_f, a′_f by invert_force_fabric (exact) and the
//   first-order reading a_f ≈ 4χ12 − a_c, a′_f ≈ 2(χ11 − χ22) − a′_c,
//   fabric_norm = D = 1 + (a_c a_f + a′_c a′_f)/2,
//   shear_ratio_collisional_frames = −⟨|b| F_bc sin2θ⟩/⟨|b| F_bc⟩ (s^bc/p^bc with s = −Σxy),
//   mean_binary_force = ⟨F_bc⟩ contact-weighted (= D·⟨F_bc⟩ angle-averaged).
// A ratio with a zero denominator is NaN.
struct Ingredients {
  double z = 0, z_active = 0, mean_cos = 0, mean_cos_cos2 = 0, Phi = 0, Psi = 0;
  double phi11 = 0, phi22 = 0, phi12 = 0, chi11 = 0, chi22 = 0, chi12 = 0, fabric_norm = 0;  // D
  double a_c = 0, a_c_prime = 0, a_f = 0, a_f_prime = 0, a_f_first_order = 0, a_f_prime_first_order = 0;
  double shear_ratio_collisional_frames = 0, mean_binary_force = 0;
};
Ingredients ingredients(const FrameSums& means);

// a_f, a′_f from a_c, a′_c and the measured force fabric, the exact solution of eqs. 6.20–6.21's
// χ12 = (a_c + a_f)/(4D), χ11 − χ22 = (a′_c + a′_f)/(2D), D = 1 + (a_c a_f + a′_c a′_f)/2,
// a 2×2 linear system in (a_f, a′_f); NaN when it is singular.
struct FabricInversion {
  double a_f, a_f_prime, fabric_norm;
};
FabricInversion invert_force_fabric(double a_c, double a_c_prime, double chi12, double chi11_minus_chi22);

// The geometric sums of eqs. 6.27–6.29 up to a limit L ≥ 0 that need not be an integer:
// continuation: the closed forms continued to real L; floor: the sums up to ⌊L⌋.
enum class SumLimit { continuation, floor };
// S(b, L) = Σ_{ℓ=1}^{L} b^ℓ; continuation b(1 − b^L)/(1 − b), L at b = 1.
double power_sum(double base, double limit, SumLimit how);
// W(q, m, L) = Σ_{ℓ=1}^{L} Σ_{i=0}^{ℓ} q^i m^{ℓ−i}; continuation (m S(m,L) − q S(q,L))/(m − q),
// at m = q its limit S(m, L) + m ∂S/∂m.
double mixed_sum(double q, double m, double limit, SumLimit how);
// Whether the continuation is real: base ≥ 0 or an integer limit. Otherwise power_sum and
// mixed_sum return the floor value for SumLimit::continuation.
bool continuation_real(double base, double limit);

// eqs. 6.27–6.29 with M = min(Φ(z−1), 1), Q = Ψ(z−1), L = max(xi_ratio − 1, 0):
//   pressure = S(M, L)                                   ((p^s − p^bc)/p^bc)
//   shear    = −½ [a_f S(Q, L) + a_c W(Q, M, L)]          ((s^s − s^bc)/p^bc, s = −Σxy)
//   xx       = S(M, L) + (a′_f/2) S(Q, L) + (a′_c/2) W(Q, M, L)   ((Σ11^s − Σ11^bc)/p^bc)
// continuation_real false when a negative base met a non-integer L (floor values used).
// Readings: Φ, Ψ as given (the caller passes 2× or 1× means), z as given.
struct Prediction {
  double pressure, shear, xx;
  bool continuation_real;
};
Prediction predict(double z, double Phi, double Psi, double a_c, double a_c_prime, double a_f, double a_f_prime,
                   double xi_ratio, SumLimit how);

// 4θ and 2θ Fourier coefficients of a binned π-periodic function (bin-average corrected):
// with f_k normalised by its bin average f̄ inside, K bins over [0, π) of centres θ_k,
// sin coefficient = (2/K) Σ_k (f_k/f̄) sin(mθ_k) / sinc(mΔθ/2), same with cos.
struct Harmonic {
  double sin_coefficient, cos_coefficient;
};
Harmonic harmonic(std::span<const double> binned, int m);

}  // namespace granflow::network
