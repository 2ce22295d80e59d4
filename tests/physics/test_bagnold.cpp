// Bagnold invariance (§3.2, Fig. 4.2): rigid grains have no time scale of their own, so
// the same packing sheared at γ̇ and 10⁴γ̇ with the same strain step γ̇·dt follows the
// same trajectory in strain, with stresses and temperature scaling exactly as γ̇².
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <tuple>
#include <vector>

#include "dynamics/engine.hpp"
#include "helpers.hpp"
#include "packing/packing.hpp"
#include "shear/observables.hpp"

namespace granflow {
namespace {

struct Trace {
  std::vector<double> p, s, t;
  int contacts = 0, max_iterations = 0;
};

Trace run(const test::Packing& packing, double rate, const Material& mat, int steps) {
  GrainState s = packing.state;
  add_affine_flow(s, packing.box, rate);
  test::add_fluctuations(s, 0.3 * rate, 5);
  Engine engine(s, packing.box, rate, mat, {}, 1e-3 / rate);
  Trace tr;
  for (int k = 0; k < steps; ++k) {
    const StepReport& r = engine.step();
    EXPECT_TRUE(r.converged);
    tr.contacts += r.contacts;
    tr.max_iterations = std::max(tr.max_iterations, r.iterations);
    const Mat2 sigma = stress(engine.state(), engine.box(), rate, engine.contacts()).total();
    tr.p.push_back(pressure(sigma) / (rate * rate));
    tr.s.push_back(shear_stress(sigma) / (rate * rate));
    tr.t.push_back(granular_temperature(engine.state(), engine.box(), rate) / (rate * rate));
  }
  return tr;
}

double worst_relative(const std::vector<double>& a, const std::vector<double>& b, const std::vector<double>& scale) {
  double w = 0;
  for (std::size_t k = 0; k < a.size(); ++k) w = std::max(w, std::fabs(a[k] - b[k]) / std::fabs(scale[k]));
  return w;
}

// The system: N = 200 grains at ν = 0.8 (a relaxed packing, as gf-pack makes).
test::Packing dense_packing() {
  PackingParams params;
  params.grains = 200;
  params.packing_fraction = 0.8;
  params.seed = 3;
  const Packing made = make_biperiodic_packing(params);
  return {make_grains(made.position, made.radius), made.box};
}

void check(const test::Packing& packing, const Material& mat) {
  const int steps = 50;  // strain 0.05
  const Trace slow = run(packing, 1e-2, mat, steps), fast = run(packing, 1e2, mat, steps);
  // Enough contacts, and clusters that take many Gauss–Seidel sweeps, to test anything.
  EXPECT_GT(slow.contacts, 5 * steps);
  EXPECT_GT(slow.max_iterations, 10);
  std::cout << "Bagnold: " << slow.contacts << " contacts, up to " << slow.max_iterations << " sweeps\n";
  const double dp = worst_relative(slow.p, fast.p, slow.p);
  const double ds = worst_relative(slow.s, fast.s, slow.p);  // s may cross zero: relative to p
  const double dt = worst_relative(slow.t, fast.t, slow.t);
  std::cout << "Bagnold: largest relative difference p " << dp << ", s " << ds << ", T " << dt << "\n";
  EXPECT_LT(dp, 1e-6);
  EXPECT_LT(ds, 1e-6);
  EXPECT_LT(dt, 1e-6);
}

// The case: ν = 0.8, e = 0.5, μ = 0.
TEST(Bagnold, FrictionlessRateInvariance) { check(dense_packing(), {0.5, 0.0, 0.0}); }

// With friction at ν = 0.7 (at ν = 0.8 the first steps from a packing at rest need more
// sweeps than the default cap, see Shear.NonConvergenceIsCounted).
TEST(Bagnold, FrictionalRateInvariance) { check(test::random_packing(200, 0.7, 21), {0.7, 0.2, 0.4}); }

// Mean and standard error of a series from `blocks` equal consecutive block means (blocks
// longer than the correlation strain, so that their means are nearly independent).
struct Estimate {
  double mean = 0, error = 0;
};
Estimate block_average(const std::vector<double>& x, std::size_t first, int blocks) {
  const std::size_t length = (x.size() - first) / blocks;
  std::vector<double> means(blocks, 0.0);
  for (int b = 0; b < blocks; ++b) {
    for (std::size_t k = 0; k < length; ++k) means[b] += x[first + b * length + k];
    means[b] /= double(length);
  }
  Estimate e;
  for (double m : means) e.mean += m / blocks;
  double var = 0;
  for (double m : means) var += (m - e.mean) * (m - e.mean);
  e.error = std::sqrt(var / (blocks - 1) / blocks);
  return e;
}

// Fig. 4.2's claim at the size: the same packing (N = 200, ν = 0.8, e = 0.5, μ = 0)
// sheared at γ̇ = 10⁻² and 10² has the same steady p/γ̇², s/γ̇², T/γ̇². Round-off grows
// chaotically, so past the first strain units the two runs are independent samples of one
// steady state: their block averages (strain 0.5 to 12) must agree within 3 combined errors.
TEST(Bagnold, SteadyStateAveragesAgree) {
  const test::Packing packing = dense_packing();
  const Material mat{0.5, 0.0, 0.0};
  const int steps = 12000, transient = 500, blocks = 23;  // strain 12, steady from 0.5, 0.5 per block
  const Trace slow = run(packing, 1e-2, mat, steps), fast = run(packing, 1e2, mat, steps);
  for (const auto& [name, a, b] :
       {std::tuple("p", &slow.p, &fast.p), std::tuple("s", &slow.s, &fast.s), std::tuple("T", &slow.t, &fast.t)}) {
    const Estimate x = block_average(*a, transient, blocks), y = block_average(*b, transient, blocks);
    const double combined = std::hypot(x.error, y.error);
    std::cout << "Bagnold steady " << name << "/rate^2: " << x.mean << " +- " << x.error << " (1e-2) vs " << y.mean
              << " +- " << y.error << " (1e2)\n";
    EXPECT_GT(std::fabs(x.mean), 10 * x.error) << name << ": too noisy to compare anything";
    EXPECT_LT(std::fabs(x.mean - y.mean), 3 * combined) << name;
  }
}

}  // namespace
}  // namespace granflow
