#include "kinetic/kinetic.hpp"

#include <cmath>

namespace granflow::kinetic {

double henderson_chi(double nu) { return (1 - 7 * nu / 16) / ((1 - nu) * (1 - nu)); }

double henderson_z(double nu) { return (1 + nu * nu / 8) / ((1 - nu) * (1 - nu)); }

double virial_z(double nu) { return 1 + nu * (2 + nu * (kVirialB3 + nu * kVirialB4)); }

double z_from_chi(double chi, double nu) { return 1 + 2 * nu * chi; }

double chi_virial(double z, double nu) { return (z - 1) / (2 * nu); }

double collision_frequency(double n, double sigma, double chi, double temperature) {
  return n * sigma * chi * std::sqrt(2 * M_PI * temperature);
}

double chi_from_collision_frequency(double omega, double n, double sigma, double temperature) {
  return omega / (n * sigma * std::sqrt(2 * M_PI * temperature));
}

double p0(double n, double m, double temperature) { return n * m * temperature / 2; }

double eta0(double m, double sigma, double temperature) { return m / sigma * std::sqrt(temperature / (2 * M_PI)); }

double enskog_collisional_pressure(double p0, double e, double chi, double nu) { return p0 * (1 + e) * chi * nu; }

double viscosity_thesis_eq6_10(double e, double nu, double chi) {
  const double f = (3 * e - 1) / (5 - e) + (1 - (1 - e) * (1 - 2 * e * e) / (81 - 17 * e + 30 * e * e * (1 - e)));
  return 4 * nu / M_PI * (4 / (5 - e) + nu * chi * (1 + e) * f);
}

Viscosity viscosity_garzo_dufty(int d, double e, double phi, double chi) {
  const double dd = d;
  const double a2 = 16 * (1 - e) * (1 - 2 * e * e) / (9 + 24 * dd + (8 * dd - 41) * e + 30 * e * e * (1 - e));
  const double c = 2 * a2;
  const double nu_eta = 3 / (4 * dd) * chi * (1 - e + 2 * dd / 3) * (1 + e) * (1 - c / 64);
  const double zeta = (dd + 2) / (4 * dd) * chi * (1 - e * e) * (1 + 3 * c / 32);
  const double eta_k =
      (1 - std::ldexp(1.0, d - 2) / (dd + 2) * (1 + e) * (1 - 3 * e) * phi * chi) / (nu_eta - zeta / 2);
  const double gamma = std::ldexp(1.0, 2 * d + 1) / (M_PI * (dd + 2)) * phi * phi * chi * (1 + e) * (1 - c / 32);
  Viscosity v;
  v.kinetic = eta_k;
  v.collisional = eta_k * std::ldexp(1.0, d - 1) / (dd + 2) * phi * chi * (1 + e) + dd / (dd + 2) * gamma;
  v.total = v.kinetic + v.collisional;
  return v;
}

Viscosity viscosity_garzo_dufty_2d(double e, double nu, double chi) {
  // η⁰ = (1/σ)√(mT_k/π) and η₀(2D) = (1/(2σ))√(mT_k/π): a value in units of η₀(2D) is half
  // as large in units of η⁰.
  Viscosity v = viscosity_garzo_dufty(2, e, nu, chi);
  v.kinetic /= 2;
  v.collisional /= 2;
  v.total /= 2;
  return v;
}

}  // namespace granflow::kinetic
