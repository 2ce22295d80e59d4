// The force-network model of lib/network (thesis §6.2) on constructed contact networks and
// sampled fabrics whose answers are known: the fabric inversion, Φ and Ψ, the coordination
// of long-lived contacts, the geometric sums to a non-integer limit, the prediction, the
// bin-corrected harmonics, and the analyser's refusal of malformed frames.
#include "network/network.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <stdexcept>
#include <vector>

#include "core/random.hpp"

namespace granflow::network {
namespace {

// Every field of a FrameSums, so that tests can add frames and leave groups out.
FrameSums combine(const FrameSums& a, const FrameSums& b, double sign) {
  FrameSums s;
  s.grains = a.grains + sign * b.grains;
  s.contacts = a.contacts + sign * b.contacts;
  s.long_lived = a.long_lived + sign * b.long_lived;
  s.active_grains = a.active_grains + sign * b.active_grains;
  s.deflection_pairs = a.deflection_pairs + sign * b.deflection_pairs;
  s.sum_cos = a.sum_cos + sign * b.sum_cos;
  s.sum_cos_cos2 = a.sum_cos_cos2 + sign * b.sum_cos_cos2;
  s.sum_sin2 = a.sum_sin2 + sign * b.sum_sin2;
  s.sum_cos2 = a.sum_cos2 + sign * b.sum_cos2;
  s.sum_f = a.sum_f + sign * b.sum_f;
  s.sum_f_sin2 = a.sum_f_sin2 + sign * b.sum_f_sin2;
  s.sum_f_cos2 = a.sum_f_cos2 + sign * b.sum_f_cos2;
  s.sum_b = a.sum_b + sign * b.sum_b;
  s.sum_b_sin2 = a.sum_b_sin2 + sign * b.sum_b_sin2;
  s.sum_b_cos2 = a.sum_b_cos2 + sign * b.sum_b_cos2;
  s.sum_bf = a.sum_bf + sign * b.sum_bf;
  s.sum_bf_sin2 = a.sum_bf_sin2 + sign * b.sum_bf_sin2;
  s.sum_bf_cos2 = a.sum_bf_cos2 + sign * b.sum_bf_cos2;
  return s;
}

// Leave-one-group-out jackknife of a statistic of the pooled sums: its value on all groups
// and its standard error.
struct Estimate {
  double value, error;
};
Estimate jackknife(const std::vector<FrameSums>& groups, const std::function<double(const FrameSums&)>& statistic) {
  FrameSums total;
  for (const FrameSums& g : groups) total = combine(total, g, 1);
  const double G = double(groups.size());
  std::vector<double> partial;
  double mean = 0;
  for (const FrameSums& g : groups) {
    partial.push_back(statistic(combine(total, g, -1)));
    mean += partial.back() / G;
  }
  double var = 0;
  for (double p : partial) var += (p - mean) * (p - mean);
  return {statistic(total), std::sqrt((G - 1) / G * var)};
}

double sample_standard_error(const std::vector<double>& x) {
  double mean = 0;
  for (double v : x) mean += v;
  mean /= double(x.size());
  double var = 0;
  for (double v : x) var += (v - mean) * (v - mean);
  return std::sqrt(var / double(x.size() - 1) / double(x.size()));
}

void add_contact(ContactRecords& c, int i, int j, Vec2 branch, std::int64_t age, double binary_force = 1.0) {
  c.pair.push_back({i, j});
  c.branch.push_back(branch);
  c.binary_force.push_back(binary_force);
  c.age.push_back(age);
}

// ---- Fabric and force fabric (eqs. 6.20–6.21) ----

// C(θ) = (1/2π)(1 + a_c sin2θ + a′_c cos2θ), F_bc(θ) = 1 + a_f sin2θ + a′_f cos2θ.
constexpr double kAc = 0.2, kAcPrime = -0.1, kAf = 0.3, kAfPrime = 0.05;
constexpr double kD = 1 + (kAc * kAf + kAcPrime * kAfPrime) / 2;  // 1.0275

TEST(Network, FabricTestValuesFromTheFormulas) {
  EXPECT_NEAR(kD, 1.0275, 1e-15);
  EXPECT_NEAR((kAc + kAf) / (4 * kD), 0.12165, 5e-6);             // χ12
  EXPECT_NEAR((kAcPrime + kAfPrime) / (2 * kD), -0.02433, 5e-6);  // χ11 − χ22
  // The exact χ returns the inputs.
  const FabricInversion inv =
      invert_force_fabric(kAc, kAcPrime, (kAc + kAf) / (4 * kD), (kAcPrime + kAfPrime) / (2 * kD));
  EXPECT_NEAR(inv.a_f, kAf, 1e-12);
  EXPECT_NEAR(inv.a_f_prime, kAfPrime, 1e-12);
  EXPECT_NEAR(inv.fabric_norm, kD, 1e-12);
  // A singular system (1 − X a_c/2 = 0 and no coupling) has no solution.
  const FabricInversion singular = invert_force_fabric(2.0, 0.0, 0.25, 0.1);
  EXPECT_TRUE(std::isnan(singular.a_f));
  EXPECT_TRUE(std::isnan(singular.a_f_prime));
}

TEST(Network, FabricInversionOnSampledContacts) {
  // 10⁶ directions drawn from C(θ) by rejection, forces with conditional mean F_bc(θ)
  // (exponential noise), branch lengths uniform in [0.9, 1.1]; 50 frames of 2·10⁴ contacts
  // between distinct grains, all new (age 1), so only the fabric sums are exercised.
  constexpr int kFrames = 50, kPerFrame = 20000;
  Rng rng(2022);
  const double c_max = 1 + std::hypot(kAc, kAcPrime);
  FrameAnalyser analyser;
  Histograms h(36, 36);
  std::vector<FrameSums> frames;
  std::vector<double> sin4;  // 2 sin4θ per contact: the 4θ coefficient's sampling spread
  std::vector<double> sin2;  // 2 sin2θ per contact
  for (int f = 0; f < kFrames; ++f) {
    ContactRecords c;
    for (int k = 0; k < kPerFrame; ++k) {
      double theta;
      do theta = rng.uniform(0, 2 * M_PI);
      while (rng.uniform() * c_max > 1 + kAc * std::sin(2 * theta) + kAcPrime * std::cos(2 * theta));
      const double mean_force = 1 + kAf * std::sin(2 * theta) + kAfPrime * std::cos(2 * theta);
      const double force = mean_force * -std::log(1 - rng.uniform());
      const double length = rng.uniform(0.9, 1.1);
      add_contact(c, 2 * k, 2 * k + 1, length * Vec2(std::cos(theta), std::sin(theta)), 1, force);
      sin4.push_back(2 * std::sin(4 * theta));
      sin2.push_back(2 * std::sin(2 * theta));
    }
    frames.push_back(analyser.analyse(c, 2 * kPerFrame, &h));
  }
  auto check = [&](const char* name, double expected, const std::function<double(const Ingredients&)>& pick) {
    const Estimate e = jackknife(frames, [&](const FrameSums& s) { return pick(ingredients(s)); });
    EXPECT_GT(e.error, 0) << name;
    EXPECT_LT(std::abs(e.value - expected), 4 * e.error) << name << " = " << e.value << " ± " << e.error;
    return e;
  };
  check("phi11", 0.475, [](const Ingredients& g) { return g.phi11; });
  check("phi22", 0.525, [](const Ingredients& g) { return g.phi22; });
  check("phi12", 0.05, [](const Ingredients& g) { return g.phi12; });
  check("chi12", (kAc + kAf) / (4 * kD), [](const Ingredients& g) { return g.chi12; });
  check("chi11-chi22", (kAcPrime + kAfPrime) / (2 * kD), [](const Ingredients& g) { return g.chi11 - g.chi22; });
  check("a_c", kAc, [](const Ingredients& g) { return g.a_c; });
  check("a_c_prime", kAcPrime, [](const Ingredients& g) { return g.a_c_prime; });
  check("a_f", kAf, [](const Ingredients& g) { return g.a_f; });
  check("a_f_prime", kAfPrime, [](const Ingredients& g) { return g.a_f_prime; });
  check("fabric_norm", kD, [](const Ingredients& g) { return g.fabric_norm; });
  // The first-order reading is off by (a_c + a_f)(1/D − 1) = −0.01338 and
  // (a′_c + a′_f)(1/D − 1) = +0.001338: far outside its sampling error.
  const Estimate d = check("a_f first order − exact", (kAc + kAf) * (1 / kD - 1),
                           [](const Ingredients& g) { return g.a_f_first_order - g.a_f; });
  EXPECT_GT(std::abs(d.value), 10 * d.error);
  check("a_f_prime first order − exact", (kAcPrime + kAfPrime) * (1 / kD - 1),
        [](const Ingredients& g) { return g.a_f_prime_first_order - g.a_f_prime; });
  // On the measured values the difference is the model's identity, to rounding.
  FrameSums total;
  for (const FrameSums& s : frames) total = combine(total, s, 1);
  const Ingredients g = ingredients(total);
  EXPECT_NEAR(g.a_f_first_order - g.a_f, (g.a_c + g.a_f) * (1 / g.fabric_norm - 1), 1e-12);
  EXPECT_NEAR(g.mean_binary_force, kD, 4 * 1.5 / std::sqrt(kFrames * kPerFrame));  // ⟨F⟩ contact-weighted = D
  // The pooled angular histogram: its 2θ coefficients are a_c, a′_c and its 4θ ones vanish,
  // within the spread of one contact's 2 sin mθ over √n (same estimator, binned).
  const Harmonic c2 = harmonic(h.angle_count, 2), c4 = harmonic(h.angle_count, 4);
  EXPECT_LT(std::abs(c2.sin_coefficient - kAc), 4 * sample_standard_error(sin2));
  EXPECT_LT(std::abs(c4.sin_coefficient), 4 * sample_standard_error(sin4));
  double counted = 0;
  for (double n : h.angle_count) counted += n;
  EXPECT_EQ(counted, double(kFrames * kPerFrame));
}

// ---- Deflections, Φ and Ψ (eq. 6.23) ----

TEST(Network, StraightChainHasNoDeflection) {
  // Grains 0, 1, 2 on the x axis: the middle one's partners lie on opposite sides.
  ContactRecords c;
  add_contact(c, 0, 1, Vec2(-1, 0), 2);
  add_contact(c, 1, 2, Vec2(-1, 0), 3);
  FrameAnalyser analyser;
  const FrameSums s = analyser.analyse(c, 3);
  EXPECT_EQ(s.deflection_pairs, 1);
  const Ingredients g = ingredients(s);
  EXPECT_DOUBLE_EQ(g.mean_cos, 1);
  EXPECT_DOUBLE_EQ(g.mean_cos_cos2, 1);
  EXPECT_DOUBLE_EQ(g.Phi, 2);
  EXPECT_DOUBLE_EQ(g.Psi, 2);
}

TEST(Network, HexagonalNeighbourhood) {
  // Grain 0 touched by six grains at 60° steps: 15 pairs of partners, at 60° (6 pairs,
  // cos x = −cos60° = −½), 120° (6, cos x = ½) and 180° (3, cos x = 1):
  // ⟨cos x⟩ = (−3 + 3 + 3)/15 = 0.2; cos2x = 2cos²x − 1 = −½, −½, 1, so
  // ⟨cos x cos2x⟩ = (6·¼ − 6·¼ + 3·1)/15 = 0.2 as well.
  ContactRecords c;
  for (int k = 1; k <= 6; ++k) {
    const double a = (k - 1) * M_PI / 3;
    add_contact(c, 0, k, -Vec2(std::cos(a), std::sin(a)), 2);  // r_0 − r_k
  }
  FrameAnalyser analyser;
  Histograms h(36, 36);
  const FrameSums s = analyser.analyse(c, 7, &h);
  EXPECT_EQ(s.deflection_pairs, 15);
  const Ingredients g = ingredients(s);
  EXPECT_NEAR(g.mean_cos, 0.2, 1e-15);
  EXPECT_NEAR(g.mean_cos_cos2, 0.2, 1e-15);
  EXPECT_NEAR(g.Phi, 0.4, 1e-15);
  // |x| = 0 (3 pairs), π/3 (6) and 2π/3 (6); the last two fall on bin edges (12Δx, 24Δx),
  // on either side by rounding.
  EXPECT_EQ(h.deflection_count[0], 3);
  EXPECT_EQ(h.deflection_count[11] + h.deflection_count[12], 6);
  EXPECT_EQ(h.deflection_count[23] + h.deflection_count[24], 6);
  // The hexagon is isotropic: no 2θ fabric.
  EXPECT_NEAR(g.a_c, 0, 1e-15);
  EXPECT_NEAR(g.a_c_prime, 0, 1e-15);
}

TEST(Network, UniformDeflectionsGiveTheThesisValues) {
  // 10⁶ grains, each with two long-lived partners at a deflection x uniform on
  // [−2π/3, 2π/3] and a random orientation: ⟨cos x⟩ = 3√3/(4π) = 0.4135,
  // ⟨cos x cos2x⟩ = 3√3/(8π) = 0.2067 (REFERENCES.md; the thesis' Φ ≈ 0.83 is twice the first).
  EXPECT_NEAR(3 * std::sqrt(3.0) / (4 * M_PI), 0.4135, 5e-5);
  EXPECT_NEAR(3 * std::sqrt(3.0) / (8 * M_PI), 0.2067, 5e-5);
  constexpr int kDraws = 1000000;
  Rng rng(622);
  ContactRecords c;
  std::vector<double> cos_x, cos_cos2;
  for (int d = 0; d < kDraws; ++d) {
    const double x = rng.uniform(-2 * M_PI / 3, 2 * M_PI / 3), a = rng.uniform(0, 2 * M_PI);
    const Vec2 u1(std::cos(a), std::sin(a));            // from I to m
    const Vec2 u2(-std::cos(a + x), -std::sin(a + x));  // from I to J: −u1 turned by x
    add_contact(c, 3 * d, 3 * d + 1, -u1, 2);           // r_I − r_m
    add_contact(c, 3 * d, 3 * d + 2, -u2, 2);           // r_I − r_J
    cos_x.push_back(std::cos(x));
    cos_cos2.push_back(std::cos(x) * std::cos(2 * x));
  }
  FrameAnalyser analyser;
  Histograms h(36, 36);
  const FrameSums s = analyser.analyse(c, 3 * kDraws, &h);
  EXPECT_EQ(s.deflection_pairs, kDraws);
  const Ingredients g = ingredients(s);
  EXPECT_LT(std::abs(g.mean_cos - 3 * std::sqrt(3.0) / (4 * M_PI)), 4 * sample_standard_error(cos_x));
  EXPECT_LT(std::abs(g.mean_cos_cos2 - 3 * std::sqrt(3.0) / (8 * M_PI)), 4 * sample_standard_error(cos_cos2));
  EXPECT_DOUBLE_EQ(g.Phi, 2 * g.mean_cos);
  EXPECT_DOUBLE_EQ(g.Psi, 2 * g.mean_cos_cos2);
  // P_C as a density over x ∈ [−π, π] (P_k = count_k/(2·pairs·Δx)) integrates to 1 and
  // vanishes beyond |x| = 2π/3 (bin 24 starts there).
  const double dx = M_PI / 36;
  double integral = 0;
  for (std::size_t k = 0; k < 36; ++k) integral += 2 * dx * h.deflection_count[k] / (2 * s.deflection_pairs * dx);
  EXPECT_NEAR(integral, 1, 1e-12);
  for (std::size_t k = 25; k < 36; ++k) EXPECT_EQ(h.deflection_count[k], 0) << k;
}

// ---- Coordination of long-lived contacts ----

TEST(Network, CoordinationOfLongLivedContactsOverTwoFrames) {
  // Six grains. Frame 1: (0,1) age 5, (1,2) age 2, (0,5) age 2 across the Lees–Edwards
  // boundary (grain 0 near the bottom wall of the cell, grain 5 near the top, the stored
  // branch is the minimum image, length 1), (2,3) and (3,4) new (age 1).
  // Long-lived: 3 pairs, stored once each; active grains 0, 1, 2, 5 (3 and 4 have only new
  // contacts): z = 2·3/6 = 1, z_active = 6/4 = 1.5.
  ContactRecords first;
  add_contact(first, 0, 1, Vec2(-1, 0), 5);
  add_contact(first, 0, 5, Vec2(0, 1), 2);
  add_contact(first, 1, 2, Vec2(-1, 0), 2);
  add_contact(first, 2, 3, Vec2(0, -1), 1);
  add_contact(first, 3, 4, Vec2(-1, 0), 1);
  FrameAnalyser analyser;
  const FrameSums s1 = analyser.analyse(first, 6);
  EXPECT_EQ(s1.contacts, 5);
  EXPECT_EQ(s1.long_lived, 3);
  EXPECT_EQ(s1.active_grains, 4);
  const Ingredients g1 = ingredients(s1);
  EXPECT_DOUBLE_EQ(g1.z, 1.0);
  EXPECT_DOUBLE_EQ(g1.z_active, 1.5);
  // Grain 0: partners 1 (+x) and 5 (−y, through the boundary): cos x = 0. Grain 1:
  // partners 0 (−x) and 2 (+x): cos x = 1. Grain 2 has one long-lived partner.
  EXPECT_EQ(s1.deflection_pairs, 2);
  EXPECT_DOUBLE_EQ(s1.sum_cos, 1.0);

  // Frame 2 (next stored step): (0,1) age 6, (0,5) age 3, (1,2) age 3, (2,3) age 2, (3,4)
  // gone, (4,5) new. Long-lived 4, active 0, 1, 2, 3, 5: z = 8/6, z_active = 8/5.
  ContactRecords second;
  add_contact(second, 0, 1, Vec2(-1, 0), 6);
  add_contact(second, 0, 5, Vec2(0, 1), 3);
  add_contact(second, 1, 2, Vec2(-1, 0), 3);
  add_contact(second, 2, 3, Vec2(0, -1), 2);
  add_contact(second, 4, 5, Vec2(-1, 0), 1);
  const FrameSums s2 = analyser.analyse(second, 6);  // the same analyser: buffers reused
  EXPECT_EQ(s2.long_lived, 4);
  EXPECT_EQ(s2.active_grains, 5);
  EXPECT_DOUBLE_EQ(ingredients(s2).z, 8.0 / 6);
  EXPECT_DOUBLE_EQ(ingredients(s2).z_active, 8.0 / 5);
  // Grain 2 now has partners 1 (−x) and 3 (+y): one more pair, cos x = 0.
  EXPECT_EQ(s2.deflection_pairs, 3);
  // The window: ratios of window means, z = 3.5/6, z_active = 3.5/4.5 (times 2).
  const Ingredients w = ingredients(combine(s1, s2, 1));
  EXPECT_DOUBLE_EQ(w.z, 7.0 / 6);
  EXPECT_DOUBLE_EQ(w.z_active, 7.0 / 4.5);
  // A frame without long-lived contacts: no deflections, Φ undefined.
  ContactRecords fresh;
  add_contact(fresh, 0, 1, Vec2(-1, 0), 1);
  const FrameSums s3 = analyser.analyse(fresh, 6);
  EXPECT_EQ(s3.long_lived, 0);
  EXPECT_EQ(s3.active_grains, 0);
  EXPECT_TRUE(std::isnan(ingredients(s3).Phi));
}

// ---- Geometric sums (eqs. 6.27–6.29) ----

double brute_power_sum(double b, int n) {
  double s = 0;
  for (int l = 1; l <= n; ++l) s += std::pow(b, l);
  return s;
}
double brute_mixed_sum(double q, double m, int n, double* magnitude = nullptr) {
  double s = 0, a = 0;
  for (int l = 1; l <= n; ++l)
    for (int i = 0; i <= l; ++i) {
      s += std::pow(q, i) * std::pow(m, l - i);
      a += std::abs(std::pow(q, i) * std::pow(m, l - i));
    }
  if (magnitude) *magnitude = a;
  return s;
}

TEST(Network, GeometricSumsAgainstBruteForceAtIntegerLimits) {
  Rng rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const double b = rng.uniform(-1.5, 1.5), q = rng.uniform(-1.5, 1.5);
    for (int L = 0; L <= 8; ++L) {
      double magnitude = 0;
      const double S = brute_power_sum(b, L);
      const double scale = 1e-13 * (1 + brute_power_sum(std::abs(b), L));
      for (SumLimit how : {SumLimit::continuation, SumLimit::floor}) {
        EXPECT_NEAR(power_sum(b, L, how), S, scale) << b << " " << L;
        const double W = brute_mixed_sum(q, b, L, &magnitude);
        EXPECT_NEAR(mixed_sum(q, b, L, how), W, 1e-13 * (1 + magnitude)) << q << " " << b << " " << L;
        EXPECT_NEAR(mixed_sum(b, b, L, how), brute_mixed_sum(b, b, L, &magnitude), 1e-13 * (1 + magnitude));
        const double near = b * (1 + 1e-9);
        EXPECT_NEAR(mixed_sum(near, b, L, how), brute_mixed_sum(near, b, L, &magnitude), 1e-13 * (1 + magnitude));
      }
      EXPECT_TRUE(continuation_real(b, L));
    }
  }
}

TEST(Network, GeometricSumsToANonIntegerLimit) {
  // REFERENCES.md's example: M = 0.8, L = 3.5.
  EXPECT_NEAR(power_sum(0.8, 3.5, SumLimit::continuation), 2.16821, 5e-6);
  EXPECT_NEAR(power_sum(0.8, 3.5, SumLimit::floor), 1.952, 1e-14);  // 0.8 + 0.64 + 0.512
  EXPECT_DOUBLE_EQ(power_sum(1.0, 3.5, SumLimit::continuation), 3.5);
  EXPECT_DOUBLE_EQ(power_sum(1.0, 3.5, SumLimit::floor), 3.0);
  EXPECT_DOUBLE_EQ(power_sum(0.0, 3.5, SumLimit::continuation), 0.0);
  EXPECT_DOUBLE_EQ(power_sum(0.8, 0.0, SumLimit::continuation), 0.0);
  // The continuation is continuous across an integer limit and near b = 1.
  EXPECT_NEAR(power_sum(0.8, 3 + 1e-9, SumLimit::continuation), 1.952, 1e-8);
  EXPECT_NEAR(power_sum(1 - 1e-12, 3.5, SumLimit::continuation), 3.5, 1e-10);
  // A negative base has no real continuation to a non-integer limit: the floor value.
  EXPECT_FALSE(continuation_real(-0.5, 3.5));
  EXPECT_TRUE(continuation_real(-0.5, 3.0));
  EXPECT_TRUE(continuation_real(0.5, 3.5));
  EXPECT_DOUBLE_EQ(power_sum(-0.5, 3.5, SumLimit::continuation), -0.375);  // −0.5 + 0.25 − 0.125
  EXPECT_DOUBLE_EQ(mixed_sum(-0.5, 0.5, 3.5, SumLimit::continuation), mixed_sum(-0.5, 0.5, 3, SumLimit::floor));

  // W(q, m, 3.5) = (m S(m) − q S(q))/(m − q), in long double here.
  auto S = [](long double b, long double L) { return b * (1 - std::pow(b, L)) / (1 - b); };
  auto dS = [](long double b, long double L) {
    return (1 - (L + 1) * std::pow(b, L) + L * std::pow(b, L + 1)) / ((1 - b) * (1 - b));
  };
  const long double m = 0.9L, q = 0.3L, L = 3.5L;
  EXPECT_NEAR(mixed_sum(0.3, 0.9, 3.5, SumLimit::continuation), double((m * S(m, L) - q * S(q, L)) / (m - q)), 1e-13);
  // The floor reading: brute force to ⌊L⌋.
  EXPECT_NEAR(mixed_sum(0.3, 0.9, 3.5, SumLimit::floor), brute_mixed_sum(0.3, 0.9, 3), 1e-14);
  // m = q: the limit S(m) + m S′(m) = 8.747488781613 at m = 0.9, and m ≈ q on either side of
  // the switch between the quotient and the limit form agree with it.
  const double limit = double(S(m, L) + m * dS(m, L));
  EXPECT_NEAR(limit, 8.747488781613, 1e-11);
  EXPECT_NEAR(mixed_sum(0.9, 0.9, 3.5, SumLimit::continuation), limit, 1e-12);
  // ∂W/∂q ≈ Σ_ℓ ℓ(ℓ + 1)/2·m^{ℓ−1} < 30 here: within 30|h| of the limit for tiny h; for
  // larger h the long double quotient (rounding ≈ 1e-19/h) is the reference.
  for (double h : {1e-12, -1e-9})
    EXPECT_NEAR(mixed_sum(0.9 + h, 0.9, 3.5, SumLimit::continuation), limit, 1e-12 + 30 * std::abs(h));
  for (double h : {5e-6, -8e-6, 2e-5, 1e-4}) {
    const long double mh = m + h;
    const double expected = double((m * S(m, L) - mh * S(mh, L)) / (m - mh));
    EXPECT_NEAR(mixed_sum(double(mh), 0.9, 3.5, SumLimit::continuation), expected, 1e-10 * limit) << h;
  }
  // At m = q = 1: L + L(L + 1)/2 = 3.5 + 7.875; and close to 1, where the closed S′ cancels.
  EXPECT_NEAR(mixed_sum(1.0, 1.0, 3.5, SumLimit::continuation), 11.375, 1e-12);
  EXPECT_NEAR(mixed_sum(1 - 1e-9, 1 - 1e-9, 3.5, SumLimit::continuation), 11.375, 1e-7);
  const long double b = 0.9999L;
  EXPECT_NEAR(mixed_sum(0.9999, 0.9999, 3.5, SumLimit::continuation), double(S(b, L) + b * dS(b, L)), 1e-10);
  EXPECT_THROW(power_sum(0.5, -1, SumLimit::floor), std::invalid_argument);
  EXPECT_TRUE(std::isnan(power_sum(0.5, std::nan(""), SumLimit::continuation)));
}

// ---- The prediction (eqs. 6.27–6.29) ----

TEST(Network, PredictionByHand) {
  // z = 4, Φ = 0.4, Ψ = 0.2: Φ(z − 1) = 1.2 capped to M = 1, Q = 0.6; ξ/ξ_el = 4, L = 3.
  // S(1, 3) = 3; S(0.6, 3) = 0.6 + 0.36 + 0.216 = 1.176;
  // W(0.6, 1, 3) = (1 + 0.6) + (1 + 0.6 + 0.36) + (1 + 0.6 + 0.36 + 0.216) = 5.736.
  // a_c = −0.2, a′_c = 0.1, a_f = −0.3, a′_f = 0.05:
  // shear = −½(−0.3·1.176 − 0.2·5.736) = 0.75; xx = 3 + 0.025·1.176 + 0.05·5.736 = 3.3162.
  for (SumLimit how : {SumLimit::continuation, SumLimit::floor}) {
    const Prediction p = predict(4, 0.4, 0.2, -0.2, 0.1, -0.3, 0.05, 4, how);
    EXPECT_NEAR(p.pressure, 3, 1e-14);
    EXPECT_NEAR(p.shear, 0.75, 1e-14);
    EXPECT_NEAR(p.xx, 3.3162, 1e-14);
    EXPECT_TRUE(p.continuation_real);
  }
  // z = 3: M = 0.8, Q = 0.4; ξ/ξ_el = 4.5, L = 3.5. Continuation:
  // S(0.8) = 4(1 − 0.8^3.5) = 2.1682131128, S(0.4) = (2/3)(1 − 0.4^3.5) = 0.6396818973,
  // W = (0.8·2.1682131128 − 0.4·0.6396818973)/0.4 = 3.6967443284;
  // shear = −½(−0.3·0.6396818973 − 0.2·3.6967443284) = 0.4656267174,
  // xx = 2.1682131128 + 0.025·0.6396818973 + 0.05·3.6967443284 = 2.3690423767.
  const Prediction c = predict(3, 0.4, 0.2, -0.2, 0.1, -0.3, 0.05, 4.5, SumLimit::continuation);
  EXPECT_NEAR(c.pressure, 2.1682131128, 1e-10);
  EXPECT_NEAR(c.shear, 0.4656267174, 1e-10);
  EXPECT_NEAR(c.xx, 2.3690423767, 1e-10);
  // Floor, L → 3: S(0.8) = 1.952, S(0.4) = 0.624, W = 1.2 + 1.12 + 0.96 = 3.28;
  // shear = −½(−0.1872 − 0.656) = 0.4216; xx = 1.952 + 0.0156 + 0.164 = 2.1316.
  const Prediction f = predict(3, 0.4, 0.2, -0.2, 0.1, -0.3, 0.05, 4.5, SumLimit::floor);
  EXPECT_NEAR(f.pressure, 1.952, 1e-14);
  EXPECT_NEAR(f.shear, 0.4216, 1e-14);
  EXPECT_NEAR(f.xx, 2.1316, 1e-14);
  // z = 0.5 (dilute): M = 0.8·(−0.5) = −0.4, Q = −0.2; L = 2.5 has no real continuation:
  // floor values, S(−0.4, 2) = −0.24, flagged.
  const Prediction n = predict(0.5, 0.8, 0.4, 0, 0, 0, 0, 3.5, SumLimit::continuation);
  EXPECT_NEAR(n.pressure, -0.24, 1e-15);
  EXPECT_FALSE(n.continuation_real);
  // ξ/ξ_el ≤ 1: empty sums; no ξ: NaN.
  const Prediction e = predict(4, 0.4, 0.2, -0.2, 0.1, -0.3, 0.05, 0.7, SumLimit::continuation);
  EXPECT_EQ(e.pressure, 0);
  EXPECT_EQ(e.shear, 0);
  EXPECT_EQ(e.xx, 0);
  EXPECT_TRUE(std::isnan(predict(4, 0.4, 0.2, 0, 0, 0, 0, std::nan(""), SumLimit::floor).pressure));
}

// ---- Harmonics of binned angular functions ----

TEST(Network, HarmonicOfBinAverages) {
  // f(θ) = 7(1 + 0.3 cos4θ + 0.2 sin2θ − 0.1 cos2θ) averaged over each of 36 bins of [0, π):
  // the bin average of cos mθ over [a, b] is (sin mb − sin ma)/(m(b − a)).
  constexpr int K = 36;
  std::vector<double> f(K);
  for (int k = 0; k < K; ++k) {
    const double a = k * M_PI / K, b = (k + 1) * M_PI / K, w = b - a;
    const double cos4 = (std::sin(4 * b) - std::sin(4 * a)) / (4 * w);
    const double sin2 = (std::cos(2 * a) - std::cos(2 * b)) / (2 * w);
    const double cos2 = (std::sin(2 * b) - std::sin(2 * a)) / (2 * w);
    f[k] = 7 * (1 + 0.3 * cos4 + 0.2 * sin2 - 0.1 * cos2);
  }
  const Harmonic h4 = harmonic(f, 4), h2 = harmonic(f, 2);
  EXPECT_NEAR(h4.cos_coefficient, 0.3, 1e-12);
  EXPECT_NEAR(h4.sin_coefficient, 0.0, 1e-12);
  EXPECT_NEAR(h2.sin_coefficient, 0.2, 1e-12);
  EXPECT_NEAR(h2.cos_coefficient, -0.1, 1e-12);
  EXPECT_TRUE(std::isnan(harmonic(std::vector<double>(K, 0.0), 4).sin_coefficient));
}

// ---- Malformed frames ----

TEST(Network, AnalyserRefusesMalformedFrames) {
  FrameAnalyser analyser;
  auto refused = [&](const ContactRecords& c, std::size_t grains) {
    EXPECT_THROW(analyser.analyse(c, grains), std::invalid_argument);
  };
  ContactRecords out_of_range;
  add_contact(out_of_range, 0, 3, Vec2(1, 0), 2);
  refused(out_of_range, 3);
  ContactRecords negative;
  add_contact(negative, -1, 2, Vec2(1, 0), 2);
  refused(negative, 3);
  ContactRecords self;
  add_contact(self, 1, 1, Vec2(1, 0), 2);
  refused(self, 3);
  ContactRecords zero_branch;
  add_contact(zero_branch, 0, 1, Vec2(0, 0), 2);
  refused(zero_branch, 3);
  ContactRecords ragged;
  add_contact(ragged, 0, 1, Vec2(1, 0), 2);
  add_contact(ragged, 1, 2, Vec2(1, 0), 2);
  ragged.binary_force.pop_back();
  refused(ragged, 3);
  ContactRecords ragged_unused = ragged;
  ragged_unused.binary_force.push_back(1);
  ragged_unused.normal_force = {1.0};  // present but one row short
  refused(ragged_unused, 3);
  // The analyser is still usable after a refusal.
  ContactRecords fine;
  add_contact(fine, 0, 1, Vec2(1, 0), 2);
  EXPECT_EQ(analyser.analyse(fine, 3).long_lived, 1);
  Histograms a(36, 36), b(18, 36);
  EXPECT_THROW(a.add(b), std::invalid_argument);
  EXPECT_THROW(Histograms(0, 36), std::invalid_argument);
}

}  // namespace
}  // namespace granflow::network
