// The engine's fast paths against plain references: one step of a dense sheared packing
// against a plain projected Gauss–Seidel written here from the documented contact law (all
// pairs below the alert distance, found by brute force, every row in every sweep, no warm
// start); cluster solves on and off; partial residual checks against full ones. The sparse
// LDLᵀ of the cluster solves is tested in tests/unit/test_sparse_ldl.cpp, the pair list in
// test_cell_list.cpp, thread counts in test_threads.cpp.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/random.hpp"
#include "dynamics/engine.hpp"
#include "helpers.hpp"
#include "packing/packing.hpp"

namespace granflow {
namespace {

using test::expect_same_state;

// One step of the documented contact law, solved by plain projected Gauss–Seidel over all
// pairs with a gap below `alert`, from zero impulses, to a round-off tolerance. Returns the
// post-step velocities (v_x, v_y, ω) of every grain.
Eigen::VectorXd reference_step(const GrainState& s, const Box& box, double rate, const Material& mat, double dt,
                               double alert) {
  struct Pair {
    int i, j;
    Vec2 n;
    double bn, bt, shift;
  };
  const int n = int(s.size());
  std::vector<Pair> pairs;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      const Vec2 d = box.minimum_image(s.position[i] - s.position[j]);
      const double gap = d.norm() - s.radius[i] - s.radius[j];
      if (gap >= alert) continue;
      const double k = std::round((s.position[i].y() - s.position[j].y()) / box.ly);
      Pair p{i, j, d.normalized(), 0, 0, k * rate * box.ly};
      const Vec2 t = perp(p.n);
      const Vec2 dv = s.velocity[i] - s.velocity[j] - Vec2(p.shift, 0);
      const double un = dv.dot(p.n);
      const double ut = dv.dot(t) - (s.radius[i] * s.angular_velocity[i] + s.radius[j] * s.angular_velocity[j]);
      p.bn = (gap <= 0 || gap + dt * un <= 0) ? (un < 0 ? -mat.restitution * un : 0.0) : -gap / dt;
      p.bt = mat.tangential_restitution * ut;
      pairs.push_back(p);
    }
  Eigen::VectorXd q(3 * n);
  for (int g = 0; g < n; ++g) q.segment<3>(3 * g) << s.velocity[g].x(), s.velocity[g].y(), s.angular_velocity[g];
  std::vector<double> pn(pairs.size(), 0.0), pt(pairs.size(), 0.0);
  for (int sweep = 0; sweep < 200000; ++sweep) {
    double worst = 0;
    for (std::size_t c = 0; c < pairs.size(); ++c) {
      const Pair& p = pairs[c];
      const Vec2 t = perp(p.n);
      const double mi = s.mass[p.i], mj = s.mass[p.j], ri = s.radius[p.i], rj = s.radius[p.j];
      const Vec2 dv = Vec2(q(3 * p.i), q(3 * p.i + 1)) - Vec2(q(3 * p.j), q(3 * p.j + 1)) - Vec2(p.shift, 0);
      const double un = dv.dot(p.n);
      const double ut = dv.dot(t) - (ri * q(3 * p.i + 2) + rj * q(3 * p.j + 2));
      const double wn = 1 / mi + 1 / mj, wt = 3 * wn;
      const double new_pn = std::max(0.0, pn[c] + (p.bn - un) / wn);
      const double limit = mat.friction * new_pn;
      const double new_pt = std::clamp(pt[c] + (p.bt - ut) / wt, -limit, limit);
      const double dpn = new_pn - pn[c], dpt = new_pt - pt[c];
      worst = std::max({worst, std::fabs(dpn) * wn, std::fabs(dpt) * wt});
      pn[c] = new_pn;
      pt[c] = new_pt;
      const Vec2 impulse = dpn * p.n + dpt * t;  // on i, at its contact point −R_i n̂
      q.segment<2>(3 * p.i) += impulse / mi;
      q.segment<2>(3 * p.j) -= impulse / mj;
      q(3 * p.i + 2) -= ri * dpt / (0.5 * mi * ri * ri);
      q(3 * p.j + 2) -= rj * dpt / (0.5 * mj * rj * rj);
    }
    if (worst < 1e-14) return q;
  }
  ADD_FAILURE() << "reference Gauss–Seidel did not converge";
  return q;
}

Engine warm_shear(const Material& mat, double nu, SolverSettings settings, int grains = 250) {
  test::Packing p = test::random_packing(grains, nu, 71);
  const double rate = 1.0;
  add_affine_flow(p.state, p.box, rate);
  test::add_fluctuations(p.state, 0.2 * rate, 72);
  Engine engine(p.state, p.box, rate, mat, settings, 1e-3 / rate);
  for (int k = 0; k < 150; ++k) engine.step();
  return engine;
}

double largest_velocity_difference(const GrainState& s, const Eigen::VectorXd& q) {
  double worst = 0;
  for (std::size_t g = 0; g < s.size(); ++g)
    worst = std::max({worst, (s.velocity[g] - Vec2(q(3 * g), q(3 * g + 1))).norm(),
                      s.radius[g] * std::fabs(s.angular_velocity[g] - q(3 * g + 2))});
  return worst;
}

double mean_diameter(const GrainState& s) {
  double sum = 0;
  for (double r : s.radius) sum += 2 * r;
  return sum / double(s.size());
}

// Frictionless, the post-step velocities are unique (they minimise a strictly convex
// energy), so a step of the engine, with its working set, warm start, spatial order,
// skipped tiles and cluster solves, must land on the reference's. Both are converged far
// below the default tolerance so that only the solution, not the stopping point, is
// compared. 1500 grains make a box of three tiles across and fourteen strips.
TEST(Solver, FrictionlessStepMatchesPlainGaussSeidel) {
  for (auto [clusters, grains] : {std::pair(true, 250), std::pair(false, 250), std::pair(true, 1500)}) {
    SCOPED_TRACE(clusters);
    SCOPED_TRACE(grains);
    SolverSettings settings;
    settings.tolerance = 1e-14;
    settings.cluster_solves = clusters;
    const Material mat{0.5, 0.0, 0.0};
    Engine engine = warm_shear(mat, 0.8, settings, grains);
    const GrainState before = engine.state();
    const Box box = engine.box();
    const Eigen::VectorXd q = reference_step(before, box, engine.rate(), mat, engine.dt(), engine.alert_distance());
    const StepReport& r = engine.step();
    ASSERT_TRUE(r.converged);
    EXPECT_GT(r.contacts, 100);
    if (clusters) {
      EXPECT_GT(r.cluster_solves, 0);
    }
    std::cout << "Solver: " << r.contacts << " contacts, " << r.iterations << " sweeps, " << r.cluster_solves
              << " cluster solves\n";
    EXPECT_LT(largest_velocity_difference(engine.state(), q), 1e-9);
  }
}

// Pairs farther apart than the alert distance (2·dt·v_rel, twice the largest relative
// displacement a step allows, above a floor of 0.01σ by default) can neither touch nor
// bind within the step. Checked against the reference solve over every pair closer than
// 0.3σ, thirty times the default floor, in a dense and a looser flow.
TEST(Solver, PairsBeyondTheAlertDistanceNeverBind) {
  for (auto [nu, least_contacts] : {std::pair(0.8, 100), std::pair(0.7, 0)}) {
    SCOPED_TRACE(nu);
    SolverSettings settings;
    settings.tolerance = 1e-14;
    const Material mat{0.5, 0.0, 0.0};
    Engine engine = warm_shear(mat, nu, settings, 250);
    const GrainState before = engine.state();
    const double sigma = mean_diameter(before);
    ASSERT_LT(engine.alert_distance(), 0.1 * sigma);  // the cut is below the old floor
    const Eigen::VectorXd q = reference_step(before, engine.box(), engine.rate(), mat, engine.dt(), 0.3 * sigma);
    const StepReport& r = engine.step();
    ASSERT_TRUE(r.converged);
    EXPECT_GT(r.contacts, least_contacts);
    EXPECT_LT(largest_velocity_difference(engine.state(), q), 1e-9);
  }
}

// Contact impulses are equal and opposite, so every step keeps the total momentum, also one
// that stalls near frictional jamming and ends at the sweep cap: there exact cluster passes
// are tried and undone, and an undo must restore the velocities it changed (a near-singular
// pass can be 10¹³ times the step's impulses, whose round-off, left behind, kicked the grains).
// Lees–Edwards crossings change v_x only, so Σ m v_y is conserved to round-off.
TEST(Solver, StalledFrictionalStepsConserveMomentum) {
  test::Packing p = test::random_packing(100, 0.82, 5);
  const double rate = 1.0;
  add_affine_flow(p.state, p.box, rate);
  SolverSettings settings;
  settings.max_iterations = 1000;
  Engine engine(p.state, p.box, rate, Material{0.0, 0.0, 0.4}, settings, 1e-3 / rate);
  int unconverged = 0;
  double worst = 0;
  for (int k = 0; k < 60; ++k) {
    auto momentum = [&](double& scale) {
      const GrainState& s = engine.state();
      double sum = 0;
      scale = 0;
      for (std::size_t g = 0; g < s.size(); ++g) {
        sum += s.mass[g] * s.velocity[g].y();
        scale += s.mass[g] * std::fabs(s.velocity[g].y());
      }
      return sum;
    };
    double scale = 0;
    const double before = momentum(scale);
    unconverged += !engine.step().converged;
    const double after = momentum(scale);
    worst = std::max(worst, std::fabs(after - before) / scale);
  }
  std::cout << "StalledFrictionalSteps: " << unconverged << " of 60 steps at the cap, largest momentum change " << worst
            << " of Σ m|v_y|\n";
  EXPECT_GE(unconverged, 10) << "the run does not stall: it tests nothing";
  EXPECT_LT(worst, 1e-12);
}

// The recorded contacts are every impulse of the step: each grain's change of momentum (and,
// with friction, of angular momentum) is the sum of its recorded forces × dt, to round-off.
// A contact left out of the records, or a record with no impulse behind it, breaks this for
// its grains. Grains that crossed the Lees–Edwards boundary also changed v_x by ±γ̇·L_y.
TEST(Solver, RecordsHoldEveryImpulse) {
  for (double mu : {0.0, 0.4}) {
    SCOPED_TRACE(mu);
    const Material mat{0.5, 0.0, mu};
    // μ = 0 reads the bearing rows from the sweep flags, μ > 0 from the impulses.
    Engine engine = warm_shear(mat, 0.8, SolverSettings{}, mu == 0 ? 1500 : 300);
    const GrainState before = engine.state();
    const double dt = engine.dt(), jump = engine.rate() * engine.box().ly;
    const StepReport& r = engine.step();
    ASSERT_TRUE(r.converged);
    const ContactRecords& c = engine.contacts();
    ASSERT_GT(c.size(), 100u);
    const std::size_t n = before.size();
    std::vector<Vec2> impulse(n, Vec2::Zero());
    std::vector<double> torque(n, 0.0);
    double largest = 0;
    for (std::size_t k = 0; k < c.size(); ++k) {
      const auto [i, j] = c.pair[k];
      EXPECT_GT(c.normal_force[k], 0.0);
      const Vec2 normal = c.branch[k].normalized();
      const Vec2 p = dt * (c.normal_force[k] * normal + c.tangential_force[k] * perp(normal));
      impulse[i] += p;
      impulse[j] -= p;
      torque[i] -= before.radius[i] * dt * c.tangential_force[k];
      torque[j] -= before.radius[j] * dt * c.tangential_force[k];
      largest = std::max(largest, p.norm());
    }
    const GrainState& after = engine.state();
    for (std::size_t g = 0; g < n; ++g) {
      Vec2 change = before.mass[g] * (after.velocity[g] - before.velocity[g]);
      // A boundary crossing shifts v_x by exactly ±γ̇·L_y: take it out where it happened.
      const double crossed = std::round((change.x() - impulse[g].x()) / (before.mass[g] * jump));
      change.x() -= crossed * before.mass[g] * jump;
      ASSERT_LT((change - impulse[g]).norm(), 1e-9 * largest) << "grain " << g;
      const double inertia = 0.5 * before.mass[g] * before.radius[g] * before.radius[g];
      ASSERT_NEAR(inertia * (after.angular_velocity[g] - before.angular_velocity[g]), torque[g],
                  1e-9 * largest * before.radius[g])
          << "grain " << g;
    }
  }
}

// With friction the impulses, even the velocities, need not be unique; at moderate density
// the step is, and engine and reference agree. At ν = 0.8 the step's cluster solves order
// clusters of 100 loop rows or more by minimum degree at once (kOrderedLoops in
// cluster_solver.cpp: 600 grains, a cluster of 464 rows, about 300 of them in loops).
TEST(Solver, FrictionalStepMatchesPlainGaussSeidel) {
  for (auto [nu, grains] : {std::pair(0.76, 250), std::pair(0.8, 250), std::pair(0.8, 600)}) {
    SCOPED_TRACE(grains);
    SCOPED_TRACE(nu);
    SolverSettings settings;
    settings.tolerance = 1e-14;
    const Material mat{0.6, 0.2, 0.3};
    Engine engine = warm_shear(mat, nu, settings, grains);
    const GrainState before = engine.state();
    const Eigen::VectorXd q =
        reference_step(before, engine.box(), engine.rate(), mat, engine.dt(), engine.alert_distance());
    const StepReport& r = engine.step();
    ASSERT_TRUE(r.converged);
    EXPECT_GT(r.contacts, grains / 12);
    std::cout << "Solver: " << r.contacts << " contacts, " << r.iterations << " sweeps, " << r.cluster_solves
              << " cluster solves, largest cluster " << r.largest_cluster << " rows\n";
    EXPECT_LT(largest_velocity_difference(engine.state(), q), 1e-9);
    // A cluster whose solve fails is left to Gauss–Seidel, which gets the same answer in far
    // more sweeps: 10, 27 and 25 here; 2 844 and 2 455 at ν = 0.8 with every solve in
    // minimum-degree order refused.
    EXPECT_LT(r.iterations, 60);
  }
}

// Cluster solves replace the slow tail of Gauss–Seidel; from the same state, at the default
// tolerance, the two runs stay together to within what the tolerance allows.
TEST(Solver, ClusterSolvesCutSweepsNotAccuracy) {
  const Material mat{0.5, 0.0, 0.0};
  const Engine start = warm_shear(mat, 0.8, {});
  SolverSettings plain;
  plain.cluster_solves = false;
  Engine a(start.state(), start.box(), start.rate(), mat, {}, start.dt());
  Engine b(start.state(), start.box(), start.rate(), mat, plain, start.dt());
  a.restore(start.step_count(), start.memory());
  b.restore(start.step_count(), start.memory());
  const double upsilon = a.settings().tolerance / a.dt();
  long sweeps_a = 0, sweeps_b = 0;
  for (int k = 0; k < 20; ++k) {
    sweeps_a += a.step().iterations;
    sweeps_b += b.step().iterations;
    ASSERT_TRUE(a.last_report().converged && b.last_report().converged);
    if (k == 0) {
      double worst = 0;
      for (std::size_t g = 0; g < a.state().size(); ++g)
        worst = std::max(worst, (a.state().velocity[g] - b.state().velocity[g]).norm());
      EXPECT_LT(worst, 10 * upsilon);
    }
  }
  std::cout << "Solver: 20 steps, " << sweeps_a << " sweeps with cluster solves, " << sweeps_b << " without\n";
  EXPECT_LT(3 * sweeps_a, sweeps_b);
  double worst = 0;
  for (std::size_t g = 0; g < a.state().size(); ++g)
    worst = std::max(worst, a.box().minimum_image(a.state().position[g] - b.state().position[g]).norm());
  EXPECT_LT(worst, 20 * a.dt() * 100 * upsilon);  // a growing gap of up to 100 Υ in velocity
}

// A frictionless run started from a frictional state (gf-shear --frame K --friction 0)
// must drop the stored tangential forces: the frictionless sweep never touches them, so a
// kept one would be applied every step and never converge.
TEST(Solver, FrictionlessRestartFromFrictionalStateDropsTangentialForces) {
  const Engine frictional = warm_shear(Material{0.5, 0.0, 0.4}, 0.8, {});
  const ContactMemory memory = frictional.memory();
  ASSERT_GT(
      std::count_if(memory.tangential_force.begin(), memory.tangential_force.end(), [](double f) { return f != 0; }),
      10);
  Engine frictionless(frictional.state(), frictional.box(), frictional.rate(), Material{0.5, 0.0, 0.0}, {},
                      frictional.dt());
  frictionless.restore(frictional.step_count(), memory);
  for (int k = 0; k < 5; ++k) {
    const StepReport& r = frictionless.step();
    ASSERT_TRUE(r.converged) << "step " << k << ": " << r.iterations << " sweeps";
    EXPECT_LT(r.iterations, 1000);
    for (double f : frictionless.contacts().tangential_force) ASSERT_EQ(f, 0.0);
  }
}

// Without shear the alert floor only decides which far pairs are listed, and those never
// bind: a floor of 0.01σ (the default) and of 0.1σ give the same trajectory to the last
// bit, on fewer candidates. The sweep strips must therefore not be sized by the alert
// distance: thinner strips would sweep in another order.
TEST(Solver, AlertFloorDoesNotChangeTrajectoryWithoutShear) {
  test::Packing p = test::random_packing(300, 0.8, 93);
  test::add_fluctuations(p.state, 1.0, 94);
  SolverSettings wide;
  wide.alert_distance = 0.1 * mean_diameter(p.state);
  const Material mat{0.5, 0.0, 0.0};
  Engine a(p.state, p.box, 0.0, mat, SolverSettings{}, 1e-3), b(p.state, p.box, 0.0, mat, wide, 1e-3);
  long candidates_a = 0, candidates_b = 0, contacts = 0;
  for (int k = 0; k < 200; ++k) {
    candidates_a += a.step().candidates;
    candidates_b += b.step().candidates;
    contacts += a.last_report().contacts;
  }
  EXPECT_GT(contacts, 200);
  EXPECT_LT(candidates_a, 0.9 * candidates_b);
  expect_same_state(a.state(), b.state());
}

// The residual check that ends a step looks again only where a sweep or a cluster solve
// changed something since the last one; elsewhere the residuals cannot have changed, so
// the trajectory is the same to the last bit as with every row checked every time, and so
// is the reported residual (8000 grains: the largest over the rows looked at only can be
// 10⁵ times too small in the first steps).
TEST(Solver, PartialChecksAreExact) {
  test::Packing p = test::random_packing(8000, 0.8, 61);
  add_affine_flow(p.state, p.box, 1.0);
  const Material mat{0.5, 0.0, 0.0};
  SolverSettings full;
  full.full_checks = true;
  Engine a(p.state, p.box, 1.0, mat, {}, 1e-3), b(p.state, p.box, 1.0, mat, full, 1e-3);
  std::int64_t updates_a = 0, updates_b = 0;
  for (int k = 0; k < 20; ++k) {
    updates_a += a.step().contact_updates;
    updates_b += b.step().contact_updates;
    ASSERT_TRUE(a.last_report().converged);
    ASSERT_EQ(a.last_report().residual, b.last_report().residual);  // the true largest, not that of the rows looked at
  }
  std::cout << "Solver: " << updates_a << " contact updates with partial checks, " << updates_b << " with full ones\n";
  EXPECT_LT(updates_a, updates_b);  // some checks were partial
  EXPECT_EQ(a.contacts().normal_force, b.contacts().normal_force);
  expect_same_state(a.state(), b.state());
}

// The same when steps run out of sweeps (counted as unconverged): the final check, after
// the last sweep or cluster solve, reports the same residual and the same verdict.
TEST(Solver, PartialChecksAreExactWhenStepsRunOut) {
  test::Packing p = test::random_packing(2000, 0.8, 62);
  add_affine_flow(p.state, p.box, 1.0);
  const Material mat{0.5, 0.0, 0.0};
  int unconverged = 0;
  for (int sweeps = 4; sweeps <= 12; ++sweeps) {
    SCOPED_TRACE(sweeps);
    SolverSettings partial, full;
    partial.max_iterations = full.max_iterations = sweeps;
    full.full_checks = true;
    Engine a(p.state, p.box, 1.0, mat, partial, 1e-3), b(p.state, p.box, 1.0, mat, full, 1e-3);
    for (int k = 0; k < 3; ++k) {
      a.step();
      b.step();
      unconverged += !a.last_report().converged;
      ASSERT_EQ(a.last_report().converged, b.last_report().converged);
      ASSERT_EQ(a.last_report().residual, b.last_report().residual);
    }
    expect_same_state(a.state(), b.state());
  }
  EXPECT_GT(unconverged, 0);  // the case this test is about happened
}

// With friction the sweeps skip rows that their last visit left settled while no row sharing
// a grain has corrected them by Υ or more since. The step still ends only when every
// residual is below Υ, so from the same state the same solution comes out, to the
// tolerance; and the skipping must pay: fewer local solves, no more sweeps.
TEST(Solver, SettledRowsSkippedWithFriction) {
  test::Packing p = test::random_packing(2000, 0.78, 63);
  const double rate = 1.0, dt = 1e-3;
  add_affine_flow(p.state, p.box, rate);
  const Material mat{0.0, 0.0, 0.4};
  SolverSettings every_row;
  every_row.skip_settled_rows = false;
  Engine a(p.state, p.box, rate, mat, {}, dt);
  // Warm up to a sheared state (the first steps from the affine start are not typical),
  // then continue both from a's state for one step.
  for (int k = 0; k < 30; ++k) a.step();
  Engine skip(a.state(), a.box(), rate, mat, {}, dt), every(a.state(), a.box(), rate, mat, every_row, dt);
  skip.restore(a.step_count(), a.memory());
  every.restore(a.step_count(), a.memory());
  const StepReport rs = skip.step(), re = every.step();
  ASSERT_TRUE(rs.converged);
  ASSERT_TRUE(re.converged);
  const double upsilon = SolverSettings{}.tolerance / dt;
  double dv = 0;
  for (std::size_t i = 0; i < skip.state().size(); ++i)
    dv = std::max(dv, (skip.state().velocity[i] - every.state().velocity[i]).norm());
  std::cout << "Solver: one step, " << rs.iterations << " and " << re.iterations << " sweeps, " << rs.contact_updates
            << " and " << re.contact_updates << " local solves, largest velocity difference " << dv / upsilon << " Υ\n";
  EXPECT_LT(dv, 100 * upsilon);
  // Over 20 steps each.
  std::int64_t updates_skip = 0, updates_every = 0, sweeps_skip = 0, sweeps_every = 0;
  for (int k = 0; k < 20; ++k) {
    const StepReport& r1 = skip.step();
    ASSERT_TRUE(r1.converged);
    updates_skip += r1.contact_updates;
    sweeps_skip += r1.iterations;
    const StepReport& r2 = every.step();
    ASSERT_TRUE(r2.converged);
    updates_every += r2.contact_updates;
    sweeps_every += r2.iterations;
  }
  std::cout << "Solver: 20 steps, " << sweeps_skip << " and " << sweeps_every << " sweeps, " << updates_skip << " and "
            << updates_every << " local solves (settled rows skipped, every row)\n";
  EXPECT_LT(updates_skip, updates_every);
  EXPECT_LE(sweeps_skip, sweeps_every + sweeps_every / 4);
}

// A packing at ν = 0.83, just below jamming, sheared from rest: its first active sets are
// hyperstatic and their exact cluster solves near-singular. Kept, such a solve can return
// self-stresses of 10^20 and more that send grains off at 10^30 in the first step ("grains
// move too fast for the box"); a solve that makes the residual much worse is undone.
TEST(Solver, NearlyJammedStartStaysBounded) {
  PackingParams params;
  params.grains = 1000;
  params.packing_fraction = 0.83;
  params.seed = 1;
  const Packing made = make_biperiodic_packing(params);
  GrainState s = make_grains(made.position, made.radius);
  const double rate = 1e-2;
  add_affine_flow(s, made.box, rate);
  Engine engine(s, made.box, rate, {0.5, 0.0, 0.0}, {}, 1e-3 / rate);
  const double affine = 0.5 * rate * made.box.ly;  // largest mean-flow speed
  int solves = 0, unconverged = 0;
  for (int k = 0; k < 30; ++k) {
    const StepReport& r = engine.step();
    // The very first step, every contact closed and the affine flow imposed, exhausts the
    // 10⁴ sweeps (residual ~1e-4, counted and reported by gf-shear); the rest converge.
    unconverged += !r.converged;
    solves += r.cluster_solves;
    double vmax = 0;
    for (const Vec2& v : engine.state().velocity) vmax = std::max(vmax, v.norm());
    ASSERT_LT(vmax, 10 * affine) << "step " << k;  // a blow-up is orders of magnitude
  }
  EXPECT_LE(unconverged, 1);
  EXPECT_GT(solves, 30) << "the cluster solves this test is about did not run";
}

// A flow too fast for the contact search ends the run with a message that names the speed and
// the time step that made the search too long, the two things a user can act on.
TEST(Solver, TooFastForTheBoxNamesTheSpeedAndTheStep) {
  GrainState s = make_grains({Vec2(6, 6), Vec2(18, 18)}, {0.7, 0.7});
  s.velocity[0] = Vec2(1000, 0);
  try {
    Engine engine(s, test::periodic_square(24), 0.0, {0.5, 0.0, 0.0}, {}, 0.01);
    engine.step();
    FAIL() << "a grain crossing 10 length units per step in a box of 24 was not refused";
  } catch (const RuntimeFailure& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("grains move too fast for the box"), std::string::npos) << message;
    EXPECT_NE(message.find("largest velocity fluctuation 1000 about the mean flow, 10 per time step of 0.01"),
              std::string::npos)
        << message;
  }
}

// Engine memory stays within a kilobyte per grain in a dense flow (one of the performance
// targets; see bench/bench_engine.cpp).
TEST(Solver, MemoryPerGrain) {
  Engine engine = warm_shear({0.5, 0.0, 0.0}, 0.8, {});
  std::cout << "Solver: " << double(engine.allocated_bytes()) / double(engine.state().size()) << " B per grain\n";
  EXPECT_LT(engine.allocated_bytes(), 1024 * engine.state().size());
}

}  // namespace
}  // namespace granflow
