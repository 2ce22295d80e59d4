// Elastic, frictionless hard disks at rest on average (γ̇ = 0): a dilute gas whose
// kinetic energy and momentum the engine must keep over many collisions.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "dynamics/engine.hpp"
#include "helpers.hpp"
#include "shear/observables.hpp"

namespace granflow {
namespace {

TEST(Equilibrium, ElasticGasKeepsEnergyAndMomentum) {
  // No pair starts nearly touching (margin 0.05σ), so collisions come one at a time.
  test::Packing p = test::random_packing(100, 0.2, 31, 0.07);
  test::add_fluctuations(p.state, 1.0, 32);
  // Displacements of ~4e-4 diameters per step. Coarser steps merge chains of collisions
  // within one step into simultaneous, partly inelastic events (the contact closed by a
  // third grain is stopped at gap 0, then bounces): the CD approximation, not a bug, and
  // it vanishes as dt² per unit time.
  const double dt = 4e-4;
  Engine engine(p.state, p.box, 0.0, {1.0, 0.0, 0.0}, {}, dt);
  const double e0 = test::kinetic_energy(engine.state());
  const Vec2 p0 = test::fluctuating_momentum(engine.state(), engine.box(), 0.0);
  double mass = 0, worst_drift = 0, worst_overlap = 0;
  for (double m : p.state.mass) mass += m;
  const double momentum_scale = mass * std::sqrt(2 * e0 / mass);
  long collisions = 0, multi = 0;
  for (int k = 0; k < 10000; ++k) {
    const StepReport& r = engine.step();
    ASSERT_TRUE(r.converged);
    collisions += r.contacts;
    multi += r.contacts > 1;
    worst_overlap = std::max(worst_overlap, r.max_overlap);
    worst_drift = std::max(worst_drift, std::fabs(test::kinetic_energy(engine.state()) / e0 - 1));
    const Vec2 pk = test::fluctuating_momentum(engine.state(), engine.box(), 0.0);
    ASSERT_NEAR((pk - p0).norm(), 0.0, 1e-13 * momentum_scale) << "step " << k;
  }
  std::cout << "Equilibrium: " << collisions << " collisions (" << multi << " steps with several), energy drift "
            << worst_drift << ", max overlap " << worst_overlap << "\n";
  EXPECT_GT(collisions, 150);
  EXPECT_LT(worst_drift, 1e-4);
  EXPECT_EQ(worst_overlap, 0.0);
}

}  // namespace
}  // namespace granflow
