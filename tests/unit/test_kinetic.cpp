// The kinetic-theory formulas of lib/kinetic against values computed by hand or published:
// Henderson's χ and Z, the exact virial coefficients, Garzó–Dufty's viscosity at e = 1 (Gass
// in 2D, Enskog in 3D), eq. 6.10 as printed, and the molecular-chaos baseline of C_v.
#include "kinetic/kinetic.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/random.hpp"

namespace granflow::kinetic {
namespace {

TEST(Kinetic, HendersonAgainstPrintedValues) {
  // REFERENCES.md prints χ to four decimals; Z by hand: (1 + ν²/8)/(1 − ν)².
  EXPECT_NEAR(henderson_chi(0.1), 1.1806, 5e-5);
  EXPECT_NEAR(henderson_chi(0.3), 1.7730, 5e-5);
  EXPECT_NEAR(henderson_chi(0.5), 3.1250, 5e-5);
  EXPECT_NEAR(henderson_chi(0.6), 4.6094, 5e-5);
  EXPECT_NEAR(henderson_z(0.1), 1.00125 / 0.81, 1e-12);  // 1.236111
  EXPECT_NEAR(henderson_z(0.3), 1.01125 / 0.49, 1e-12);  // 2.063776 (Henderson's 2.064)
  EXPECT_NEAR(henderson_z(0.5), 4.125, 1e-12);           // 1.03125/0.25
  EXPECT_NEAR(henderson_z(0.6), 6.53125, 1e-12);         // 1.045/0.16
}

TEST(Kinetic, ExactVirialCoefficients) {
  EXPECT_NEAR(kVirialB3, 3.128018, 5e-7);
  EXPECT_NEAR(kVirialB4, 4.257854, 5e-7);
  EXPECT_NEAR(virial_z(0.1), 1 + 0.2 + 0.01 * 3.128018 + 0.001 * 4.257854, 1e-6);
}

TEST(Kinetic, HendersonSeriesAgainstExactVirial) {
  // Henderson's Z = (1 + ν²/8)(1 + 2ν + 3ν² + 4ν³ + …) = 1 + 2ν + (25/8)ν² + (17/4)ν³ + …:
  // exact to first order (the second virial coefficient, 2); its B₃ = 3.125 is 0.003018 (0.1 %)
  // below the exact 3.128018, its B₄ = 4.25 is 0.0079 below 4.257854.
  const double h = 1e-4;
  EXPECT_NEAR((henderson_z(h) - 1) / h, 2, 1e-3);
  EXPECT_NEAR((henderson_z(h) - 1 - 2 * h) / (h * h), 25.0 / 8, 1e-3);
  EXPECT_NEAR(kVirialB3 - 25.0 / 8, 0.003018, 5e-7);
  EXPECT_NEAR(kVirialB4 - 17.0 / 4, 0.007854, 5e-7);
  // At ν = 0.1 the two differ by the higher terms only: 1.236111 against 1.235538.
  EXPECT_NEAR(henderson_z(0.1) - virial_z(0.1), 5.73e-4, 1e-5);
}

TEST(Kinetic, VirialRelationAtElasticRestitution) {
  // χ = (Z − 1)/(2ν) inverts Z = 1 + 2νχ, and Henderson's χ is exactly the virial χ of his Z.
  for (double nu : {0.1, 0.3, 0.5, 0.6, 0.8}) {
    EXPECT_NEAR(chi_virial(henderson_z(nu), nu), henderson_chi(nu), 1e-12 * henderson_chi(nu)) << nu;
    EXPECT_NEAR(z_from_chi(henderson_chi(nu), nu), henderson_z(nu), 1e-12 * henderson_z(nu)) << nu;
    // The Enskog pressure at e = 1: p⁰ + p_pred (eq. 6.9) = p⁰ Z.
    const double p = p0(2.0, 3.0, 0.7);
    EXPECT_NEAR((p + enskog_collisional_pressure(p, 1, henderson_chi(nu), nu)) / p, henderson_z(nu), 1e-12);
  }
  // Eq. 6.9 by hand: p⁰ = 4, e = 0.5, χ = 2, ν = 0.3: 4·1.5·2·0.3 = 3.6.
  EXPECT_NEAR(enskog_collisional_pressure(4, 0.5, 2, 0.3), 3.6, 1e-12);
}

TEST(Kinetic, CollisionFrequencyRoundTrip) {
  // ω = nσχ√(2πT): with T = 1/(2π), n = 2, σ = 0.5, χ = 3 it is 3 by hand.
  EXPECT_NEAR(collision_frequency(2, 0.5, 3, 1 / (2 * M_PI)), 3, 1e-12);
  for (double chi : {1.0, 1.7729, 4.6}) {
    const double omega = collision_frequency(0.8, 1.3, chi, 2.5);
    EXPECT_NEAR(chi_from_collision_frequency(omega, 0.8, 1.3, 2.5), chi, 1e-12 * chi);
  }
}

TEST(Kinetic, Normalisations) {
  // p⁰ = nmT/2; η⁰ = (m/σ)√(T/2π). With T = 2π: η⁰ = m/σ.
  EXPECT_NEAR(p0(2, 3, 0.5), 1.5, 1e-12);
  EXPECT_NEAR(eta0(3, 2, 2 * M_PI), 1.5, 1e-12);
  // η⁰ = 2η₀(2D), η₀(2D) = ((2 + 2)/8)Γ(1)π^{−1/2}σ^{−1}√(mT_k), T_k = mT/2.
  const double m = 1.7, sigma = 0.9, T = 0.3, Tk = m * T / 2;
  EXPECT_NEAR(eta0(m, sigma, T), 2 * 0.5 / std::sqrt(M_PI) / sigma * std::sqrt(m * Tk), 1e-12);
}

TEST(Kinetic, GarzoDufty2dAtElasticRestitution) {
  // Total/collisional in units of η₀(2D), Henderson's χ (REFERENCES.md), to 5 decimals.
  const struct {
    double nu, total, collisional;
  } cases[] = {{0.1, 1.08893, 0.14187}, {0.3, 1.72993, 0.86590}, {0.5, 4.09069, 3.27069}};
  for (const auto& c : cases) {
    const Viscosity v = viscosity_garzo_dufty(2, 1, c.nu, henderson_chi(c.nu));
    EXPECT_NEAR(v.total, c.total, 5e-6) << c.nu;
    EXPECT_NEAR(v.collisional, c.collisional, 5e-6) << c.nu;
    EXPECT_NEAR(v.kinetic + v.collisional, v.total, 1e-12);
    // In the thesis' η⁰ = 2η₀(2D): half.
    const Viscosity w = viscosity_garzo_dufty_2d(1, c.nu, henderson_chi(c.nu));
    EXPECT_NEAR(w.total, c.total / 2, 5e-6) << c.nu;
    EXPECT_NEAR(w.collisional, c.collisional / 2, 5e-6) << c.nu;
  }
  // Gass's closed form 1/χ + 2ν + (1 + 8/π)ν²χ, for any χ.
  for (double nu : {0.05, 0.2, 0.4, 0.6, 0.75})
    for (double chi : {1.0, henderson_chi(nu), 7.5}) {
      const double gass = 1 / chi + 2 * nu + (1 + 8 / M_PI) * nu * nu * chi;
      EXPECT_NEAR(viscosity_garzo_dufty(2, 1, nu, chi).total, gass, 1e-12 * gass) << nu << " " << chi;
    }
}

TEST(Kinetic, GarzoDufty2dInelasticByHand) {
  // At e < 1 the a₂ terms count. By hand, d = 2, e = 0.5, φ = 0.2, χ = 1.42578125:
  //   9 + 48 + (16 − 41)·0.5 + 30·0.25·0.5 = 48.25;  a₂ = 16·0.5·0.5/48.25 = 0.0829016;  c* = 0.1658031
  //   ν_η* = (3/8)·1.42578125·(0.5 + 4/3)·1.5·(1 − c*/64) = 1.4703369·0.9974093 = 1.4665278
  //   ζ* = (4/8)·1.42578125·0.75·(1 + 3c*/32) = 0.5346680·1.0155440 = 0.5429789
  //   ν_η* − ζ*/2 = 1.4665278 − 0.2714894 = 1.1950383
  //   η_k* = [1 − (1/4)·1.5·(−0.5)·0.2·1.42578125]/1.1950383 = 1.0534668/1.1950383 = 0.8815339
  //   γ* = (32/(4π))·0.04·1.42578125·1.5·(1 − c*/32) = 0.2178434·0.9948186 = 0.2167146
  //   collisional = η_k*·(2/4)·0.2·1.42578125·1.5 + (2/4)γ* = 0.1885312 + 0.1083573 = 0.2968885
  //   total = 0.8815339 + 0.2968885 = 1.1784224 (units of η₀(2D))
  const Viscosity v = viscosity_garzo_dufty(2, 0.5, 0.2, 1.42578125);
  EXPECT_NEAR(v.kinetic, 0.8815339, 1e-7);
  EXPECT_NEAR(v.collisional, 0.2968885, 1e-7);
  EXPECT_NEAR(v.total, 1.1784224, 1e-7);
}

TEST(Kinetic, GarzoDuftyIn3dIsEnskogAtElasticRestitution) {
  // The general-d formulas at d = 3, e = 1 are Enskog's classic viscosity (Chapman–Cowling,
  // first Sonine approximation), in units of η₀(3D) = (5/16σ²)√(mT_k/π):
  // η/η₀ = (1 + (8/5)φχ)²/χ + (768/(25π))φ²χ.
  for (double phi : {0.05, 0.2, 0.4})
    for (double chi : {1.0, 2.5}) {
      const double enskog = std::pow(1 + 1.6 * phi * chi, 2) / chi + 768 / (25 * M_PI) * phi * phi * chi;
      EXPECT_NEAR(viscosity_garzo_dufty(3, 1, phi, chi).total, enskog, 1e-12 * enskog) << phi << " " << chi;
    }
}

TEST(Kinetic, ThesisEq6_10AsPrinted) {
  // By hand, e = 0, ν = 0.5, χ = 3.125 (Henderson's χ(0.5)):
  //   4/(5 − e) = 0.8
  //   f(0) = (3·0 − 1)/5 + 1 − (1·1)/(81 − 0 + 0) = −0.2 + 1 − 0.0123457 = 0.7876543
  //   νχ(1 + e) = 0.5·3.125·1 = 1.5625;  1.5625·0.7876543 = 1.2307099
  //   bracket = 0.8 + 1.2307099 = 2.0307099;  4ν/π = 2/π = 0.6366198
  //   s_pred/(γ̇η⁰) = 2.0307099·0.6366198 = 1.2927901
  EXPECT_NEAR(viscosity_thesis_eq6_10(0, 0.5, 3.125), 1.2927901, 1e-7);
  // By hand, e = 0.5, ν = 0.2, χ = 1.42578125 (Henderson's χ(0.2) = 0.9125/0.64):
  //   4/(5 − e) = 4/4.5 = 0.8888889
  //   (3e − 1)/(5 − e) = 0.5/4.5 = 0.1111111
  //   (1 − e)(1 − 2e²) = 0.5·0.5 = 0.25;  81 − 17·0.5 + 30·0.25·0.5 = 76.25;  0.25/76.25 = 0.0032787
  //   f(0.5) = 0.1111111 + 1 − 0.0032787 = 1.1078324
  //   νχ(1 + e) = 0.2·1.42578125·1.5 = 0.4277344;  0.4277344·1.1078324 = 0.4738580
  //   bracket = 0.8888889 + 0.4738580 = 1.3627469;  4ν/π = 0.8/π = 0.2546479
  //   s_pred/(γ̇η⁰) = 1.3627469·0.2546479 = 0.3470206
  EXPECT_NEAR(viscosity_thesis_eq6_10(0.5, 0.2, 1.42578125), 0.3470206, 1e-7);
}

TEST(Kinetic, ThesisEq6_10AgainstGarzoDuftyCollisional) {
  // Both in units of η⁰ with Henderson's χ. Over ν = 0.2–0.5 the printed formula is
  // 2.10–2.35× the 2D collisional viscosity at every e of the thesis' grid; outside it the
  // factor spans 1.94 (e = 0, ν = 0.85) to 2.55 (e = 1, ν → 0).
  double lo = 1e9, hi = 0, lo_all = 1e9, hi_all = 0;
  for (double e : {0.0, 0.1, 0.25, 0.5, 0.75, 0.92, 1.0})
    for (double nu = 0.05; nu < 0.851; nu += 0.05) {
      const double chi = henderson_chi(nu);
      const double ratio = viscosity_thesis_eq6_10(e, nu, chi) / viscosity_garzo_dufty_2d(e, nu, chi).collisional;
      lo_all = std::min(lo_all, ratio), hi_all = std::max(hi_all, ratio);
      if (nu > 0.199 && nu < 0.501) lo = std::min(lo, ratio), hi = std::max(hi, ratio);
    }
  EXPECT_GT(lo, 2.1);
  EXPECT_LT(hi, 2.4);
  EXPECT_GT(lo_all, 1.9);
  EXPECT_LT(hi_all, 2.6);
  // As ν → 0 both are linear in ν: 16ν/(π(5 − e)) against 2ν/(5 − e) when a₂ = 0, i.e. 8/π
  // exactly at e = 1 and e = 1/√2; elsewhere a₂ ≠ 0 moves GD's limit (e = 0: 2.462).
  for (double e : {1.0, 1 / std::sqrt(2.0)}) {
    const double nu = 1e-9;
    EXPECT_NEAR(viscosity_thesis_eq6_10(e, nu, 1) / viscosity_garzo_dufty_2d(e, nu, 1).collisional, 8 / M_PI, 1e-6)
        << e;
  }
}

TEST(Kinetic, VelocityCorrelationBaselinesUnderMolecularChaos) {
  // Independent Maxwellian normal velocities a = v^i·σ̂, b = v^j·σ̂, each of variance T/2
  // (T = ⟨|V|²⟩ over two components). A pair approaches when g = a − b > 0. Counting every
  // collision once weighs an approaching pair by its collision rate ∝ g; counting every
  // approaching pair at contact once does not.
  Rng rng(21);
  const double T = 1.3, s = std::sqrt(T / 2);
  double flux_sum = 0, flux_ab = 0, pairs = 0, pairs_ab = 0;
  for (int i = 0; i < 2000000; ++i) {
    const double a = s * rng.normal(), b = s * rng.normal(), g = a - b;
    if (g <= 0) continue;
    flux_sum += g, flux_ab += g * a * b;
    pairs += 1, pairs_ab += a * b;
  }
  // Standard errors ≈ 1e-3 for both with 10⁶ approaching pairs.
  EXPECT_NEAR(flux_ab / flux_sum / T, kCvMolecularChaosPerCollision, 4e-3);
  EXPECT_NEAR(pairs_ab / pairs / T, kCvMolecularChaosApproachingPairs, 4e-3);
}

}  // namespace
}  // namespace granflow::kinetic
