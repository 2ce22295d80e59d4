// Gravity and immobile grains (the incline's rough base): free fall, a bounce off a
// fixed grain, and a disk resting on one without jitter.
#include <gtest/gtest.h>

#include <cmath>

#include "dynamics/engine.hpp"
#include "helpers.hpp"

namespace granflow {
namespace {

Box open_box() {
  Box b;
  b.lx = 20;
  b.ly = 20;
  b.periodic_y = false;
  return b;
}

GrainState on_fixed_grain(double gap, Vec2 velocity) {
  GrainState s = make_grains({Vec2(5, 1), Vec2(5, 2 + gap)}, {0.5, 0.5});
  s.fixed[0] = 1;
  s.velocity[1] = velocity;
  return s;
}

TEST(Gravity, FreeFallIsExactEuler) {
  const Vec2 g(0.3, -9.81);
  const double dt = 1e-3;
  Engine engine(on_fixed_grain(5.0, Vec2(1, 2)), open_box(), 0.0, {0.5, 0.0, 0.0}, {}, dt, g);
  Vec2 r = engine.state().position[1], v(1, 2);
  for (int k = 0; k < 50; ++k) {
    engine.step();
    v += dt * g;
    r += dt * v;
  }
  EXPECT_EQ(engine.contacts().size(), 0u);
  EXPECT_EQ(engine.state().velocity[1], v);
  EXPECT_EQ(engine.state().position[1], r);
  EXPECT_EQ(engine.state().velocity[0], Vec2(0, 0));  // fixed grains feel no gravity
  EXPECT_EQ(engine.state().position[0], Vec2(5, 1));
}

TEST(Gravity, BounceOffFixedGrain) {
  const double e = 0.6, dt = 1e-3;
  Engine engine(on_fixed_grain(1e-4, Vec2(0, -1)), open_box(), 0.0, {e, 0.0, 0.0}, {}, dt, Vec2(0, -9.81));
  engine.step();
  ASSERT_EQ(engine.contacts().size(), 1u);
  EXPECT_NEAR(engine.state().velocity[1].y(), e, 1e-14);  // u_n⁺ = −e·u_n⁻ with the pre-step u_n⁻
  const double m = engine.state().mass[1];
  EXPECT_NEAR(engine.contacts().binary_force[0], (1 + e) * m / dt, 1e-10);  // reduced mass = m
  EXPECT_EQ(engine.state().velocity[0], Vec2(0, 0));
}

// Resting contact: u_n⁻ = 0 with zero gap is active with target u_n⁺ ≥ 0, so the
// normal force balances the weight exactly every step; no bounce, no sinking.
TEST(Gravity, RestingDiskStaysPut) {
  const double dt = 1e-3, g = 9.81;
  Engine engine(on_fixed_grain(0.0, Vec2(0, 0)), open_box(), 0.0, {0.8, 0.0, 0.5}, {}, dt, Vec2(0, -g));
  const Vec2 start = engine.state().position[1];
  const double m = engine.state().mass[1];
  for (int k = 0; k < 1000; ++k) {
    const StepReport& r = engine.step();
    ASSERT_EQ(r.contacts, 1);
    ASSERT_NEAR(engine.contacts().normal_force[0], m * g, 1e-12 * m * g);
    ASSERT_EQ(engine.contacts().age[0], k + 1);
    ASSERT_EQ(engine.contacts().binary_force[0], 0.0);
  }
  EXPECT_LT(engine.state().velocity[1].norm(), 1e-15);
  EXPECT_LT((engine.state().position[1] - start).norm(), 1e-15);
  EXPECT_LE(engine.last_report().max_overlap, 1e-15);
}

}  // namespace
}  // namespace granflow
