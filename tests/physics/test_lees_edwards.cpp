// Lees–Edwards boundaries: contacts through the moving image, grains crossing the
// top and bottom, and conservation of the fluctuating momentum in a sheared cell.
#include <gtest/gtest.h>

#include <cmath>

#include "dynamics/engine.hpp"
#include "helpers.hpp"

namespace granflow {
namespace {

Box cell(double l, double offset) {
  Box b;
  b.lx = b.ly = l;
  b.periodic_y = true;
  b.offset = offset;
  return b;
}

// Grain 0 near the top, grain 1 near the bottom; 1's image above (shifted by +δ) is
// almost touching 0 and, both grains being at rest in the lab, moves towards it at
// γ̇·Ly. The impulses must equal those of the same pair inside the cell with v_1 = γ̇·Ly·x̂.
TEST(LeesEdwards, ContactThroughMovingImage) {
  const double rate = 0.5, l = 10, delta = 3, dt = 1e-3;
  const Material mat{0.6, 0.3, 0.4};
  const Vec2 n = Vec2(0.5, -std::sqrt(0.75));
  const Vec2 d = 1.001 * n;  // r_0 − image of r_1
  const Vec2 r0(5, 9.6);
  const Vec2 image = r0 - d;
  GrainState s = make_grains({r0, image - Vec2(delta, l)}, {0.5, 0.5});
  ASSERT_GT(s.position[1].y(), 0.0);
  s.angular_velocity = {0.7, -0.2};
  Engine sheared(s, cell(l, delta), rate, mat, {}, dt);

  GrainState ref = make_grains({Vec2(5, 5), Vec2(5, 5) - d}, {0.5, 0.5});
  ref.angular_velocity = s.angular_velocity;
  ref.velocity[1] = Vec2(rate * l, 0);
  Engine plain(ref, cell(l, 0), 0.0, mat, {}, dt);

  sheared.step();
  plain.step();
  ASSERT_EQ(sheared.contacts().size(), 1u);
  ASSERT_EQ(plain.contacts().size(), 1u);
  const ContactRecords &a = sheared.contacts(), &b = plain.contacts();
  const double m = 0.5 * s.mass[0];
  EXPECT_NEAR(a.normal_force[0] * dt, (1 + mat.restitution) * m * rate * l * n.x(), 1e-12);
  EXPECT_NEAR(a.normal_force[0], b.normal_force[0], 1e-12 * b.normal_force[0]);
  EXPECT_NEAR(a.tangential_force[0], b.tangential_force[0], 1e-12 * b.normal_force[0]);
  EXPECT_NEAR(a.binary_force[0], b.binary_force[0], 1e-12 * b.normal_force[0]);
  EXPECT_NE(a.tangential_force[0], 0.0);
  EXPECT_NEAR((a.branch[0] - d).norm(), 0.0, 1e-12);
  // Velocity changes are the same; the lab velocities differ by the image velocity.
  const GrainState &sa = sheared.state(), &sb = plain.state();
  EXPECT_NEAR((sa.velocity[0] - sb.velocity[0]).norm(), 0.0, 1e-12);
  EXPECT_NEAR((sa.velocity[1] - (sb.velocity[1] - Vec2(rate * l, 0))).norm(), 0.0, 1e-12);
  EXPECT_NEAR(sa.angular_velocity[0], sb.angular_velocity[0], 1e-12);
  EXPECT_NEAR(sa.angular_velocity[1], sb.angular_velocity[1], 1e-12);
  // Pre-step normal velocities are fluctuating ones: ṽ = v − γ̇(y − Ly/2)x̂.
  EXPECT_NEAR(a.pre_normal_velocity[0][0], -rate * (r0.y() - 5) * n.x(), 1e-12);
  EXPECT_NEAR(a.pre_normal_velocity[0][1], -rate * (s.position[1].y() - 5) * n.x(), 1e-12);
}

// A grain leaving through the top re-enters at the bottom shifted by −δ (the offset
// at the end of the step) with v_x − γ̇Ly; through the bottom, the opposite.
TEST(LeesEdwards, CrossingShiftsPositionAndVelocity) {
  const double rate = 0.8, l = 10, delta = 2.5, dt = 0.01;
  GrainState s = make_grains({Vec2(2, l - 0.005), Vec2(7, 0.004), Vec2(5, 5)}, {0.5, 0.5, 0.5});
  s.velocity = {Vec2(0.3, 1.0), Vec2(-0.2, -1.0), Vec2(0, 0)};
  Engine engine(s, cell(l, delta), rate, {0.5, 0.0, 0.0}, {}, dt);
  engine.step();
  const double offset = delta + rate * l * dt;
  EXPECT_NEAR(engine.box().offset, offset, 1e-15);
  const GrainState& a = engine.state();
  EXPECT_NEAR(a.position[0].y(), 0.005, 1e-12);
  EXPECT_NEAR(a.position[0].x(), 2 + 0.003 - offset + l, 1e-12);
  EXPECT_NEAR(a.velocity[0].x(), 0.3 - rate * l, 1e-14);
  EXPECT_EQ(a.velocity[0].y(), 1.0);
  EXPECT_NEAR(a.position[1].y(), l - 0.006, 1e-12);
  EXPECT_NEAR(a.position[1].x(), 7 - 0.002 + offset, 1e-12);
  EXPECT_NEAR(a.velocity[1].x(), -0.2 + rate * l, 1e-14);
}

// Two grains straddling the boundary keep a continuous separation while one crosses:
// d(t + dt) = d(t) + dt·(v_0 − v_1 − k·γ̇·Ly·x̂) in the minimum image, whatever the wrap.
TEST(LeesEdwards, SeparationContinuousAcrossBoundary) {
  const double rate = 0.1, l = 12, delta = 7.1, dt = 0.01;
  // Grain 1's image above sits at d = (−2.5, −1.2) from grain 0; 0 leaves through the
  // top, 1 through the bottom, and they never touch.
  GrainState s = make_grains({Vec2(4, l - 0.3), Vec2(4 - delta + l + 2.5, 0.9)}, {0.5, 0.6});
  s.velocity = {Vec2(0.4, 2.0), Vec2(0.1, -2.0)};
  Engine engine(s, cell(l, delta), rate, {0.5, 0.0, 0.0}, {}, dt);
  int crossings = 0;
  for (int k = 0; k < 60; ++k) {
    const GrainState before = engine.state();
    const Box box = engine.box();
    const Vec2 d = box.minimum_image(before.position[0] - before.position[1]);
    const double image = std::round((before.position[0].y() - before.position[1].y()) / l);
    const Vec2 expected = d + dt * (before.velocity[0] - before.velocity[1] - Vec2(image * rate * l, 0));
    engine.step();
    ASSERT_EQ(engine.contacts().size(), 0u);
    const GrainState& after = engine.state();
    for (int g = 0; g < 2; ++g) crossings += std::fabs(after.position[g].y() - before.position[g].y()) > 0.5 * l;
    // Equal up to a lattice vector of the sheared cell.
    const Vec2 now = after.position[0] - after.position[1];
    EXPECT_NEAR(engine.box().minimum_image(now - expected).norm(), 0.0, 1e-12) << "step " << k;
  }
  EXPECT_EQ(crossings, 2);
}

// Σ m ṽ in a dense sheared cell with collisions through the boundary. Lab momentum
// changes by multiples of m·γ̇Ly at crossings and image contacts; the fluctuating one
// obeys d(Σ m ṽ)/dt = −γ̇ (Σ m ṽ_y) x̂ (the SLLOD term of eq. 4.2 summed over grains),
// so it is constant when Σ m ṽ_y = 0. A net drift `lift` in y makes every grain cross.
void check_fluctuating_momentum(double lift, int min_crossings) {
  test::Packing p = test::random_packing(100, 0.7, 11);
  const double rate = 2.0, dt = 5e-4;
  add_affine_flow(p.state, p.box, rate);
  test::add_fluctuations(p.state, 2 * rate, 12);
  for (Vec2& v : p.state.velocity) v += Vec2(0.3 * rate, lift);
  Engine engine(p.state, p.box, rate, {0.5, 0.0, 0.4}, {}, dt);
  const Vec2 p0 = test::fluctuating_momentum(engine.state(), engine.box(), rate);
  double mass = 0;
  for (double m : p.state.mass) mass += m;
  const double scale = mass * (rate * p.box.ly + std::fabs(lift));
  int crossings = 0, boundary_contacts = 0;
  for (int k = 0; k < 2000; ++k) {
    const GrainState before = engine.state();
    const StepReport& r = engine.step();
    ASSERT_TRUE(r.converged);
    for (std::size_t i = 0; i < before.size(); ++i)
      crossings += std::fabs(engine.state().position[i].y() - before.position[i].y()) > 0.5 * p.box.ly;
    for (const auto& [i, j] : engine.contacts().pair)
      boundary_contacts += std::fabs(before.position[i].y() - before.position[j].y()) > 0.5 * p.box.ly;
    const Vec2 expected = p0 - Vec2(rate * (k + 1) * dt * p0.y(), 0);
    const Vec2 pk = test::fluctuating_momentum(engine.state(), engine.box(), rate);
    ASSERT_NEAR((pk - expected).norm(), 0.0, 1e-13 * scale) << "step " << k;
  }
  EXPECT_GE(crossings, min_crossings);
  EXPECT_GT(boundary_contacts, 100);
}

TEST(LeesEdwards, FluctuatingMomentumConserved) { check_fluctuating_momentum(0.0, 0); }

TEST(LeesEdwards, FluctuatingMomentumUnderDrift) { check_fluctuating_momentum(10.0, 50); }

}  // namespace
}  // namespace granflow
