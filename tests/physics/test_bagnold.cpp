// Bagnold invariance (§3.2, Fig. 4.2): rigid grains have no time scale of their own, so
// the same packing sheared at γ̇ and 10⁴γ̇ with the same strain step γ̇·dt follows the
// same trajectory in strain, with stresses and temperature scaling exactly as γ̇².
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <vector>

#include "dynamics/engine.hpp"
#include "dynamics/observables.hpp"
#include "helpers.hpp"

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

void check(const Material& mat) {
  const test::Packing packing = test::random_packing(200, 0.7, 21);
  const int steps = 50;  // strain 0.05
  const Trace slow = run(packing, 1e-2, mat, steps), fast = run(packing, 1e2, mat, steps);
  // Enough contacts, and clusters that take many Gauss–Seidel sweeps, to test anything.
  EXPECT_GT(slow.contacts, 5 * steps);
  EXPECT_GT(slow.max_iterations, 20);
  std::cout << "Bagnold: " << slow.contacts << " contacts, up to " << slow.max_iterations << " sweeps\n";
  const double dp = worst_relative(slow.p, fast.p, slow.p);
  const double ds = worst_relative(slow.s, fast.s, slow.p);  // s may cross zero: relative to p
  const double dt = worst_relative(slow.t, fast.t, slow.t);
  std::cout << "Bagnold: largest relative difference p " << dp << ", s " << ds << ", T " << dt << "\n";
  EXPECT_LT(dp, 1e-6);
  EXPECT_LT(ds, 1e-6);
  EXPECT_LT(dt, 1e-6);
}

TEST(Bagnold, FrictionlessRateInvariance) { check({0.5, 0.0, 0.0}); }

TEST(Bagnold, FrictionalRateInvariance) { check({0.7, 0.2, 0.4}); }

}  // namespace
}  // namespace granflow
