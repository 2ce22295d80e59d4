// The frictional one-step contact problem of small random clusters: the engine's impulses
// obey every contact law to round-off and equal a solution found independently, by
// enumerating the contact states (contact_brute_force.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <map>
#include <utility>
#include <vector>

#include "contact_brute_force.hpp"
#include "core/random.hpp"
#include "dynamics/engine.hpp"

namespace granflow {
namespace {

using test::brute_force;
using test::check_laws;
using test::ContactProblem;
using test::LawViolation;
using test::Reference;

// A hand-built problem of two coupled contacts whose solution is known: contact 0 sticks
// (|P_t| < μP_n, u_t⁺ = b_t), contact 1 slides (P_t = −μP_n, u_t⁺ > b_t). The free
// velocities are chosen as u⁻ = u⁺ − W·P so that P is the solution.
struct HandBuilt {
  ContactProblem problem;
  Eigen::VectorXd solution;
};

HandBuilt two_contacts() {
  HandBuilt h;
  ContactProblem& p = h.problem;
  p.pairs = {{0, 1}, {1, 2}};
  p.mu = 0.5;
  p.W.resize(4, 4);
  p.W << 1.0, 0.2, 0.3, -0.1,  //
      0.2, 3.0, 0.1, 0.4,      //
      0.3, 0.1, 1.2, 0.2,      //
      -0.1, 0.4, 0.2, 3.5;
  h.solution.resize(4);
  h.solution << 1.0, -0.2, 2.0, -1.0;  // |−0.2| < 0.5·1; −1 = −0.5·2
  p.bn.resize(2);
  p.bt.resize(2);
  p.bn << 0.25, 0.0;
  p.bt << 0.1, -0.3;
  Eigen::VectorXd after(4);
  after << p.bn(0), p.bt(0), p.bn(1), p.bt(1) + 0.8;  // both bounds tight; contact 1 slips forward
  p.u0 = after - p.W * h.solution;
  return h;
}

TEST(FrictionClusters, CheckLawsSeesEveryViolation) {
  const HandBuilt h = two_contacts();
  EXPECT_LE(check_laws(h.problem, h.solution).max(), 1e-14);
  // Each law broken once: that law's measure sees it (others may see it too).
  struct Broken {
    const char* law;
    int row;
    double value;
    double LawViolation::*measure;
  };
  const std::vector<Broken> broken{
      {"P_n >= 0", 0, -0.1, &LawViolation::nonnegative},
      {"u_n >= b_n", 0, 0.7, &LawViolation::bound},                 // too little push: penetrates
      {"complementarity", 0, 1.4, &LawViolation::complementarity},  // too much: pushes off
      {"|P_t| <= mu P_n", 3, -1.3, &LawViolation::cone},
      {"sticking => no slip", 1, -0.1, &LawViolation::stick},
      {"sliding against the slip", 3, 1.0, &LawViolation::slide},
  };
  for (const Broken& b : broken) {
    SCOPED_TRACE(b.law);
    Eigen::VectorXd P = h.solution;
    P(b.row) = b.value;
    const LawViolation v = check_laws(h.problem, P);
    EXPECT_GT(v.*b.measure, 1e-3) << "the check of this law does not see it broken";
  }
}

// Two disks hitting a fixed one (two independent binary collisions, e = 0, μ = 0.4): the
// enumeration finds the closed-form solution, and only it. Contact 0-1: n̂ = −x̂, t̂ = −ŷ,
// u⁻ = (−1, 0.05): P_n = m, sticking needs |P_t| = 0.05·m/3 < μP_n. Contact 0-2: n̂ = −ŷ,
// t̂ = x̂, u⁻ = (−1, −2): sticking would need 2m/3 > μP_n, so it slides, P_t = +μm, and
// u_t⁺ = −2 + 3μ = −0.8 keeps the sign that makes P_t oppose it.
TEST(FrictionClusters, BruteForceSolvesBinaryCollisions) {
  GrainState s = make_grains({Vec2(10, 10), Vec2(11, 10), Vec2(10, 11)}, {0.5, 0.5, 0.5});
  s.fixed[0] = 1;
  s.velocity[1] = Vec2(-1, 0.05);
  s.velocity[2] = Vec2(2, -1);
  const Reference ref = brute_force(s, {0.0, 0.0, 0.4}, 1e-3, 0.1);
  ASSERT_EQ(ref.pairs.size(), 2u);  // 1-2 is 0.41 apart
  ASSERT_EQ(ref.solutions.size(), 1u);
  EXPECT_FALSE(ref.redundant);
  const double m = s.mass[1];
  const Eigen::VectorXd& P = ref.solutions[0].impulse;
  EXPECT_NEAR(P(0), m, 1e-14);
  EXPECT_NEAR(P(1), -0.05 * m / 3, 1e-14);
  EXPECT_NEAR(P(2), m, 1e-14);
  EXPECT_NEAR(P(3), 0.4 * m, 1e-14);
  EXPECT_EQ(ref.solutions[0].state[0], test::ContactState::stick);
  EXPECT_EQ(ref.solutions[0].state[1], test::ContactState::slide_plus);
}

// A random cluster of n disks (radii 0.4–0.6) around `centre`: a random tree of touching
// disks, where some disks close a loop by touching two others at once. A bond's gap is 0,
// a slight overlap, or a gap below the alert distance that a step may or may not close.
// Velocities converge on the centre of the cluster, with noise and random spins; with
// `fix_one`, the first disk is fixed (at rest).
struct RandomCluster {
  GrainState state;
  int loops = 0;
};

RandomCluster random_cluster(Rng& rng, int n, bool fix_one, const Vec2& centre) {
  std::vector<Vec2> pos{centre};
  std::vector<double> radii{rng.uniform(0.4, 0.6)};
  int loops = 0;
  auto bond_gap = [&] {
    const double u = rng.uniform();
    return u < 0.4 ? 0.0 : u < 0.6 ? -rng.uniform(0, 1e-4) : rng.uniform(0, 2e-3);
  };
  while (int(pos.size()) < n) {
    const double r = rng.uniform(0.4, 0.6);
    const int a = int(rng.uniform() * double(pos.size()));
    Vec2 p;
    int b = -1;
    if (pos.size() >= 2 && rng.uniform() < 0.35) {  // close a loop: touch a and b
      b = int(rng.uniform() * double(pos.size()));
      if (b == a) continue;
      const double la = radii[a] + r + bond_gap(), lb = radii[b] + r + bond_gap();
      const Vec2 d = pos[b] - pos[a];
      const double base = d.norm();
      if (base >= la + lb || base <= std::fabs(la - lb)) continue;
      const double x = (la * la - lb * lb + base * base) / (2 * base);
      const double side = rng.uniform() < 0.5 ? 1.0 : -1.0;
      p = pos[a] + x * d / base + side * std::sqrt(la * la - x * x) * perp(Vec2(d / base));
    } else {
      const double angle = rng.uniform(0, 2 * M_PI);
      p = pos[a] + (radii[a] + r + bond_gap()) * Vec2(std::cos(angle), std::sin(angle));
    }
    bool clear = true;  // no overlap with the others than the chosen partners
    for (std::size_t q = 0; q < pos.size() && clear; ++q)
      if (int(q) != a && int(q) != b) clear = (p - pos[q]).norm() - radii[q] - r >= 0;
    if (!clear) continue;
    loops += b >= 0;
    pos.push_back(p);
    radii.push_back(r);
  }
  RandomCluster c;
  c.loops = loops;
  c.state = make_grains(pos, radii);
  Vec2 middle = Vec2::Zero();
  for (const Vec2& q : pos) middle += q / double(n);
  for (int g = 0; g < n; ++g) {
    if (fix_one && g == 0) {
      c.state.fixed[g] = 1;
      continue;
    }
    c.state.velocity[g] = 2.0 * (middle - pos[g]) + Vec2(rng.normal(), rng.normal());
    c.state.angular_velocity[g] = rng.normal() / radii[g];
  }
  return c;
}

struct Tally {
  int clusters = 0, redundant = 0, non_unique = 0, continuum = 0, loops = 0, fixed = 0, redrawn = 0;
  std::map<int, int> by_contacts;                           // clusters by candidate pairs
  int off = 0, stick = 0, slide_plus = 0, slide_minus = 0;  // contacts of the engine's solutions
  std::int64_t systems = 0;
  std::map<int, std::int64_t> sweeps, max_sweeps, region_solves;  // per Solver
  double worst_law = 0, worst_impulse = 0, worst_velocity = 0;
};

// Bound on every law's violation by the engine's impulses, relative to the problem's
// velocity scale (≈ 1–6 here). The engine stops when no local solve would change a
// velocity by Υ = tolerance/dt = 10⁻¹¹ or more; a contact's law is then off by at most
// the corrections its neighbours made after its own last solve, a few Υ, far below this.
constexpr double kLawBound = 1e-9;
// Impulses and velocities against the enumerated solution, relative to the largest
// impulse (velocity): the same few Υ, times the conditioning of the small systems.
constexpr double kMatchBound = 1e-9;

// The solvers compared: Gauss–Seidel alone, with the exact cluster solves (the default), and
// with a region solve after the first sweep (RegionSolver, over the whole of these clusters).
enum Solver { kGaussSeidel, kClusterSolves, kRegionSolves };
const char* solver_name(int s) {
  return s == kGaussSeidel ? "Gauss-Seidel only" : s == kClusterSolves ? "cluster solves" : "region solve";
}

// One step's settings for the comparisons: a tight tolerance, so that they see round-off only.
SolverSettings tight_settings(int solver, double alert) {
  SolverSettings settings;
  settings.tolerance = 1e-14;
  settings.alert_distance = alert;
  settings.max_iterations = 1000000;
  settings.cluster_solves = solver == kClusterSolves;
  settings.region_solve_after = solver == kRegionSolves ? 1 : 0;
  return settings;
}

// The engine's impulses (force·dt) in the problem's row order; fails on a contact the problem
// does not know.
void engine_impulses(const ContactProblem& p, const Engine& engine, double dt, Eigen::VectorXd& P) {
  std::map<std::pair<int, int>, int> row;
  for (int k = 0; k < p.contacts(); ++k) row[p.pairs[k]] = k;
  P = Eigen::VectorXd::Zero(2 * p.contacts());
  const ContactRecords& rec = engine.contacts();
  for (std::size_t r = 0; r < rec.size(); ++r) {
    const auto it = row.find({rec.pair[r][0], rec.pair[r][1]});
    ASSERT_NE(it, row.end()) << "a contact the reference does not know";
    P(2 * it->second) = rec.normal_force[r] * dt;
    P(2 * it->second + 1) = rec.tangential_force[r] * dt;
  }
}

void check_cluster(const RandomCluster& cluster, const Material& mat, Tally& tally) {
  const double dt = 1e-3, alert = 0.1;
  Box box;
  box.lx = box.ly = 40;
  const Reference ref = brute_force(cluster.state, mat, dt, alert);
  const ContactProblem& p = ref.problem;
  const int c = p.contacts();
  ++tally.clusters;
  tally.redundant += ref.redundant;
  tally.non_unique += ref.solutions.size() > 1;
  tally.loops += cluster.loops > 0;
  tally.fixed += cluster.state.fixed[0];
  tally.systems += ref.systems;
  ASSERT_FALSE(ref.solutions.empty()) << "the enumeration found no solution";
  for (const int solver : {kGaussSeidel, kClusterSolves, kRegionSolves}) {
    SCOPED_TRACE(solver_name(solver));
    Engine engine(cluster.state, box, 0.0, mat, tight_settings(solver, alert), dt);
    const StepReport& report = engine.step();
    ASSERT_TRUE(report.converged);
    ASSERT_EQ(engine.alert_distance(), alert);
    ASSERT_EQ(report.candidates, c);
    tally.sweeps[solver] += report.iterations;
    tally.max_sweeps[solver] = std::max<std::int64_t>(tally.max_sweeps[solver], report.iterations);
    tally.region_solves[solver] += report.region_solves;
    if (solver != kRegionSolves) {
      EXPECT_EQ(report.region_solves, 0);
    }

    Eigen::VectorXd P;
    engine_impulses(p, engine, dt, P);
    if (testing::Test::HasFatalFailure()) return;

    // (i) Every law, on the engine's own impulses.
    const LawViolation v = check_laws(p, P);
    tally.worst_law = std::max(tally.worst_law, v.max());
    EXPECT_LE(v.nonnegative, kLawBound);
    EXPECT_LE(v.bound, kLawBound);
    EXPECT_LE(v.complementarity, kLawBound);
    EXPECT_LE(v.cone, kLawBound);
    EXPECT_LE(v.stick, kLawBound);
    EXPECT_LE(v.slide, kLawBound);

    // The grains' velocities are those the impulses give through the independent Jacobian.
    const Eigen::VectorXd q = p.velocity(P);
    const double vscale = q.cwiseAbs().maxCoeff();
    double dv = 0;
    for (std::size_t g = 0; g < cluster.state.size(); ++g) {
      const GrainState& a = engine.state();
      dv = std::max({dv, std::fabs(a.velocity[g].x() - q(3 * g)), std::fabs(a.velocity[g].y() - q(3 * g + 1)),
                     a.radius[g] * std::fabs(a.angular_velocity[g] - q(3 * g + 2))});
    }
    tally.worst_velocity = std::max(tally.worst_velocity, dv / vscale);
    EXPECT_LE(dv, kMatchBound * vscale);

    // (ii) The engine's impulses are one of the enumerated solutions (the only one if unique).
    double nearest = INFINITY;
    for (std::size_t k = 0; k < ref.solutions.size(); ++k) {
      const Eigen::VectorXd& R = ref.solutions[k].impulse;
      const double size = std::max(R.cwiseAbs().maxCoeff(), P.cwiseAbs().maxCoeff());
      const double d = size > 0 ? (R - P).cwiseAbs().maxCoeff() / size : 0.0;  // 0: no contact takes an impulse
      nearest = std::min(nearest, d);
    }
    if (nearest > kMatchBound && ref.redundant) {
      // A continuum of solutions (W singular): the enumeration holds its vertices only, and
      // the engine may stop anywhere on it; its impulses obey the laws, checked above.
      ++tally.continuum;
    } else {
      EXPECT_LE(nearest, kMatchBound) << ref.solutions.size() << " enumerated solution(s)";
      tally.worst_impulse = std::max(tally.worst_impulse, nearest);
    }

    // (iii) Contact states of the engine's solution.
    if (solver == kGaussSeidel) {
      const double scale = P.cwiseAbs().maxCoeff();
      for (int k = 0; k < c; ++k) {
        const double pn = P(2 * k), pt = P(2 * k + 1);
        if (pn <= 1e-9 * scale) ++tally.off;
        else if (pt >= mat.friction * pn * (1 - 1e-7)) ++tally.slide_plus;
        else if (pt <= -mat.friction * pn * (1 - 1e-7)) ++tally.slide_minus;
        else ++tally.stick;
      }
    }
  }
}

// For one μ: e ∈ {0, 0.5}, e_t alternately 0 and 0.3, 24 clusters each of 3–8 disks (uniform),
// a quarter of them with a fixed disk.
void check_friction(double mu, std::uint64_t seed) {
  Tally tally;
  Rng rng(seed);
  for (double e : {0.0, 0.5})
    for (int k = 0; k < 24; ++k) {
      const Material mat{e, k % 2 ? 0.3 : 0.0, mu};
      RandomCluster cluster;
      for (;; ++tally.redrawn) {  // at most kMaxBruteForceContacts candidate pairs
        const int n = 3 + int(6 * rng.uniform());
        const bool fix_one = rng.uniform() < 0.25;
        cluster = random_cluster(rng, n, fix_one, Vec2(20, 20));
        const int c = test::contact_problem(cluster.state, mat, 1e-3, 0.1).contacts();
        if (c <= test::kMaxBruteForceContacts) {
          ++tally.by_contacts[c];
          break;
        }
      }
      SCOPED_TRACE(testing::Message() << "e = " << e << ", cluster " << k);
      check_cluster(cluster, mat, tally);
      if (testing::Test::HasFatalFailure()) return;
    }
  std::cout << "FrictionClusters mu = " << mu << ": " << tally.clusters << " clusters (" << tally.loops
            << " with loops, " << tally.fixed << " with a fixed disk, " << tally.redrawn
            << " redrawn with too many contacts, " << tally.redundant << " redundant, " << tally.non_unique
            << " with several solutions, " << tally.continuum
            << " engine off the enumerated vertices); contacts: " << tally.stick << " stick, " << tally.slide_plus
            << " slide +, " << tally.slide_minus << " slide -, " << tally.off << " off; " << tally.systems
            << " systems enumerated\n  clusters by contacts:";
  for (const auto& [contacts, count] : tally.by_contacts) std::cout << " " << contacts << ": " << count;
  std::cout << "\n"
            << "  worst relative law violation " << tally.worst_law << ", impulse " << tally.worst_impulse
            << ", velocity " << tally.worst_velocity << "; sweeps per step: Gauss-Seidel only "
            << double(tally.sweeps[kGaussSeidel]) / tally.clusters << " (max " << tally.max_sweeps[kGaussSeidel]
            << "), cluster_solves " << double(tally.sweeps[kClusterSolves]) / tally.clusters << " (max "
            << tally.max_sweeps[kClusterSolves] << "), region solve after the first sweep "
            << double(tally.sweeps[kRegionSolves]) / tally.clusters << " (max " << tally.max_sweeps[kRegionSolves]
            << ", " << tally.region_solves[kRegionSolves] << " region solves)\n";
  // The set exercises friction: contacts stick and slide both ways.
  EXPECT_GT(tally.stick, 0);
  EXPECT_GT(tally.slide_plus, 0);
  EXPECT_GT(tally.slide_minus, 0);
  // The exact cluster solves land on the solution: a fraction of Gauss–Seidel's sweeps (a
  // wrong matrix entry or facet would leave Gauss–Seidel to do the work).
  EXPECT_LT(4 * tally.sweeps[kClusterSolves], tally.sweeps[kGaussSeidel]);
  // The region solve lands on the solution after the first sweep: the second finds nothing
  // left to correct (a wrong entry of its problem would leave Gauss–Seidel to do the work).
  EXPECT_GT(tally.region_solves[kRegionSolves], 0);
  EXPECT_LE(tally.max_sweeps[kRegionSolves], 2);
}

TEST(FrictionClusters, Mu0_1) { check_friction(0.1, 11); }
TEST(FrictionClusters, Mu0_4) { check_friction(0.4, 12); }
TEST(FrictionClusters, Mu1) { check_friction(1.0, 13); }

// A disk falling into the pocket between two fixed disks with a little restitution (e = 10⁻³):
// two contacts, four impulse unknowns, three degrees of freedom, so the contacts hold a
// self-stress (a compression along the chord between them) that moves no grain. The slight
// rebound gives the two contacts different normal targets, so no impulses can let both stick:
// one must slide. Gauss–Seidel alone drifts along the self-stress by a step as small as that
// mismatch, for thousands of sweeps; the cluster solve steps along it to the cone's boundary
// at once.
TEST(FrictionClusters, WedgedGrainStepsAlongItsSelfStress) {
  GrainState s =
      make_grains({Vec2(20, 20), Vec2(21.02, 20), Vec2(20.51, 20 + std::sqrt(1 - 0.51 * 0.51))}, {0.5, 0.5, 0.5});
  s.fixed[0] = s.fixed[1] = 1;
  s.velocity[2] = Vec2(0.3, -1);
  s.angular_velocity[2] = 0.2;
  const double dt = 1e-3, alert = 0.1;
  Box box;
  box.lx = box.ly = 40;
  const Material mat{1e-3, 0.0, 0.4};
  const Reference ref = brute_force(s, mat, dt, alert);
  ASSERT_EQ(ref.problem.contacts(), 2);
  EXPECT_EQ(Eigen::FullPivLU<Eigen::MatrixXd>(ref.problem.W).rank(), 3);  // the self-stress
  ASSERT_EQ(ref.solutions.size(), 1u);                                    // one contact slides, the other sticks
  const Eigen::VectorXd& R = ref.solutions[0].impulse;
  std::map<int, int> sweeps, solves;
  for (const int solver : {kGaussSeidel, kClusterSolves, kRegionSolves}) {
    SCOPED_TRACE(solver_name(solver));
    Engine engine(s, box, 0.0, mat, tight_settings(solver, alert), dt);
    const StepReport& report = engine.step();
    ASSERT_TRUE(report.converged);
    sweeps[solver] = report.iterations;
    solves[solver] = report.cluster_solves + report.region_solves;
    Eigen::VectorXd P;
    engine_impulses(ref.problem, engine, dt, P);
    if (testing::Test::HasFatalFailure()) return;
    EXPECT_LE(check_laws(ref.problem, P).max(), kLawBound);
    EXPECT_LE((P - R).cwiseAbs().maxCoeff(), kMatchBound * R.cwiseAbs().maxCoeff());
  }
  std::cout << "FrictionClusters wedged grain: sweeps " << sweeps[kGaussSeidel] << " (Gauss-Seidel only), "
            << sweeps[kClusterSolves] << " (cluster solves, " << solves[kClusterSolves] << " passes) and "
            << sweeps[kRegionSolves] << " (" << solves[kRegionSolves] << " region solve)\n";
  EXPECT_GT(sweeps[kGaussSeidel], 1000);
  EXPECT_LE(sweeps[kClusterSolves], 20);
  EXPECT_EQ(solves[kRegionSolves], 1);
  EXPECT_LE(sweeps[kRegionSolves], 2);
}

// A large cluster (80 disks, loops, one fixed) squeezed together at μ = 0.4, e = 0: too many
// contacts to enumerate, so the laws are checked on the engine's impulses. Gauss–Seidel alone
// needs hundreds of sweeps; the exact frictional cluster solves land on a solution in a few
// tens, with every law met to the same bound; so do the region solves, a part at a time.
TEST(FrictionClusters, LargeClusterSolvedInFewSweeps) {
  Rng rng(17);
  const RandomCluster cluster = random_cluster(rng, 80, true, Vec2(20, 20));
  const double dt = 1e-3, alert = 0.1;
  Box box;
  box.lx = box.ly = 40;
  for (const double mu : {0.4, 1.0}) {
    SCOPED_TRACE(mu);
    const Material mat{0.0, 0.0, mu};
    const ContactProblem p = test::contact_problem(cluster.state, mat, dt, alert);
    std::map<int, int> sweeps, largest, regions;
    for (const int solver : {kGaussSeidel, kClusterSolves, kRegionSolves}) {
      Engine engine(cluster.state, box, 0.0, mat, tight_settings(solver, alert), dt);
      const StepReport& report = engine.step();
      ASSERT_TRUE(report.converged);
      sweeps[solver] = report.iterations;
      largest[solver] = report.largest_cluster;
      regions[solver] = report.region_solves;
      Eigen::VectorXd P;
      engine_impulses(p, engine, dt, P);
      if (testing::Test::HasFatalFailure()) return;
      EXPECT_LE(check_laws(p, P).max(), kLawBound) << solver_name(solver);
    }
    std::cout << "FrictionClusters large, mu = " << mu << ": " << p.contacts() << " candidates, sweeps "
              << sweeps[kGaussSeidel] << " (Gauss-Seidel only), " << sweeps[kClusterSolves]
              << " (cluster solves, largest " << largest[kClusterSolves] << " rows) and " << sweeps[kRegionSolves]
              << " (" << regions[kRegionSolves] << " region solves)\n";
    EXPECT_GE(largest[kClusterSolves], 40);
    EXPECT_GT(sweeps[kGaussSeidel], 200);
    EXPECT_LE(sweeps[kClusterSolves], 40);
    // The region solves take at most 100 rows at the first attempt and 200 at the second
    // (500 sweeps later), around the rows still corrected most: on this cluster of 101
    // candidates they solve a part of it at a time, and Gauss–Seidel the rest.
    EXPECT_GE(regions[kRegionSolves], 1);
    EXPECT_LT(sweeps[kRegionSolves], sweeps[kGaussSeidel]);
  }
}

}  // namespace
}  // namespace granflow
