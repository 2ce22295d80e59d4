// Simultaneous multi-contact impacts: the engine's impulses against a brute-force
// solution of the same one-step contact problem (enumeration of contact states, each
// a small linear system solved with Eigen). The Jacobian is built here from contact-
// point velocities, independently of the engine's formulas.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "core/random.hpp"
#include "dynamics/engine.hpp"
#include "helpers.hpp"

namespace granflow {
namespace {

struct Reference {
  std::vector<std::pair<int, int>> pairs;
  Eigen::VectorXd impulse;   // (P_n, P_t) per pair, in the frame n̂ = (r_i − r_j)/|…|, t̂ = ẑ × n̂
  Eigen::VectorXd velocity;  // (v_x, v_y, ω) per grain after the step
  int solutions = 0;         // distinct admissible contact-state assignments found
};

Reference brute_force(const GrainState& s, const Material& mat, double dt, double alert) {
  const int n = int(s.size());
  Reference ref;
  std::vector<Vec2> normal;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      const Vec2 d = s.position[i] - s.position[j];
      if (d.norm() - s.radius[i] - s.radius[j] < alert) {
        ref.pairs.emplace_back(i, j);
        normal.push_back(d.normalized());
      }
    }
  const int c = int(ref.pairs.size());
  // Relative velocity of the two surface points facing each other, r_i − R_i n̂ and r_j + R_j n̂.
  auto contact_velocity = [&](const Eigen::VectorXd& q, int k) {
    const auto [i, j] = ref.pairs[k];
    auto at = [&](int g, const Vec2& arm) {
      const Eigen::Vector3d v(q(3 * g), q(3 * g + 1), 0), w(0, 0, q(3 * g + 2));
      const Eigen::Vector3d u = v + w.cross(Eigen::Vector3d(arm.x(), arm.y(), 0));
      return Vec2(u.x(), u.y());
    };
    const Vec2 u = at(i, -s.radius[i] * normal[k]) - at(j, s.radius[j] * normal[k]);
    const Vec2 t(-normal[k].y(), normal[k].x());
    return Eigen::Vector2d(u.dot(normal[k]), u.dot(t));
  };
  Eigen::MatrixXd H(2 * c, 3 * n);
  for (int col = 0; col < 3 * n; ++col)
    for (int k = 0; k < c; ++k) H.block<2, 1>(2 * k, col) = contact_velocity(Eigen::VectorXd::Unit(3 * n, col), k);
  Eigen::VectorXd q0(3 * n), minv(3 * n);
  for (int g = 0; g < n; ++g) {
    q0.segment<3>(3 * g) << s.velocity[g].x(), s.velocity[g].y(), s.angular_velocity[g];
    minv.segment<3>(3 * g) << 1 / s.mass[g], 1 / s.mass[g], 2 / (s.mass[g] * s.radius[g] * s.radius[g]);
  }
  const Eigen::MatrixXd W = H * minv.asDiagonal() * H.transpose();
  const Eigen::VectorXd u0 = H * q0;
  // Targets by the engine's documented law.
  Eigen::VectorXd bn(c), bt(c);
  for (int k = 0; k < c; ++k) {
    const auto [i, j] = ref.pairs[k];
    const double gap = (s.position[i] - s.position[j]).norm() - s.radius[i] - s.radius[j];
    const double un = u0(2 * k);
    bn(k) = (gap <= 0 || gap + dt * un <= 0) ? (un < 0 ? -mat.restitution * un : 0.0) : -gap / dt;
    bt(k) = mat.tangential_restitution * u0(2 * k + 1);
  }
  // Contact states: 0 off, 1 stick, 2 slide with P_t = +μP_n, 3 slide with P_t = −μP_n.
  const int kinds = mat.friction > 0 ? 4 : 2;
  const double tol = 1e-10 * (1 + u0.cwiseAbs().maxCoeff());
  std::vector<Eigen::VectorXd> found;
  int combos = 1;
  for (int k = 0; k < c; ++k) combos *= kinds;
  for (int code = 0; code < combos; ++code) {
    std::vector<int> state(c);
    for (int k = 0, rest = code; k < c; ++k, rest /= kinds) state[k] = rest % kinds;
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * c, 2 * c);
    Eigen::VectorXd b = Eigen::VectorXd::Zero(2 * c);
    for (int k = 0; k < c; ++k) {
      const int rn = 2 * k, rt = 2 * k + 1;
      if (state[k] == 0) {
        A(rn, rn) = 1;
        A(rt, rt) = 1;
        continue;
      }
      A.row(rn) = W.row(rn);
      b(rn) = bn(k) - u0(rn);
      if (state[k] == 1 && mat.friction > 0) {
        A.row(rt) = W.row(rt);
        b(rt) = bt(k) - u0(rt);
      } else {  // sliding, or frictionless: P_t = ±μ P_n (= 0 when μ = 0)
        A(rt, rt) = 1;
        A(rt, rn) = state[k] == 3 ? mat.friction : -mat.friction;
      }
    }
    Eigen::FullPivLU<Eigen::MatrixXd> lu(A);
    if (!lu.isInvertible()) continue;
    const Eigen::VectorXd P = lu.solve(b);
    const Eigen::VectorXd u = u0 + W * P;
    bool ok = true;
    for (int k = 0; k < c && ok; ++k) {
      const double pn = P(2 * k), pt = P(2 * k + 1);
      if (state[k] == 0) ok = u(2 * k) >= bn(k) - tol;
      else ok = pn >= -tol && std::fabs(pt) <= mat.friction * pn + tol;
      if (ok && state[k] == 2) ok = u(2 * k + 1) <= bt(k) + tol;
      if (ok && state[k] == 3) ok = u(2 * k + 1) >= bt(k) - tol;
    }
    if (!ok) continue;
    bool seen = false;
    for (const auto& f : found) seen = seen || (f - P).cwiseAbs().maxCoeff() < 1e-9 * (1 + P.norm());
    if (!seen) found.push_back(P);
  }
  ref.solutions = int(found.size());
  if (!found.empty()) {
    ref.impulse = found[0];
    ref.velocity = q0 + minv.asDiagonal() * H.transpose() * found[0];
  }
  return ref;
}

void compare(const GrainState& s, const Material& mat, double dt) {
  Box box;
  box.lx = box.ly = 40;
  SolverSettings settings;
  settings.tolerance = 1e-14;  // tight, so that the comparison sees round-off only
  settings.alert_distance = 0.1;
  Engine engine(s, box, 0.0, mat, settings, dt);
  const Reference ref = brute_force(engine.state(), mat, dt, 0.1);
  ASSERT_EQ(ref.solutions, 1) << "the reference problem should have a unique solution";
  engine.step();
  EXPECT_TRUE(engine.last_report().converged);
  EXPECT_EQ(engine.last_report().candidates, int(ref.pairs.size()));

  std::map<std::pair<int, int>, std::pair<double, double>> got;
  const ContactRecords& rec = engine.contacts();
  for (std::size_t k = 0; k < rec.size(); ++k)
    got[{rec.pair[k][0], rec.pair[k][1]}] = {rec.normal_force[k] * dt, rec.tangential_force[k] * dt};
  const double scale = ref.impulse.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0.0);
  int active = 0;
  for (std::size_t k = 0; k < ref.pairs.size(); ++k) {
    const auto it = got.find(ref.pairs[k]);
    const double pn = it == got.end() ? 0.0 : it->second.first;
    const double pt = it == got.end() ? 0.0 : it->second.second;
    active += ref.impulse(2 * k) > 1e-9 * scale;
    EXPECT_NEAR(pn, ref.impulse(2 * k), 1e-9 * scale) << "pair " << ref.pairs[k].first << "-" << ref.pairs[k].second;
    EXPECT_NEAR(pt, ref.impulse(2 * k + 1), 1e-9 * scale)
        << "pair " << ref.pairs[k].first << "-" << ref.pairs[k].second;
  }
  EXPECT_GE(active, 2) << "not a multi-contact event";
  const GrainState& a = engine.state();
  for (std::size_t g = 0; g < a.size(); ++g) {
    const double vs = 1 + ref.velocity.cwiseAbs().maxCoeff();
    EXPECT_NEAR(a.velocity[g].x(), ref.velocity(3 * g), 1e-9 * vs);
    EXPECT_NEAR(a.velocity[g].y(), ref.velocity(3 * g + 1), 1e-9 * vs);
    EXPECT_NEAR(a.angular_velocity[g], ref.velocity(3 * g + 2), 1e-9 * vs / a.radius[g]);
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
