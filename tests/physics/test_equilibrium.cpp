// Elastic, frictionless hard disks at rest on average (γ̇ = 0): a dilute gas whose
// kinetic energy and momentum the engine must keep over many collisions.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <vector>

#include "dynamics/engine.hpp"
#include "helpers.hpp"
#include "shear/observables.hpp"
#include "statistics/blocking.hpp"

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

// The molecular-chaos baseline of the velocity correlation C_v (thesis eq. 6.11), every
// collision counted once: in a dilute elastic gas the pre-collisional normal velocities
// a = V_i·n, b = V_j·n of a colliding pair are independent Gaussians of variance T/2
// (T = ⟨|V|²⟩, two components) weighted by the rate of approach (a − b)⁺, so that
// ⟨ab⟩ = (⟨w²⟩ − ⟨u³⟩⁺/⟨u⟩⁺)/2 = (T/2 − T)/2 = −T/4 with u, w = (a ∓ b)/√2. The engine's
// collision_velocity_product, summed over collisions and divided by their number and T,
// must give −1/4: not 0, which uncorrelated velocities without the collision bias would give.
TEST(Equilibrium, DiluteElasticGasVelocityCorrelationIsMinusOneQuarter) {
  // 500 equal disks (σ = 1) on a square lattice at ν = 0.1, spins zero (frictionless: they
  // stay zero, so the temperature is translational).
  const int side = 23, n = 500;
  const double sigma = 1, nu = 0.1;
  const double l = std::sqrt(n * M_PI * sigma * sigma / 4 / nu);
  std::vector<Vec2> pos;
  for (int k = 0; k < n; ++k) pos.emplace_back((k % side + 0.5) * l / side, (k / side + 0.5) * l / side);
  GrainState s = make_grains(pos, std::vector<double>(n, 0.5 * sigma));
  test::add_fluctuations(s, 1.0, 41);
  for (double& w : s.angular_velocity) w = 0;
  const double dt = 0.01;
  Engine engine(s, test::periodic_square(l), 0.0, {1.0, 0.0, 0.0}, {}, dt);
  for (int k = 0; k < 1000; ++k) engine.step();  // a few collisions per grain: the lattice forgotten
  // Rows of 10 steps; C_v = Σ product / (Σ collisions · T̄), its error from the blocked
  // error of the series product − C_v·collisions·T̄ (a ratio linearised; T̄ is constant here).
  std::vector<double> product, collisions, temperature;
  double p = 0, c = 0;
  for (int k = 1; k <= 5000; ++k) {
    const StepReport& r = engine.step();
    p += r.collision_velocity_product;
    c += r.collisions;
    if (k % 10 == 0) {
      product.push_back(p);
      collisions.push_back(c);
      temperature.push_back(granular_temperature(engine.state(), engine.box(), 0.0));
      p = c = 0;
    }
  }
  double sp = 0, sc = 0, st = 0;
  for (std::size_t k = 0; k < product.size(); ++k) sp += product[k], sc += collisions[k], st += temperature[k];
  const double t = st / double(temperature.size());
  const double cv = sp / (sc * t);
  std::vector<double> residual(product.size());
  for (std::size_t k = 0; k < product.size(); ++k) residual[k] = product[k] - cv * collisions[k] * t;
  const double error = blocking_error(residual).error / (sc / double(product.size()) * t);
  std::cout << "Dilute elastic gas: " << sc << " collisions, T = " << t << ", C_v = " << cv << " ± " << error << "\n";
  RecordProperty("collisions", std::to_string(sc));
  RecordProperty("velocity_correlation", std::to_string(cv));
  RecordProperty("velocity_correlation_error", std::to_string(error));
  ASSERT_GT(sc, 3000);
  EXPECT_NEAR(cv, -0.25, 3 * error);
  EXPECT_GT(std::fabs(cv), 5 * error);  // the statistics tell −1/4 from 0
  EXPECT_LT(error, 0.05);
}

}  // namespace
}  // namespace granflow
