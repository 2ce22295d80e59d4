// Incline depth profiles on constructed configurations with known answers: the exact
// area of a disk in a strip, the contact stress of a resting vertical chain split among
// layers (it must equal the weight above, layer by layer) and the mean-shear subtraction of
// the temperature. The steady-state detection gf-incline applies is tested in test_steady.cpp.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <vector>

#include "core/error.hpp"
#include "core/random.hpp"
#include "dynamics/engine.hpp"
#include "incline/observer.hpp"
#include "incline/profiles.hpp"
#include "io/trajectory.hpp"

namespace granflow {
namespace {

// ∫ over the strip of the chord length, by the midpoint rule.
double strip_area_numeric(double yc, double r, double a, double b) {
  const int n = 200000;
  double area = 0;
  const double h = (b - a) / n;
  for (int k = 0; k < n; ++k) {
    const double u = a + (k + 0.5) * h - yc;
    if (std::fabs(u) < r) area += 2 * std::sqrt(r * r - u * u) * h;
  }
  return area;
}

TEST(DiskStripArea, WholeHalfAndOutside) {
  const double r = 0.7;
  EXPECT_NEAR(disk_strip_area(3, r, 0, 10), M_PI * r * r, 1e-14);
  EXPECT_NEAR(disk_strip_area(3, r, 3, 10), 0.5 * M_PI * r * r, 1e-14);
  EXPECT_EQ(disk_strip_area(3, r, 4, 10), 0.0);
  EXPECT_EQ(disk_strip_area(3, r, -5, 2), 0.0);
}

TEST(DiskStripArea, MatchesIntegrationAndAddsUp) {
  Rng rng(4);
  for (int trial = 0; trial < 20; ++trial) {
    const double r = rng.uniform(0.3, 1.0), yc = rng.uniform(-1, 1);
    const double a = rng.uniform(-1.5, 1.5), b = a + rng.uniform(0.01, 2);
    EXPECT_NEAR(disk_strip_area(yc, r, a, b), strip_area_numeric(yc, r, a, b), 2e-8) << trial;
  }
  // Strips tiling the line cover the disk exactly once.
  double total = 0;
  for (int k = -5; k < 5; ++k) total += disk_strip_area(0.123, 0.9, 0.37 * k, 0.37 * (k + 1));
  EXPECT_NEAR(total, M_PI * 0.81, 1e-14);
}

// A fixed grain at y = 0 carrying a vertical chain of touching disks of different radii.
struct Chain {
  GrainState state;
  Box box;
};

Chain vertical_chain() {
  const std::vector<double> radii{0.6, 0.75, 0.55, 0.8, 0.65, 0.7, 0.5};
  std::vector<Vec2> position;
  double y = 0;
  for (std::size_t k = 0; k < radii.size(); ++k) {
    if (k > 0) y += radii[k - 1] + radii[k];
    position.emplace_back(4.0, y);
  }
  Chain c;
  c.state = make_grains(position, radii);
  c.state.fixed[0] = 1;
  c.box = Box{9.0, y + radii.back() + 1.4, false, 0.0};
  return c;
}

// The chain's contacts at rest: each carries the weight of the disks above it.
ContactRecords resting_forces(const GrainState& s, double g) {
  ContactRecords c;
  for (std::size_t k = 0; k + 1 < s.size(); ++k) {
    double above = 0;
    for (std::size_t i = k + 1; i < s.size(); ++i) above += s.mass[i];
    c.pair.push_back({int(k), int(k + 1)});
    c.branch.push_back(s.position[k] - s.position[k + 1]);  // r_i − r_j points down
    c.normal_force.push_back(g * above);                    // on the lower grain i, along n̂ (down)
    c.tangential_force.push_back(0);
    c.binary_force.push_back(0);
    c.pre_normal_velocity.push_back({0, 0});
    c.age.push_back(1);
  }
  return c;
}

// (g/Lx)·(1/Δy)·∫ over the layer of the mass above y, by numerical integration.
double weight_above_numeric(const GrainState& s, double g, double lx, double a, double b) {
  const int n = 100000;
  double sum = 0;
  for (int k = 0; k < n; ++k) {
    const double y = a + (k + 0.5) * (b - a) / n;
    for (std::size_t i = 0; i < s.size(); ++i)
      if (!s.fixed[i] && s.position[i].y() > y) sum += s.mass[i];
  }
  return g * sum / n / lx;
}

TEST(ContactStressSplitting, RestingChainCarriesTheWeightAboveEveryLayer) {
  const double g = 2.5, bin = 0.45;
  const Chain chain = vertical_chain();
  const ProfileGrid grid = profile_grid(chain.box, bin);
  ProfileAccumulator acc(grid, 10);
  const ContactRecords contacts = resting_forces(chain.state, g);
  for (int step = 1; step <= 3; ++step)
    acc.add(step, step * 0.1, chain.state, contacts, incline_observables(chain.state));
  const double mean_r = 0.65, mean_m = 1.3;
  const Profiles p = average_profiles(grid, acc.blocks(), 0, g, mean_r, mean_m);
  ASSERT_EQ(p.samples, 3);
  ASSERT_GT(p.y.size(), 15u);
  for (std::size_t k = 0; k < p.y.size(); ++k) {
    const double a = double(k) * bin, b = a + bin;
    const double w = weight_above_numeric(chain.state, g, chain.box.lx, a, b);
    EXPECT_NEAR(p.weight_above[k], w, 1e-4 * w + 1e-12) << "layer " << k;
    EXPECT_NEAR(p.stress_yy[k], p.weight_above[k], 1e-12 * p.weight_above[k] + 1e-15) << "layer " << k;
    EXPECT_NEAR(p.stress_xx[k], 0, 1e-15);
    EXPECT_NEAR(p.shear_stress[k], 0, 1e-15);
  }
  // The same from the engine's own forces: the resting chain is an exact equilibrium.
  Engine engine(chain.state, chain.box, 0.0, Material{}, SolverSettings{}, 1e-3, Vec2(0, -g));
  ProfileAccumulator solved(grid, 10);
  for (int step = 1; step <= 20; ++step) {
    engine.step();
    solved.add(step, engine.time(), engine.state(), engine.contacts(), incline_observables(engine.state()));
  }
  const Profiles q = average_profiles(grid, solved.blocks(), 1, g, mean_r, mean_m);
  for (std::size_t k = 0; k < q.y.size(); ++k)
    EXPECT_NEAR(q.stress_yy[k], q.weight_above[k], 1e-4 * q.weight_above[k]) << "layer " << k;
}

TEST(Profiles, PackingFractionOfALayerOfDisks) {
  // Equal disks side by side, centres at y = 1 in layers of 2: each layer holds exactly
  // half of each disk.
  const double r = 0.5, lx = 10;
  std::vector<Vec2> position;
  for (int k = 0; k < 10; ++k) position.emplace_back(0.5 + k, 1.0);
  GrainState s = make_grains(position, std::vector<double>(10, r));
  const ProfileGrid grid = profile_grid(Box{lx, 3.0, false, 0.0}, 1.0);
  ProfileAccumulator acc(grid, 1);
  acc.add(1, 0.0, s, {}, incline_observables(s));
  const Profiles p = average_profiles(grid, acc.blocks(), 0, 1.0, r, M_PI * r * r);
  ASSERT_EQ(p.packing_fraction.size(), 2u);  // the empty top layer is cut
  EXPECT_NEAR(p.packing_fraction[0], 10 * 0.5 * M_PI * r * r / lx, 1e-14);
  EXPECT_NEAR(p.packing_fraction[1], 10 * 0.5 * M_PI * r * r / lx, 1e-14);
}

TEST(Profiles, MeanShearInsideALayerIsNotHeat) {
  // Rows of grains in a linear flow v_x = γ̇y, plus v_y = ±u alternating in every row:
  // the mean shear across each thick layer must not count as temperature, so T = u²
  // exactly, V_x = γ̇·(layer centre), and the kinetic Σxx vanishes.
  const double rate = 0.8, u = 0.1, bin = 3.0, r = 0.2;
  std::vector<Vec2> position;
  for (int row = 0; row < 12; ++row)
    for (int k = 0; k < 8; ++k) position.emplace_back(0.5 + k, 0.25 + 0.5 * row);
  GrainState s = make_grains(position, std::vector<double>(position.size(), r));
  for (std::size_t i = 0; i < s.size(); ++i) s.velocity[i] = Vec2(rate * s.position[i].y(), (i % 2 ? u : -u));
  const ProfileGrid grid = profile_grid(Box{8.0, 6.0, false, 0.0}, bin);
  ProfileAccumulator acc(grid, 1);
  acc.add(1, 0.0, s, {}, incline_observables(s));
  const Profiles p = average_profiles(grid, acc.blocks(), 0, 1.0, r, M_PI * r * r);
  ASSERT_EQ(p.y.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_NEAR(p.velocity_x[k], rate * p.y[k], 1e-14);
    EXPECT_NEAR(p.shear_rate[k], rate, 1e-14);
    EXPECT_NEAR(p.temperature[k], u * u, 1e-12);
    EXPECT_NEAR(p.stress_xx[k], 0, 1e-12);
    EXPECT_NEAR(p.stress_yy[k], 6 * 8 * M_PI * r * r * u * u / (8 * bin), 1e-14);
  }
}

TEST(ProfileBlocks, RoundTripThroughATrajectoryFile) {
  const Chain chain = vertical_chain();
  const ProfileGrid grid = profile_grid(chain.box, 0.7);
  ProfileAccumulator acc(grid, 2);
  const ContactRecords contacts = resting_forces(chain.state, 1.0);
  GrainState moving = chain.state;
  for (std::size_t i = 1; i < moving.size(); ++i) moving.velocity[i] = Vec2(0.1 * double(i), -0.03 * double(i * i));
  for (int step = 1; step <= 5; ++step)  // blocks of 2, 2 and 1 samples
    acc.add(step, 0.01 * step, moving, contacts, incline_observables(moving));
  const std::string path =
      (std::filesystem::temp_directory_path() / ("granflow_blocks_" + std::to_string(::getpid()) + ".h5")).string();
  {
    io::TrajectoryWriter writer(path);
    writer.write_grains({chain.state.radius, chain.state.mass, chain.state.fixed}, chain.box);
    io::Frame frame;
    frame.box = chain.box;
    frame.position = chain.state.position;
    frame.velocity = moving.velocity;
    frame.orientation = chain.state.orientation;
    frame.angular_velocity = chain.state.angular_velocity;
    writer.append_frame(frame);
    write_blocks(writer, "/state", acc);
    writer.close();
  }
  const std::vector<ProfileBlock> back = read_blocks(io::TrajectoryReader(path), "/state", grid);
  ASSERT_EQ(back.size(), 3u);
  for (std::size_t b = 0; b < back.size(); ++b) {
    const ProfileBlock& a = acc.blocks()[b];
    EXPECT_EQ(back[b].index, a.index);
    EXPECT_EQ(back[b].samples, a.samples);
    EXPECT_EQ(back[b].time_begin, a.time_begin);
    EXPECT_EQ(back[b].time_end, a.time_end);
    EXPECT_EQ(back[b].observables.kinetic_energy, a.observables.kinetic_energy);
    EXPECT_EQ(back[b].sums, a.sums);
  }
  // A grid of another size is refused with the file's name.
  EXPECT_THROW(read_blocks(io::TrajectoryReader(path), "/state", profile_grid(chain.box, 0.35)), UsageError);
  std::filesystem::remove(path);
}

// The automatic block length (--profile-block 0): 5000 steps for runs of 10⁵ steps or
// more, so long runs keep the blocks they always had; shorter runs get at least 20 full
// blocks for the steady-state detection; never less than one step.
TEST(ProfileBlocks, AutomaticLengthFitsTheRun) {
  EXPECT_EQ(automatic_profile_block(1000000), 5000);
  EXPECT_EQ(automatic_profile_block(100000), 5000);
  EXPECT_EQ(automatic_profile_block(99999), 4999);
  EXPECT_EQ(automatic_profile_block(1000), 50);
  EXPECT_EQ(automatic_profile_block(25), 1);
  EXPECT_EQ(automatic_profile_block(1), 1);
  for (std::int64_t steps : {1, 7, 19, 20, 39, 1000, 12345, 99999, 100000, 250000})
    EXPECT_GE(steps / automatic_profile_block(steps), std::min<std::int64_t>(20, steps)) << steps;
}

}  // namespace
}  // namespace granflow
