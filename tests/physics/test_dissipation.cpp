// The engine's per-step tallies: collisions (contacts born in the step) and the kinetic
// energy the contact impulses dissipate, against closed forms and the energy balance of
// steady simple shear.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <set>
#include <vector>

#include "dynamics/engine.hpp"
#include "helpers.hpp"
#include "shear/observables.hpp"
#include "statistics/blocking.hpp"

namespace granflow {
namespace {

// Two equal disks (R = 0.5) on one line in a periodic box of side L, moving towards each
// other at ±v. Elastic and frictionless, they exchange velocities at each collision, so the
// pair's gaps (one on each side, summing to L − 4R) close at 2v in turn: collisions at
// t_k = g₀/(2v) + k·(L − 4R)/(2v). The run ends half a period after the 7th. Each collision
// meets the two disks at ±v along n: its velocity product (V_i·n)(V_j·n) is −v².
TEST(Collisions, TwoDisksInAPeriodicBoxCountedInClosedForm) {
  const double l = 10, r = 0.5, v = 0.5, g0 = 2;
  GrainState s = make_grains({Vec2(2, 5), Vec2(2 + 2 * r + g0, 5)}, {r, r});
  s.velocity[0] = Vec2(v, 0);
  s.velocity[1] = Vec2(-v, 0);
  const double first = g0 / (2 * v), period = (l - 4 * r) / (2 * v);
  const double end = first + 6 * period + 0.5 * period;
  int expected = 0;
  for (double t = first; t < end; t += period) ++expected;
  ASSERT_EQ(expected, 7);

  const double dt = 1.0 / 256;
  Engine engine(s, test::periodic_square(l), 0.0, {1.0, 0.0, 0.0}, {}, dt);
  const long steps = std::lround(end / dt);
  long counted = 0, births = 0;
  double product = 0;
  for (long k = 0; k < steps; ++k) {
    const StepReport& rep = engine.step();
    ASSERT_LE(rep.collisions, 1) << "step " << k;
    counted += rep.collisions;
    if (rep.collisions == 1) {
      EXPECT_NEAR(rep.collision_velocity_product, -v * v, 1e-12) << "step " << k;
    } else {
      EXPECT_EQ(rep.collision_velocity_product, 0) << "step " << k;
    }
    product += rep.collision_velocity_product;
    for (std::size_t c = 0; c < engine.contacts().size(); ++c) births += engine.contacts().age[c] == 1;
  }
  EXPECT_EQ(counted, expected);
  EXPECT_EQ(births, expected);
  EXPECT_NEAR(product, -expected * v * v, 1e-12);
}

// Kinetic energy, translational and rotational, independently of the engine.
double energy(const GrainState& s) { return test::kinetic_energy(s); }

// One head-on collision of unequal disks: the step's dissipated energy is
// (1 − e²)·m_red·u_n²/2, and the run's total equals the kinetic energy lost. The velocity
// product of the collision is that of the incoming velocities along the line of centres,
// 0.8·(−0.5), whatever e.
TEST(Dissipation, HeadOnCollisionMatchesClosedForm) {
  for (double e : {0.0, 0.5, 0.9}) {
    GrainState s = make_grains({Vec2(6, 12), Vec2(9, 12)}, {0.7, 0.45});
    s.velocity[0] = Vec2(0.8, 0);
    s.velocity[1] = Vec2(-0.5, 0);
    const double mred = s.mass[0] * s.mass[1] / (s.mass[0] + s.mass[1]);
    const double un = -1.3;
    const double expected = 0.5 * (1 - e * e) * mred * un * un;
    const double before = energy(s);
    Engine engine(s, test::periodic_square(24), 0.0, {e, 0.0, 0.0}, {}, 0.01);
    double total = 0;
    int collisions = 0;
    for (int k = 0; k < 300; ++k) {
      const StepReport& rep = engine.step();
      total += rep.dissipated_energy;
      collisions += rep.collisions;
      if (rep.collisions == 1) {
        EXPECT_NEAR(rep.dissipated_energy, expected, 1e-12 * expected) << "e = " << e;
        EXPECT_NEAR(rep.collision_velocity_product, 0.8 * -0.5, 1e-12) << "e = " << e;
      }
    }
    EXPECT_EQ(collisions, 1) << "e = " << e;
    EXPECT_NEAR(total, expected, 1e-12 * expected) << "e = " << e;
    EXPECT_NEAR(before - energy(engine.state()), total, 1e-12 * expected) << "e = " << e;
  }
}

// With friction, spin and a tangential impulse: the tally still equals the loss of kinetic
// energy, translational plus rotational.
TEST(Dissipation, FrictionalObliqueCollisionEqualsKineticEnergyLost) {
  const Vec2 n(0.8, 0.6);
  GrainState s = make_grains({Vec2(12, 12), Vec2(12, 12) - 2.0 * n}, {0.7, 0.45});
  s.velocity[0] = -0.9 * n + 0.4 * perp(n);
  s.velocity[1] = 0.6 * n - 0.1 * perp(n);
  s.angular_velocity[0] = 0.7;
  s.angular_velocity[1] = -1.1;
  const double before = energy(s);
  Engine engine(s, test::periodic_square(24), 0.0, {0.6, 0.2, 0.5}, {}, 0.01);
  double total = 0;
  for (int k = 0; k < 150; ++k) total += engine.step().dissipated_energy;
  EXPECT_GT(total, 0.01 * before);
  EXPECT_NEAR(before - energy(engine.state()), total, 1e-12 * before);
}

// An elastic frictionless gas (ν = 0.6): in every step whose contacts are disjoint pairs
// (binary collisions) the impulses take out nothing but round-off, below 10⁻¹³ of the mean
// kinetic energy per grain per contact (measured: 3·10⁻¹⁵). Steps where a grain carries two
// contacts do dissipate (Moreau's law on simultaneous contacts stops a closing pair at zero
// gap); whatever they take out, the tally is the energy the gas actually lost.
TEST(Dissipation, ElasticFrictionlessGasBinaryCollisionsDissipateNothing) {
  test::Packing p = test::random_packing(300, 0.6, 7, 1e-3);
  test::add_fluctuations(p.state, 1.0, 8);
  const double before = energy(p.state);
  const double per_grain = before / 300;
  Engine engine(p.state, p.box, 0.0, {1.0, 0.0, 0.0}, {}, 2e-3);
  double total = 0, largest_binary = 0;
  long binary_steps = 0, binary_collisions = 0;
  for (int k = 0; k < 1000; ++k) {
    const StepReport& rep = engine.step();
    total += rep.dissipated_energy;
    const ContactRecords& c = engine.contacts();
    std::vector<int> degree(300, 0);
    bool binary = true;
    for (std::size_t q = 0; q < c.size(); ++q) binary &= ++degree[c.pair[q][0]] == 1 && ++degree[c.pair[q][1]] == 1;
    if (!binary || c.size() == 0) continue;
    ++binary_steps;
    binary_collisions += rep.collisions;
    largest_binary = std::max(largest_binary, std::fabs(rep.dissipated_energy) / double(c.size()));
  }
  ASSERT_GT(binary_steps, 500);
  ASSERT_GT(binary_collisions, 500);
  RecordProperty("largest_binary_dissipation_per_contact_over_energy_per_grain",
                 std::to_string(largest_binary / per_grain));
  EXPECT_LT(largest_binary, 1e-13 * per_grain);
  EXPECT_NEAR(before - energy(engine.state()), total, 1e-12 * before);
}

// Steady simple shear (ν = 0.7, e = 0.5, frictionless): the work of the shear stress,
// s·γ̇·A per unit time, equals the dissipation rate, within block errors.
TEST(Dissipation, SteadyShearWorkEqualsDissipationRate) {
  const double rate = 1, dt = 2e-3;
  test::Packing p = test::random_packing(400, 0.7, 11, 1e-3);
  add_affine_flow(p.state, p.box, rate);
  Engine engine(p.state, p.box, rate, {0.5, 0.0, 0.0}, {}, dt);
  for (int k = 0; k < 1500; ++k) engine.step();  // transient: strain 3
  const double area = engine.box().area();
  std::vector<double> work, loss;
  // Births counted independently of the ages: pairs in contact now and not in the step before.
  std::set<std::array<int, 2>> previous(engine.contacts().pair.begin(), engine.contacts().pair.end());
  long lasting = 0;
  for (int k = 0; k < 2500; ++k) {  // strain 5
    const StepReport& rep = engine.step();
    std::set<std::array<int, 2>> now(engine.contacts().pair.begin(), engine.contacts().pair.end());
    int born = 0;
    for (const auto& pair : now) born += previous.count(pair) == 0;
    lasting += long(now.size()) - born;
    ASSERT_EQ(rep.collisions, born) << "step " << k;
    previous = std::move(now);
    const StressTensors st = stress(engine.state(), engine.box(), rate, engine.contacts());
    work.push_back(-shear_stress(st.total()) * rate * area);
    loss.push_back(rep.dissipated_energy / dt);
  }
  auto mean = [](const std::vector<double>& x) {
    double m = 0;
    for (double v : x) m += v;
    return m / double(x.size());
  };
  std::vector<double> diff(work.size());
  for (std::size_t k = 0; k < work.size(); ++k) diff[k] = work[k] - loss[k];
  const double w = mean(work), d = mean(loss);
  const Blocking err = blocking_error(diff);
  RecordProperty("work_rate", std::to_string(w));
  RecordProperty("dissipation_rate", std::to_string(d));
  RecordProperty("difference_error", std::to_string(err.error));
  ASSERT_GT(lasting, 1000);  // contacts that last several steps, which are not collisions
  ASSERT_GT(d, 0);
  EXPECT_NEAR(w, d, 3 * err.error + 1e-3 * d) << "work " << w << " dissipation " << d << " ± " << err.error;
  // The error bar is small enough for the test to mean something.
  EXPECT_LT(err.error, 0.05 * d);
}

}  // namespace
}  // namespace granflow
