// The window's ingredients of the force-network model from the frame sums: coordination,
// Φ and Ψ, fabric and force fabric and their Fourier components, and the harmonics of
// binned angular functions (network.hpp for the definitions).
#include <algorithm>
#include <cmath>
#include <limits>

#include "network/network.hpp"

namespace granflow::network {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double ratio(double numerator, double denominator) { return denominator != 0 ? numerator / denominator : kNaN; }

}  // namespace

FabricInversion invert_force_fabric(double a_c, double a_c_prime, double chi12, double chi11_minus_chi22) {
  const double X = 4 * chi12, Y = 2 * chi11_minus_chi22;
  // (1 − X a_c/2) a_f − (X a′_c/2) a′_f = X − a_c
  // −(Y a_c/2) a_f + (1 − Y a′_c/2) a′_f = Y − a′_c
  const double A11 = 1 - X * a_c / 2, A12 = -X * a_c_prime / 2;
  const double A21 = -Y * a_c / 2, A22 = 1 - Y * a_c_prime / 2;
  const double r1 = X - a_c, r2 = Y - a_c_prime;
  const double det = A11 * A22 - A12 * A21;
  // Singular up to rounding of the two products: no meaningful solution.
  const double scale = std::abs(A11 * A22) + std::abs(A12 * A21);
  if (!std::isfinite(det) || !(std::abs(det) > 64 * std::numeric_limits<double>::epsilon() * scale))
    return {kNaN, kNaN, kNaN};
  const double a_f = (r1 * A22 - A12 * r2) / det;
  const double a_f_prime = (A11 * r2 - A21 * r1) / det;
  return {a_f, a_f_prime, 1 + (a_c * a_f + a_c_prime * a_f_prime) / 2};
}

Ingredients ingredients(const FrameSums& m) {
  Ingredients g;
  g.z = ratio(2 * m.long_lived, m.grains);
  g.z_active = ratio(2 * m.long_lived, m.active_grains);
  g.mean_cos = ratio(m.sum_cos, m.deflection_pairs);
  g.mean_cos_cos2 = ratio(m.sum_cos_cos2, m.deflection_pairs);
  g.Phi = 2 * g.mean_cos;
  g.Psi = 2 * g.mean_cos_cos2;
  // n_x² = (1 + cos2θ)/2, n_y² = (1 − cos2θ)/2, n_x n_y = sin2θ/2.
  g.phi11 = ratio(m.contacts + m.sum_cos2, 2 * m.contacts);
  g.phi22 = ratio(m.contacts - m.sum_cos2, 2 * m.contacts);
  g.phi12 = ratio(m.sum_sin2, 2 * m.contacts);
  g.chi11 = ratio(m.sum_f + m.sum_f_cos2, 2 * m.sum_f);
  g.chi22 = ratio(m.sum_f - m.sum_f_cos2, 2 * m.sum_f);
  g.chi12 = ratio(m.sum_f_sin2, 2 * m.sum_f);
  g.a_c = ratio(2 * m.sum_sin2, m.contacts);          // 4 φ12
  g.a_c_prime = ratio(2 * m.sum_cos2, m.contacts);    // 2 (φ11 − φ22)
  const double X = ratio(2 * m.sum_f_sin2, m.sum_f);  // 4 χ12
  const double Y = ratio(2 * m.sum_f_cos2, m.sum_f);  // 2 (χ11 − χ22)
  const FabricInversion inv = invert_force_fabric(g.a_c, g.a_c_prime, X / 4, Y / 2);
  g.a_f = inv.a_f;
  g.a_f_prime = inv.a_f_prime;
  g.fabric_norm = inv.fabric_norm;
  g.a_f_first_order = X - g.a_c;
  g.a_f_prime_first_order = Y - g.a_c_prime;
  // Σ_αβ ∝ Σ |b| F_bc n_α n_β: p ∝ ½Σ|b|F_bc, s = −Σxy ∝ −½Σ|b|F_bc sin2θ.
  g.shear_ratio_collisional_frames = ratio(-m.sum_bf_sin2, m.sum_bf);
  g.mean_binary_force = ratio(m.sum_f, m.contacts);
  return g;
}

Harmonic harmonic(std::span<const double> binned, int m) {
  const std::size_t K = binned.size();
  if (K == 0) return {kNaN, kNaN};
  double mean = 0;
  for (double f : binned) mean += f;
  mean /= double(K);
  if (!(mean != 0) || !std::isfinite(mean)) return {kNaN, kNaN};
  const double width = M_PI / double(K);
  double s = 0, c = 0;
  for (std::size_t k = 0; k < K; ++k) {
    const double theta = (double(k) + 0.5) * width;
    s += binned[k] / mean * std::sin(m * theta);
    c += binned[k] / mean * std::cos(m * theta);
  }
  // A bin holds the average of cos(mθ) over its width: cos(mθ_k)·sinc(mΔθ/2).
  const double u = m * width / 2;
  const double sinc = u != 0 ? std::sin(u) / u : 1.0;
  return {2 * s / (double(K) * sinc), 2 * c / (double(K) * sinc)};
}

}  // namespace granflow::network
