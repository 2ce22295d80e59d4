// Isolated binary collisions against closed-form results.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <string>
#include <vector>

#include "dynamics/engine.hpp"
#include "helpers.hpp"

namespace granflow {
namespace {

double inertia(const GrainState& s, int i) { return 0.5 * s.mass[i] * s.radius[i] * s.radius[i]; }

class HeadOn : public ::testing::TestWithParam<double> {};

// Unequal disks approaching along an oblique line from afar: no impulse until the
// step at which the pair is predicted to touch, then u_n⁺ = −e·u_n⁻ exactly, momentum
// conserved, and the gap never negative.
TEST_P(HeadOn, RestitutionExactNoOverlap) {
  const double e = GetParam();
  const Vec2 n(0.8, 0.6);
  GrainState s = make_grains({Vec2(12, 12), Vec2(12, 12) - 2.0 * n}, {0.7, 0.45});
  s.velocity[0] = -0.9 * n + 0.2 * perp(n);  // a glancing component: the normal at impact is not n
  s.velocity[1] = 0.6 * n;
  const double dt = 0.01;
  Engine engine(s, test::periodic_square(24), 0.0, {e, 0.0, 0.0}, {}, dt);
  const double mi = s.mass[0], mj = s.mass[1];
  const Vec2 momentum = mi * s.velocity[0] + mj * s.velocity[1];

  int collision_steps = 0;
  double un_before = 0, un_after = 0;
  double min_gap = INFINITY;
  for (int k = 0; k < 150; ++k) {
    const GrainState before = engine.state();
    const Vec2 d = engine.box().minimum_image(before.position[0] - before.position[1]);
    const Vec2 nn = d.normalized();
    const double gap = d.norm() - 0.7 - 0.45;
    const double un = (before.velocity[0] - before.velocity[1]).dot(nn);
    engine.step();
    const GrainState& after = engine.state();
    min_gap = std::min(min_gap, test::min_gap(after, engine.box()));
    const Vec2 p = mi * after.velocity[0] + mj * after.velocity[1];
    EXPECT_NEAR((p - momentum).norm(), 0.0, 1e-14 * mi);
    // The impulse comes exactly at the step where the pair is predicted to touch.
    const bool predicted = gap + dt * un <= 0;
    ASSERT_EQ(engine.contacts().size(), predicted ? 1u : 0u) << "step " << k;
    if (!predicted) continue;
    ++collision_steps;
    un_before = un;
    un_after = (after.velocity[0] - after.velocity[1]).dot(nn);
    const ContactRecords& c = engine.contacts();
    EXPECT_EQ(c.age[0], 1);
    const double reduced = mi * mj / (mi + mj);
    EXPECT_NEAR(c.normal_force[0], (1 + e) * reduced * -un / dt, 1e-12 * c.normal_force[0]);
    EXPECT_NEAR(c.binary_force[0], c.normal_force[0], 1e-12 * c.normal_force[0]);
    EXPECT_EQ(c.tangential_force[0], 0.0);
    EXPECT_NEAR(c.pre_normal_velocity[0][0], before.velocity[0].dot(nn), 1e-15);
    EXPECT_NEAR(c.pre_normal_velocity[0][1], before.velocity[1].dot(nn), 1e-15);
  }
  EXPECT_EQ(collision_steps, 1);
  EXPECT_LT(un_before, 0.0);
  EXPECT_NEAR(un_after, -e * un_before, 1e-12 * std::fabs(un_before));
  EXPECT_GE(min_gap, 0.0);
  EXPECT_EQ(engine.unconverged_steps(), 0);
}

INSTANTIATE_TEST_SUITE_P(TwoDisk, HeadOn, ::testing::Values(0.0, 0.25, 0.7, 1.0));

class HeadOnOverlap : public ::testing::TestWithParam<double> {};

// The same pair under the thesis' activation (SolverSettings::activation = overlap): no
// impulse while the pair is apart at the start of a step, so it overlaps first, by less than
// dt·|u_n⁻|; the impulse comes exactly at the first step that starts with g ≤ 0, with
// u_n⁺ = −e·u_n⁻, and momentum is conserved.
TEST_P(HeadOnOverlap, BouncesOnceOverlapping) {
  const double e = GetParam();
  const Vec2 n(0.8, 0.6);
  GrainState s = make_grains({Vec2(12, 12), Vec2(12, 12) - 2.0 * n}, {0.7, 0.45});
  s.velocity[0] = -0.9 * n + 0.2 * perp(n);
  s.velocity[1] = 0.6 * n;
  const double dt = 0.01;
  SolverSettings settings;
  settings.activation = Activation::overlap;
  Engine engine(s, test::periodic_square(24), 0.0, {e, 0.0, 0.0}, settings, dt);
  const double mi = s.mass[0], mj = s.mass[1];
  const Vec2 momentum = mi * s.velocity[0] + mj * s.velocity[1];

  int first = -1;
  double un_before = 0, un_after = 0, gap_at_impact = 0;
  for (int k = 0; k < 150; ++k) {
    const GrainState before = engine.state();
    const Vec2 d = engine.box().minimum_image(before.position[0] - before.position[1]);
    const Vec2 nn = d.normalized();
    const double gap = d.norm() - 0.7 - 0.45;
    const double un = (before.velocity[0] - before.velocity[1]).dot(nn);
    engine.step();
    const GrainState& after = engine.state();
    const Vec2 p = mi * after.velocity[0] + mj * after.velocity[1];
    EXPECT_NEAR((p - momentum).norm(), 0.0, 1e-14 * mi);
    if (first >= 0) continue;
    if (gap > 0) {
      ASSERT_EQ(engine.contacts().size(), 0u) << "step " << k << ": an impulse before the pair overlaps";
      continue;
    }
    ASSERT_EQ(engine.contacts().size(), 1u) << "step " << k;
    first = k;
    un_before = un;
    un_after = (after.velocity[0] - after.velocity[1]).dot(nn);
    gap_at_impact = gap;
    const double reduced = mi * mj / (mi + mj);
    EXPECT_NEAR(engine.contacts().normal_force[0], (1 + e) * reduced * -un / dt, 1e-12 * (1 + e) * reduced * -un / dt);
  }
  ASSERT_GE(first, 0);
  EXPECT_LT(un_before, 0.0);
  EXPECT_NEAR(un_after, -e * un_before, 1e-12 * std::fabs(un_before));
  // It overlapped (these numbers never touch exactly), by less than one step's approach.
  EXPECT_LT(gap_at_impact, 0.0);
  EXPECT_LT(-gap_at_impact, 1.05 * dt * std::fabs(un_before));
  EXPECT_EQ(engine.unconverged_steps(), 0);
}

INSTANTIATE_TEST_SUITE_P(TwoDisk, HeadOnOverlap, ::testing::Values(0.0, 0.25, 0.7, 1.0));

// Oblique frictional collision of a nearly touching pair, against the closed-form
// solution derived here from the contact-point velocity u = v + ω ẑ×(c − r) of each disk.
struct Oblique {
  double mu, et;
  Vec2 vi, vj;
  double wi, wj;
  const char* expect;  // "stick", "slide" or "none" (no tangential impulse)
};

class ObliqueCollision : public ::testing::TestWithParam<Oblique> {};

TEST_P(ObliqueCollision, MatchesClosedForm) {
  const Oblique& c = GetParam();
  const double e = 0.6, dt = 1e-3;
  const Vec2 n = Vec2(1.0, 0.3).normalized();
  const double ri = 0.6, rj = 0.8;
  GrainState s = make_grains({Vec2(10, 10), Vec2(10, 10) - (ri + rj + 1e-4) * n}, {ri, rj});
  s.velocity = {c.vi, c.vj};
  s.angular_velocity = {c.wi, c.wj};
  Engine engine(s, test::periodic_square(20), 0.0, {e, c.et, c.mu}, {}, dt);
  engine.step();
  ASSERT_EQ(engine.contacts().size(), 1u);

  // Closed form. Generalized velocities q = (v_x, v_y, ω) of both disks; contact point c.
  const Vec2 t(-n.y(), n.x());
  // Each disk is struck at its own surface point facing the other one.
  const Vec2 point[2] = {s.position[0] - ri * n, s.position[1] + rj * n};
  auto contact_velocity = [&](const Eigen::Matrix<double, 6, 1>& q) {
    auto at = [&](int g) {
      const Eigen::Vector3d v(q(3 * g), q(3 * g + 1), 0), w(0, 0, q(3 * g + 2));
      const Vec2 r = point[g] - s.position[g];
      const Eigen::Vector3d u = v + w.cross(Eigen::Vector3d(r.x(), r.y(), 0));
      return Vec2(u.x(), u.y());
    };
    const Vec2 u = at(0) - at(1);
    return Eigen::Vector2d(u.dot(n), u.dot(t));
  };
  Eigen::Matrix<double, 2, 6> H;
  for (int k = 0; k < 6; ++k) H.col(k) = contact_velocity(Eigen::Matrix<double, 6, 1>::Unit(k));
  Eigen::Matrix<double, 6, 1> q0, minv;
  q0 << c.vi.x(), c.vi.y(), c.wi, c.vj.x(), c.vj.y(), c.wj;
  minv << 1 / s.mass[0], 1 / s.mass[0], 1 / inertia(s, 0), 1 / s.mass[1], 1 / s.mass[1], 1 / inertia(s, 1);
  const Eigen::Matrix2d W = H * minv.asDiagonal() * H.transpose();
  const Eigen::Vector2d u0 = H * q0;
  ASSERT_LT(u0(0), 0.0);
  const Eigen::Vector2d du(-e * u0(0) - u0(0), c.et * u0(1) - u0(1));
  Eigen::Vector2d P = W.lu().solve(du);  // sticking
  const bool stick = std::fabs(P(1)) <= c.mu * P(0);
  if (!stick) {
    const double sign = P(1) > 0 ? 1 : -1;
    P(0) = du(0) / (W(0, 0) + sign * c.mu * W(0, 1));
    P(1) = sign * c.mu * P(0);
  }
  const Eigen::Matrix<double, 6, 1> q1 = q0 + minv.asDiagonal() * H.transpose() * P;

  const std::string expect = c.expect;
  if (expect == "stick") {
    EXPECT_TRUE(stick);
  } else if (expect == "slide") {
    EXPECT_FALSE(stick);
  } else {
    EXPECT_NEAR(P(1), 0.0, 1e-15);
  }
  const ContactRecords& rec = engine.contacts();
  const double scale = P.norm();
  EXPECT_NEAR(rec.normal_force[0] * dt, P(0), 1e-12 * scale);
  EXPECT_NEAR(rec.tangential_force[0] * dt, P(1), 1e-12 * scale);
  EXPECT_LE(std::fabs(rec.tangential_force[0]), c.mu * rec.normal_force[0] * (1 + 1e-14));
  const GrainState& a = engine.state();
  Eigen::Matrix<double, 6, 1> q;
  q << a.velocity[0].x(), a.velocity[0].y(), a.angular_velocity[0], a.velocity[1].x(), a.velocity[1].y(),
      a.angular_velocity[1];
  const double vscale = q0.norm();
  EXPECT_LT((q - q1).cwiseAbs().maxCoeff(), 1e-12 * vscale);
  const Eigen::Vector2d u1 = H * q;
  EXPECT_NEAR(u1(0), -e * u0(0), 1e-12 * vscale);
  if (stick) {
    EXPECT_NEAR(u1(1), c.et * u0(1), 1e-11 * vscale);
  }

  // Angular momentum of each disk about the point where it is struck is unchanged.
  for (int g = 0; g < 2; ++g) {
    const Vec2 arm = s.position[g] - point[g];
    const double l0 = s.mass[g] * cross(arm, s.velocity[g]) + inertia(s, g) * s.angular_velocity[g];
    const double l1 = s.mass[g] * cross(arm, a.velocity[g]) + inertia(s, g) * a.angular_velocity[g];
    EXPECT_NEAR(l1, l0, 1e-12 * (std::fabs(l0) + s.mass[g] * vscale));
  }
}

// n̂ = (1, 0.3)/|…| points from j to i; velocities chosen so that the pair approaches.
INSTANTIATE_TEST_SUITE_P(TwoDisk, ObliqueCollision,
                         ::testing::Values(Oblique{0.5, 0.0, Vec2(-1.0, 0.1), Vec2(0.2, 0.0), 0.0, 0.0, "stick"},
                                           Oblique{0.5, 0.0, Vec2(-1.0, 2.5), Vec2(0.2, -1.0), 1.0, 0.0, "slide"},
                                           Oblique{0.1, -0.5, Vec2(-1.0, 0.4), Vec2(0.0, 0.0), 0.0, -2.0, "slide"},
                                           Oblique{2.0, -0.5, Vec2(-1.0, 0.4), Vec2(0.0, 0.0), 0.0, -2.0, "stick"},
                                           Oblique{0.3, 0.4, Vec2(-1.0, 0.0), Vec2(0.0, 0.0), 0.5, 0.2, "stick"},
                                           Oblique{0.0, 0.0, Vec2(-1.0, 0.7), Vec2(0.3, 0.0), 2.0, 0.0, "none"}),
                         // Named by index and outcome: GoogleTest's default name prints the struct's bytes,
                         // padding and the string's address included, which change from build to build.
                         [](const ::testing::TestParamInfo<Oblique>& param_info) {
                           return std::to_string(param_info.index) + "_" + param_info.param.expect;
                         });

// Rolling without slip at the contact point (u_t = 0): no tangential impulse whatever μ.
// Fails if the sign of the spin term in u_t is wrong.
TEST(TwoDisk, MeshingGearsFeelNoFriction) {
  const Vec2 n(0, 1);
  const double ri = 0.5, rj = 0.9;
  GrainState s = make_grains({Vec2(10, 10), Vec2(10, 10) - (ri + rj + 1e-4) * n}, {ri, rj});
  s.velocity = {Vec2(0.3, -1.0), Vec2(0.0, 0.0)};
  // u_t = (v_i − v_j)·t̂ − (R_i ω_i + R_j ω_j) with t̂ = (−1, 0): −0.3 − (0.5·ω_i + 0.9·ω_j) = 0.
  s.angular_velocity = {0.6, -2.0 / 3.0};
  Engine engine(s, test::periodic_square(20), 0.0, {0.5, 0.0, 1.0}, {}, 1e-3);
  engine.step();
  ASSERT_EQ(engine.contacts().size(), 1u);
  EXPECT_NEAR(engine.contacts().tangential_force[0], 0.0, 1e-12 * engine.contacts().normal_force[0]);
  EXPECT_DOUBLE_EQ(engine.state().angular_velocity[0], 0.6);
}

}  // namespace
}  // namespace granflow
