// Dense Lees–Edwards shear runs: Coulomb's law on every contact, overlaps bounded by
// the solver tolerance, honest non-convergence reports, contact ages, exact restarts.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <map>
#include <utility>

#include "dynamics/engine.hpp"
#include "helpers.hpp"

namespace granflow {
namespace {

Engine sheared(int n, double nu, const Material& mat, std::uint64_t seed, SolverSettings settings = {}) {
  test::Packing p = test::random_packing(n, nu, seed);
  const double rate = 1.0;
  add_affine_flow(p.state, p.box, rate);
  test::add_fluctuations(p.state, 0.2 * rate, seed + 1);
  return Engine(p.state, p.box, rate, mat, settings, 1e-3 / rate);
}

TEST(Shear, CoulombBoundOnEveryContact) {
  const Material mat{0.5, 0.3, 0.4};
  Engine engine = sheared(200, 0.75, mat, 41);
  long contacts = 0, sliding = 0, sticking = 0;
  for (int k = 0; k < 500; ++k) {
    ASSERT_TRUE(engine.step().converged);
    const ContactRecords& c = engine.contacts();
    for (std::size_t q = 0; q < c.size(); ++q) {
      ASSERT_GT(c.normal_force[q], 0.0);
      const double ratio = std::fabs(c.tangential_force[q]) / c.normal_force[q];
      ASSERT_LE(ratio, mat.friction * (1 + 1e-14)) << "step " << k;
      ++contacts;
      sliding += ratio > mat.friction * (1 - 1e-12);
      sticking += ratio < 0.5 * mat.friction;
    }
  }
  std::cout << "Coulomb: " << contacts << " contacts, " << sliding << " sliding, " << sticking
            << " well inside the cone\n";
  EXPECT_GT(sliding, 100);
  EXPECT_GT(sticking, 100);
}

// The only source of overlap is the residual: Υ·dt = tolerance per step.
TEST(Shear, OverlapBelowTenTolerances) {
  for (const Material& mat : {Material{0.5, 0.0, 0.0}, Material{0.3, 0.0, 0.3}}) {
    SCOPED_TRACE(mat.friction);
    Engine engine = sheared(200, mat.friction > 0 ? 0.76 : 0.8, mat, 43);
    double worst = 0;
    long contacts = 0;
    for (int k = 0; k < 1000; ++k) {
      const StepReport& r = engine.step();
      ASSERT_TRUE(r.converged) << "step " << k;
      ASSERT_LT(r.residual, engine.settings().tolerance);
      worst = std::max(worst, r.max_overlap);
      contacts += r.contacts;
    }
    std::cout << "Overlap: " << contacts / 1000.0 << " contacts per step, max overlap " << worst << "\n";
    // Enough contacts to test anything. The count is chaotic: over seeds 43–52 of this set-up
    // it ranges over 45–75 per step, and any change in the order of the solver's updates
    // lands elsewhere in that range.
    EXPECT_GT(contacts, 40 * 1000);
    EXPECT_LT(worst, 10 * engine.settings().tolerance);
    EXPECT_GE(test::min_gap(engine.state(), engine.box()), -10 * engine.settings().tolerance);
  }
}

TEST(Shear, NonConvergenceIsCounted) {
  SolverSettings settings;
  settings.max_iterations = 3;
  Engine engine = sheared(200, 0.8, {0.5, 0.0, 0.0}, 47, settings);
  int failed = 0;
  for (int k = 0; k < 100; ++k) {
    const StepReport& r = engine.step();
    EXPECT_LE(r.iterations, 3);
    if (!r.converged) {
      ++failed;
      EXPECT_EQ(r.iterations, 3);
      EXPECT_GE(r.residual, settings.tolerance);
    }
  }
  EXPECT_GT(failed, 0);
  EXPECT_EQ(engine.unconverged_steps(), failed);
}

// Age: 1 for a pair without P_n > 0 in the previous step, else the previous age + 1.
TEST(Shear, ContactAgeCountsConsecutiveSteps) {
  Engine engine = sheared(200, 0.8, {0.2, 0.0, 0.2}, 53);
  std::map<std::pair<int, int>, int> previous;
  long old_contacts = 0;
  for (int k = 0; k < 300; ++k) {
    engine.step();
    std::map<std::pair<int, int>, int> now;
    const ContactRecords& c = engine.contacts();
    for (std::size_t q = 0; q < c.size(); ++q) {
      const std::pair<int, int> key(c.pair[q][0], c.pair[q][1]);
      ASSERT_LT(key.first, key.second);
      const auto it = previous.find(key);
      ASSERT_EQ(c.age[q], it == previous.end() ? 1 : it->second + 1);
      old_contacts += c.age[q] > 1;
      now[key] = c.age[q];
    }
    previous = std::move(now);
  }
  EXPECT_GT(old_contacts, 1000);
}

// A run continued from a copy of its state, box and contact memory is bit-identical.
TEST(Shear, RestartIsBitIdentical) {
  const Material mat{0.5, 0.2, 0.3};
  Engine reference = sheared(150, 0.78, mat, 59);
  for (int k = 0; k < 100; ++k) reference.step();
  Engine restarted(reference.state(), reference.box(), reference.rate(), mat, reference.settings(), reference.dt());
  restarted.restore(reference.step_count(), reference.memory());
  for (int k = 0; k < 100; ++k) {
    reference.step();
    restarted.step();
  }
  ASSERT_EQ(restarted.step_count(), reference.step_count());
  const GrainState &a = reference.state(), &b = restarted.state();
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a.position[i], b.position[i]);
    ASSERT_EQ(a.velocity[i], b.velocity[i]);
    ASSERT_EQ(a.angular_velocity[i], b.angular_velocity[i]);
    ASSERT_EQ(a.orientation[i], b.orientation[i]);
  }
  EXPECT_EQ(reference.box().offset, restarted.box().offset);
  EXPECT_EQ(reference.contacts().normal_force, restarted.contacts().normal_force);
  EXPECT_EQ(reference.contacts().age, restarted.contacts().age);
  EXPECT_GT(reference.contacts().size(), 0u);
  // Without the memory the solver starts cold and the trajectory differs in the last bits.
  Engine cold(reference.state(), reference.box(), reference.rate(), mat, reference.settings(), reference.dt());
  reference.step();
  cold.step();
  EXPECT_NE(reference.contacts().normal_force, cold.contacts().normal_force);
}

}  // namespace
}  // namespace granflow
