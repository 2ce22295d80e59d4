// Simultaneous multi-contact impacts: the engine's impulses against a brute-force
// solution of the same one-step contact problem (contact_brute_force.hpp: enumeration of
// contact states, each a small linear system solved with Eigen, the Jacobian built from
// contact-point velocities independently of the engine's formulas).
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <map>
#include <utility>
#include <vector>

#include "contact_brute_force.hpp"
#include "core/random.hpp"
#include "dynamics/engine.hpp"
#include "helpers.hpp"

namespace granflow {
namespace {

using test::brute_force;
using test::Reference;

void compare(const GrainState& s, const Material& mat, double dt) {
  Box box;
  box.lx = box.ly = 40;
  SolverSettings settings;
  settings.tolerance = 1e-14;  // tight, so that the comparison sees round-off only
  settings.alert_distance = 0.1;
  Engine engine(s, box, 0.0, mat, settings, dt);
  const Reference ref = brute_force(engine.state(), mat, dt, 0.1);
  ASSERT_EQ(ref.solutions.size(), 1u) << "the reference problem should have a unique solution";
  const Eigen::VectorXd& impulse = ref.solutions[0].impulse;
  const Eigen::VectorXd& velocity = ref.solutions[0].velocity;
  engine.step();
  EXPECT_TRUE(engine.last_report().converged);
  EXPECT_EQ(engine.last_report().candidates, int(ref.pairs.size()));

  std::map<std::pair<int, int>, std::pair<double, double>> got;
  const ContactRecords& rec = engine.contacts();
  for (std::size_t k = 0; k < rec.size(); ++k)
    got[{rec.pair[k][0], rec.pair[k][1]}] = {rec.normal_force[k] * dt, rec.tangential_force[k] * dt};
  const double scale = impulse.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0.0);
  int active = 0;
  for (std::size_t k = 0; k < ref.pairs.size(); ++k) {
    const auto it = got.find(ref.pairs[k]);
    const double pn = it == got.end() ? 0.0 : it->second.first;
    const double pt = it == got.end() ? 0.0 : it->second.second;
    active += impulse(2 * k) > 1e-9 * scale;
    EXPECT_NEAR(pn, impulse(2 * k), 1e-9 * scale) << "pair " << ref.pairs[k].first << "-" << ref.pairs[k].second;
    EXPECT_NEAR(pt, impulse(2 * k + 1), 1e-9 * scale) << "pair " << ref.pairs[k].first << "-" << ref.pairs[k].second;
  }
  EXPECT_GE(active, 2) << "not a multi-contact event";
  const GrainState& a = engine.state();
  for (std::size_t g = 0; g < a.size(); ++g) {
    const double vs = 1 + velocity.cwiseAbs().maxCoeff();
    EXPECT_NEAR(a.velocity[g].x(), velocity(3 * g), 1e-9 * vs);
    EXPECT_NEAR(a.velocity[g].y(), velocity(3 * g + 1), 1e-9 * vs);
    EXPECT_NEAR(a.angular_velocity[g], velocity(3 * g + 2), 1e-9 * vs / a.radius[g]);
  }
}

// Newton's cradle: a disk hits a touching pair at rest. Simultaneous impact, not a
// sequence of binary collisions.
TEST(Cluster, RowOfThree) {
  GrainState s = make_grains({Vec2(10, 10), Vec2(11, 10), Vec2(12, 10)}, {0.5, 0.5, 0.5});
  s.velocity[0] = Vec2(1, 0);
  for (double e : {0.0, 0.5, 1.0}) {
    SCOPED_TRACE(e);
    compare(s, {e, 0.0, 0.0}, 1e-3);
  }
}

// Three mutually touching disks of different sizes, all moving and squeezed together;
// optionally a fourth disk touching two of them from outside (five contacts). With
// friction the fourth disk would make the impulses non-unique (10 contact rows, 9
// relative degrees of freedom), so the frictional case uses the triangle alone.
GrainState squeezed_cluster(std::uint64_t seed, bool fourth) {
  const double ra = 0.7, rb = 0.5, rc = 0.6, rd = 0.45;
  auto third = [](Vec2 a, double la, Vec2 b, double lb) {  // touching point left of a→b
    const double base = (b - a).norm();
    const double x = (la * la - lb * lb + base * base) / (2 * base);
    const Vec2 u = (b - a) / base;
    return Vec2(a + x * u + std::sqrt(la * la - x * x) * perp(u));
  };
  const Vec2 a(15, 15), b = a + Vec2(ra + rb, 0);
  const Vec2 c = third(a, ra + rc, b, rb + rc);
  std::vector<Vec2> pos{a, b, c};
  std::vector<double> radii{ra, rb, rc};
  if (fourth) {
    pos.push_back(third(c, rc + rd, b, rb + rd));  // on the side away from a
    radii.push_back(rd);
  }
  GrainState s = make_grains(pos, radii);
  Rng rng(seed);
  Vec2 centre = Vec2::Zero();
  for (const Vec2& p : pos) centre += p / double(pos.size());
  for (std::size_t g = 0; g < s.size(); ++g) {
    s.velocity[g] = Vec2(rng.normal(), rng.normal()) + 2.0 * (centre - s.position[g]);
    s.angular_velocity[g] = rng.normal();
  }
  return s;
}

TEST(Cluster, FourDisksFrictionless) {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    SCOPED_TRACE(seed);
    compare(squeezed_cluster(seed, true), {0.5, 0.0, 0.0}, 1e-3);
  }
}

TEST(Cluster, TriangleFrictional) {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    SCOPED_TRACE(seed);
    compare(squeezed_cluster(seed, false), {0.5, 0.2, 0.3}, 1e-3);
    compare(squeezed_cluster(seed, false), {0.9, -0.4, 0.05}, 1e-3);
  }
}

// A large frictionless cluster of trees and loops, squeezed together: a chain of 30 disks,
// one end on a fixed disk, with a hexagonal patch on it (triangles: loops) and leaning
// columns on it (a comb: trees). Gauss–Seidel alone needs thousands of sweeps on such a
// chain; the exact cluster solve must land on the same velocities (unique without
// friction) within a few sweeps, so an error in it shows either as a wrong state or as
// many sweeps (a sign flipped in the matrix or the right-hand side: 655 and 2366).
TEST(Cluster, TreesAndLoopsSolvedExactly) {
  std::vector<Vec2> pos;
  for (int k = 0; k < 30; ++k) pos.emplace_back(10 + k, 10);
  for (int k = 0; k < 5; ++k) pos.emplace_back(10.5 + k, 10 + std::sqrt(3.0) / 2);
  const double pi = std::acos(-1.0);
  for (auto [foot, degrees] :
       {std::pair(10, 60), std::pair(14, 120), std::pair(18, 75), std::pair(22, 100), std::pair(26, 50)})
    for (int h = 1; h <= 4; ++h)  // leaning columns: leaves pushing at angles
      pos.push_back(Vec2(10 + foot, 10) + h * Vec2(std::cos(degrees * pi / 180), std::sin(degrees * pi / 180)));
  pos.emplace_back(9, 10);  // the fixed disk
  GrainState s = make_grains(pos, std::vector<double>(pos.size(), 0.5));
  s.fixed.back() = 1;
  Rng rng(7);
  const Vec2 centre(25, 11);
  for (std::size_t g = 0; g + 1 < s.size(); ++g)
    s.velocity[g] = centre - s.position[g] + 0.05 * Vec2(rng.normal(), rng.normal());
  const Material mat{0.0, 0.0, 0.0};
  Box box;
  box.lx = box.ly = 80;
  SolverSettings settings;
  settings.tolerance = 1e-14;
  settings.alert_distance = 0.1;
  Engine clusters(s, box, 0.0, mat, settings, 1e-3);
  settings.cluster_solves = false;
  settings.max_iterations = 200000;
  Engine plain(s, box, 0.0, mat, settings, 1e-3);
  const StepReport& a = clusters.step();
  const StepReport& b = plain.step();
  ASSERT_TRUE(a.converged && b.converged);
  std::cout << "Cluster: " << a.contacts << " contacts; " << a.iterations << " sweeps, " << a.cluster_solves
            << " cluster solves (largest " << a.largest_cluster << " rows); " << b.iterations << " sweeps without\n";
  EXPECT_GE(a.contacts, 50);
  EXPECT_GE(a.largest_cluster, 50);
  EXPECT_GT(b.iterations, 200);
  EXPECT_LE(a.iterations, 30);  // 13
  for (std::size_t g = 0; g < s.size(); ++g)
    EXPECT_LT((clusters.state().velocity[g] - plain.state().velocity[g]).norm(), 1e-9) << "grain " << g;
}

}  // namespace
}  // namespace granflow
