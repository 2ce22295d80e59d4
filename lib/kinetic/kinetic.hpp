#pragma once
// Kinetic theory of inelastic hard disks (d = 2), thesis §6.1: the formulas gf-kinetic
// compares the measured stresses and collision rates with. Plain functions, no I/O.
//
// Conventions (docs/method/kinetic.md):
// - T is the thesis' granular temperature (eq. 4.5): ⟨|V|²⟩ over both components of the
//   peculiar velocity, WITHOUT the mass. The temperature per degree of freedom is
//   T_k = mT/2.
// - ν is the area fraction, πnσ²/4 for equal disks; n the number density (grains per unit
//   area), m the grain mass, σ the grain diameter (the mean m and σ for a polydisperse
//   packing, as the thesis does), e the normal restitution.
// - Units are whatever the caller's n, m, σ, T are in: pressures come out in m·T/area
//   (force per unit length in 2D), viscosities in m/σ·√T, frequencies in √T/σ.
// - Two viscosity units appear: the thesis' η⁰ = (m/σ)√(T/2π) (eq. 6.10's normalisation),
//   and Garzó–Dufty's η₀(d) (below); in 2D η⁰ = 2·η₀(2D).
#include <cmath>

namespace granflow::kinetic {

// ---- Equilibrium hard disks (e = 1, γ̇ = 0) ----

// Henderson's contact value of the pair correlation of equal hard disks,
// χ(ν) = (1 − 7ν/16)/(1 − ν)² (Henderson, Mol. Phys. 30, 971 (1975)); dimensionless.
double henderson_chi(double nu);

// Henderson's compressibility factor Z = p/(nT_k) = (1 + ν²/8)/(1 − ν)². It overestimates
// Z above ν ≈ 0.6 (by ≈ 13 % near ν = 0.7). Expanded, Z = 1 + 2ν + (25/8)ν² + (17/4)ν³ + …
double henderson_z(double nu);

// Exact virial coefficients of hard disks in powers of the area fraction,
// Z = 1 + 2ν + B₃ν² + B₄ν³ + …: B₃ = 4(4/3 − √3/π), B₄ = 8(2 − 9√3/(2π) + 10/π²).
inline const double kVirialB3 = 4 * (4.0 / 3 - std::sqrt(3.0) / M_PI);
inline const double kVirialB4 = 8 * (2 - 9 * std::sqrt(3.0) / (2 * M_PI) + 10 / (M_PI * M_PI));

// The virial series of Z through third order in ν: 1 + 2ν + B₃ν² + B₄ν³.
double virial_z(double nu);

// The hard-disk virial relation Z = 1 + 2νχ, exact in equilibrium with χ = g(σ⁺), and its
// inverse χ = (Z − 1)/(2ν): χ from a measured pressure, Z = p/(nT_k) = 2p/(nmT).
double z_from_chi(double chi, double nu);
double chi_virial(double z, double nu);

// Enskog's collision frequency per grain, ω = nσχ√(2πT) = 2nσχ√(πT_k/m) (thesis §6.1, where
// "√(2πδT)" is a typesetting artefact), in collisions per grain per unit time: the number
// of collision events per unit time is Nω/2. And its inverse, the thesis' measurement of χ:
// χ = ω/(nσ√(2πT)).
double collision_frequency(double n, double sigma, double chi, double temperature);
double chi_from_collision_frequency(double omega, double n, double sigma, double temperature);

// ---- Normalisations of eqs. 6.9 and 6.10 ----

// p⁰ = nmT/2 = nT_k, the ideal-gas (kinetic) pressure.
double p0(double n, double m, double temperature);

// η⁰ = (m/σ)√(T/(2π)) = (1/σ)√(mT_k/π), the thesis' viscosity unit.
double eta0(double m, double sigma, double temperature);

// ---- Predictions for sheared inelastic disks ----

// The Enskog collisional pressure, eq. 6.9: p_pred = p⁰(1 + e)χν. The total Enskog pressure
// is p⁰ + p_pred; at e = 1 it is the virial p⁰·Z with Z = 1 + 2νχ.
double enskog_collisional_pressure(double p0, double e, double chi, double nu);

// Eq. 6.10 EXACTLY as printed in the thesis, s_pred/(γ̇η⁰), dimensionless:
//   (4ν/π)·[4/(5 − e) + νχ(1 + e)f(e)],
//   f(e) = (3e − 1)/(5 − e) + 1 − (1 − e)(1 − 2e²)/(81 − 17e + 30e²(1 − e)).
// The last fraction is Garzó–Dufty's a₂/16 = c*/32 with the 3D denominator (2D has
// 57 − 25e + 30e²(1 − e)), and its prefactors make it 1.9–2.6× the 2D collisional
// viscosity below (2.1–2.35× for ν = 0.2–0.5 at every e; 8/π as ν → 0 at e = 1). Kept as printed, not corrected:
// docs/method/kinetic.md.
double viscosity_thesis_eq6_10(double e, double nu, double chi);

// Garzó–Dufty's Navier–Stokes shear viscosity of inelastic hard spheres in d dimensions
// (Phys. Rev. E 59, 5895 (1999), first Sonine approximation, φ the volume (area) fraction),
// in units of η₀(d) = ((d + 2)/8)·Γ(d/2)·π^{−(d−1)/2}·σ^{1−d}·√(mT_k):
//   a₂ = 16(1 − e)(1 − 2e²)/[9 + 24d + (8d − 41)e + 30e²(1 − e)], c* = 2a₂,
//   ν_η* = (3/(4d))χ(1 − e + 2d/3)(1 + e)(1 − c*/64), ζ* = ((d + 2)/(4d))χ(1 − e²)(1 + 3c*/32),
//   η_k* = [1 − (2^{d−2}/(d + 2))(1 + e)(1 − 3e)φχ]/(ν_η* − ζ*/2),
//   γ* = (2^{2d+1}/(π(d + 2)))φ²χ(1 + e)(1 − c*/32),
//   η* = η_k*[1 + (2^{d−1}/(d + 2))φχ(1 + e)] + (d/(d + 2))γ*.
// kinetic = η_k*, collisional = η* − η_k* (the part a contact-stress measurement sees).
struct Viscosity {
  double kinetic = 0;
  double collisional = 0;
  double total = 0;
};
Viscosity viscosity_garzo_dufty(int d, double e, double phi, double chi);

// The same in 2D (φ = ν), converted to the thesis' unit η⁰ = 2·η₀(2D): directly comparable
// with viscosity_thesis_eq6_10 and with s/(γ̇η⁰) measured. At e = 1 the total is half of
// Gass's 1/χ + 2ν + (1 + 8/π)ν²χ (that one in units of η₀(2D)).
Viscosity viscosity_garzo_dufty_2d(double e, double nu, double chi);

// ---- Pre-collisional velocity correlation C_v (eq. 6.11) ----
// C_v = ⟨(v^i·σ̂)(v^j·σ̂)⟩/T over colliding pairs, peculiar velocities, T the thesis' T. Its
// value without correlations (molecular chaos: independent Maxwellian velocities) depends
// on how the collisions are averaged:
// - every collision counted once (flux-weighted: a pair approaching at normal speed g
//   collides at a rate ∝ g — what counting the collisions of each step gives): −1/4, since
//   the flux favours pairs moving towards each other (derivation in docs/method/kinetic.md);
// - every approaching pair at contact counted once, without the flux weight: 0.
// (Normalised by T_k/m = T/2 instead of T, the first would read −1/2.)
inline constexpr double kCvMolecularChaosPerCollision = -0.25;
inline constexpr double kCvMolecularChaosApproachingPairs = 0.0;

}  // namespace granflow::kinetic
