// Incline flow (thesis §4.3): momentum balance of the depth profiles, eq. 4.7–4.9. Averaged
// over a layer, the flux of momentum through horizontal lines balances the weight above
// them, so in steady flow Σyy = g cos θ·W and s = g sin θ·W layer by layer, and a pile on a
// level base comes to rest carrying exactly its weight, with no grain through the base.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <vector>

#include "dynamics/engine.hpp"
#include "incline/observer.hpp"
#include "incline/profiles.hpp"
#include "incline/start.hpp"
#include "packing/packing.hpp"

namespace granflow {
namespace {

struct InclineRun {
  ProfileAccumulator profiles;
  double mean_radius, mean_mass;
};

// A dilute start (gf-pack --incline) released under gravity for `steps` steps of
// time_step·τ, with profiles sampled at every step in blocks of block_steps.
InclineRun run_incline(double width, double height, Vec2 gravity, double time_step, std::int64_t steps,
                       std::int64_t block_steps, double tolerance) {
  InclineParams p;
  p.width = width;
  p.height = height;
  p.seed = 5;
  const Packing packing = make_incline_packing(p);
  GrainState grains = make_grains(packing.position, packing.radius);
  grains.fixed = packing.fixed;
  double radius = 0, mass = 0;
  int mobile = 0;
  for (std::size_t i = 0; i < grains.size(); ++i)
    if (!grains.fixed[i]) {
      radius += grains.radius[i];
      mass += grains.mass[i];
      ++mobile;
    }
  radius /= mobile;
  mass /= mobile;
  const double tau = std::sqrt(radius / gravity.norm());
  Material material;
  material.restitution = 0.5;
  SolverSettings settings;
  settings.tolerance = tolerance;
  Engine engine(grains, packing.box, 0.0, material, settings, time_step * tau, gravity);
  InclineRun run{ProfileAccumulator(profile_grid(packing.box, 3 * 2 * radius), block_steps), radius, mass};
  while (engine.step_count() < steps) {
    engine.step();
    sample_incline(engine, run.profiles);  // throws if a grain leaves the layer
  }
  return run;
}

TEST(InclineMomentumBalance, SteadyFlowCarriesTheWeightAboveEachLayer) {
  // Frictionless, e = 0.5, at 14°: steady within ~100 τ for a layer 10 diameters thick.
  // (At 20° such a layer keeps accelerating for hundreds of τ.)
  const double theta = 14, g = 1;
  const Vec2 gravity = incline_gravity(g, theta);
  // The balance is an identity of the impulses, converged or not: a loose tolerance
  // only saves solver sweeps.
  const InclineRun run = run_incline(20, 10, gravity, 1e-2, 30000, 1000, 1e-6);
  const InclineUnits units{0, 1, g, run.mean_radius, run.mean_mass};
  const ProfileAnalysis a = analyse_profiles(run.profiles, units, 100.0 * std::sqrt(run.mean_radius / g));
  const Profiles& p = a.profiles;
  ASSERT_EQ(a.steady.first, 10u);
  ASSERT_GE(p.y.size(), 4u);
  const double c = std::cos(theta * M_PI / 180), s = std::sin(theta * M_PI / 180);
  // The balance holds for the time average up to the change of the momentum above each line
  // over the window, which fluctuates from run to run with the round-off history (over
  // 50 τ a shear ratio can be off by 3 %, about one standard error):
  // averaged over 200 τ, each ratio is held to 2 % or 3 standard errors of the mean of its
  // 10 τ blocks, whichever is larger (3–4.5 % for the shear ratios).
  const auto& blocks = run.profiles.blocks();
  std::vector<Profiles> per_block;
  for (std::size_t b = a.steady.first; b < blocks.size(); ++b)
    per_block.push_back(average_profiles(run.profiles.grid(), {blocks[b]}, 0, g, run.mean_radius, run.mean_mass));
  auto standard_error = [&](auto ratio) {
    double sum = 0, squares = 0;
    for (const Profiles& one : per_block) {
      sum += ratio(one);
      squares += ratio(one) * ratio(one);
    }
    const double n = double(per_block.size()), mean = sum / n;
    return std::sqrt((squares / n - mean * mean) / (n - 1));
  };
  auto bound = [&](auto ratio) { return std::max(0.02, 3 * standard_error(ratio)); };
  // Bulk: without the layer at the base and the top one, at the free surface.
  for (std::size_t k = 1; k + 1 < p.y.size(); ++k) {
    SCOPED_TRACE("layer " + std::to_string(k));
    auto normal = [&](const Profiles& q) { return q.stress_yy[k] / (c * q.weight_above[k]); };
    auto shear = [&](const Profiles& q) { return q.shear_stress[k] / (s * q.weight_above[k]); };
    std::cout << "Incline: layer " << k << " Σyy/(g cos θ W) = " << normal(p) << " ± " << standard_error(normal)
              << ", s/(g sin θ W) = " << shear(p) << " ± " << standard_error(shear) << "\n";
    EXPECT_NEAR(normal(p), 1, bound(normal));
    EXPECT_NEAR(shear(p), 1, bound(shear));
    EXPECT_GT(p.velocity_x[k], p.velocity_x[k - 1]);  // flowing, faster towards the surface
  }
}

TEST(InclineMomentumBalance, LevelPileComesToRestOnItsWeight) {
  const double g = 1;
  // At rest the forces must hold the weight to the solver's precision: a tight tolerance.
  // 80 τ: a frictionless pile takes tens of τ to stop creeping (how long depends on the
  // round-off history, hence on solver details).
  const InclineRun run = run_incline(10, 5, incline_gravity(g, 0), 1e-2, 8000, 500, 1e-10);
  const auto& blocks = run.profiles.blocks();
  const double energy_start = blocks[1].observables.kinetic_energy / double(blocks[1].samples);
  const double energy_end = blocks.back().observables.kinetic_energy / double(blocks.back().samples);
  EXPECT_LT(energy_end, 1e-6 * energy_start);
  const Profiles p =
      average_profiles(run.profiles.grid(), blocks, blocks.size() - 2, g, run.mean_radius, run.mean_mass);
  for (std::size_t k = 0; k < p.y.size(); ++k) {
    SCOPED_TRACE("layer " + std::to_string(k));
    EXPECT_NEAR(p.stress_yy[k], p.weight_above[k], 1e-4 * p.weight_above[0]);
    EXPECT_NEAR(p.shear_stress[k], 0, 1e-4 * p.weight_above[0]);
    EXPECT_LT(std::fabs(p.velocity_x[k]), 1e-4);  // the solver's resolution: tolerance/dt
  }
}

}  // namespace
}  // namespace granflow
