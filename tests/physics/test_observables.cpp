// Temperature (eq. 4.5) and stress tensors (eq. 4.6, 6.2) of a hand-made state.
#include <gtest/gtest.h>

#include <cmath>

#include "shear/observables.hpp"

namespace granflow {
namespace {

TEST(Observables, HandComputedTemperatureAndStress) {
  Box box;
  box.lx = box.ly = 10;
  const double rate = 0.5;
  // Equal disks (m = π); streaming velocity γ̇(y − 5): 0, 0, 1.25, and a fixed grain.
  GrainState s = make_grains({Vec2(2, 5), Vec2(4, 5), Vec2(6, 7.5), Vec2(8, 1)}, {1, 1, 1, 1});
  s.velocity = {Vec2(1, 0), Vec2(-1, 2), Vec2(1.25, -2), Vec2(50, 50)};
  s.angular_velocity = {1, 2, 3, 100};
  s.fixed[3] = 1;
  // ṽ = (1, 0), (−1, 2), (0, −2): mean 0. ω − Ω = −1, 0, 1.
  // 3T = (1 + 5 + 4) + ½(1 + 0 + 1) = 11.
  EXPECT_NEAR(granular_temperature(s, box, rate), 11.0 / 3.0, 1e-14);

  ContactRecords c;
  // Contact 1: branch (−2, 0), n̂ = (−1, 0), t̂ = (0, −1); F = 3n̂ + 1t̂ = (−3, −1); F_bc = 2.
  // Contact 2: branch (0, 2), F = 5·(0, 1); F_bc = 1.
  c.pair = {{0, 1}, {1, 2}};
  c.branch = {Vec2(-2, 0), Vec2(0, 2)};
  c.normal_force = {3, 5};
  c.tangential_force = {1, 0};
  c.binary_force = {2, 1};
  c.pre_normal_velocity = {{0, 0}, {0, 0}};
  c.age = {1, 1};
  const StressTensors st = stress(s, box, rate, c);
  Mat2 kinetic, contact, collisional;
  kinetic << 2 * M_PI, -2 * M_PI, -2 * M_PI, 8 * M_PI;  // Σ m ṽṽ
  contact << 6, 2, 0, 10;                               // Σ σ_α F_β
  collisional << 4, 0, 0, 2;                            // Σ |σ| F_bc n̂n̂
  EXPECT_LT((st.kinetic - kinetic / 100).norm(), 1e-15);
  EXPECT_LT((st.contact - contact / 100).norm(), 1e-15);
  EXPECT_LT((st.collisional - collisional / 100).norm(), 1e-15);
  const Mat2 total = st.total();
  const double p = (2 * M_PI + 6 + 8 * M_PI + 10) / 200;
  EXPECT_NEAR(pressure(total), p, 1e-15);
  EXPECT_NEAR(shear_stress(total), (-2 * M_PI + 2) / 100, 1e-15);
  EXPECT_NEAR(normal_stress_difference(total), ((2 * M_PI + 6) - (8 * M_PI + 10)) / 100 / (2 * p), 1e-14);
}

}  // namespace
}  // namespace granflow
