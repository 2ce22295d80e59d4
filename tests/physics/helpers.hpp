#pragma once
// Shared set-ups for the physics tests: packings built here (not by gf-pack), energies
// and momenta computed independently of the engine.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "core/random.hpp"
#include "core/vec.hpp"
#include "dynamics/grains.hpp"
#include "geometry/box.hpp"
#include "neighbours/cell_list.hpp"

namespace granflow::test {

struct Packing {
  GrainState state;
  Box box;
};

// n disks, diameters uniform in σ(1 ± 0.26), in a square Lees–Edwards cell at packing
// fraction nu: random positions, then overlaps removed by repeated pairwise push-apart
// until every gap is at least `margin`. Grains are at rest.
inline Packing random_packing(int n, double nu, std::uint64_t seed, double margin = 1e-6) {
  const double sigma = 1.4, delta = 0.26 * sigma;
  Rng rng(seed);
  std::vector<double> radii(n);
  double area = 0;
  for (double& r : radii) {
    r = 0.5 * rng.uniform(sigma - delta, sigma + delta);
    area += M_PI * r * r;
  }
  Packing p;
  p.box.lx = p.box.ly = std::sqrt(area / nu);
  p.box.periodic_y = true;
  std::vector<Vec2> pos(n);
  for (Vec2& r : pos) r = Vec2(rng.uniform(0, p.box.lx), rng.uniform(0, p.box.ly));
  const double rmax = *std::max_element(radii.begin(), radii.end());
  CellList cells;
  std::vector<Vec2> push(n), velocity(n, Vec2::Zero());
  for (int sweep = 0;; ++sweep) {
    if (sweep == 20000) throw std::runtime_error("random_packing: overlaps not removed");
    cells.build(pos, p.box, 2 * rmax + margin);
    std::fill(push.begin(), push.end(), Vec2::Zero());
    bool clear = true;
    cells.for_each_pair(pos, [&](int i, int j, const Vec2& d) {
      const double dist = d.norm();
      const double deficit = radii[i] + radii[j] + margin - dist;
      if (deficit <= 0) return;
      clear = false;
      // Over-resolve slightly so that pairs do not creep towards the margin forever.
      const Vec2 shift = (0.3 * (deficit + margin)) * d / dist;
      push[i] += shift;
      push[j] -= shift;
    });
    if (clear) break;
    for (int i = 0; i < n; ++i) {
      pos[i] += push[i];
      p.box.wrap(pos[i], velocity[i], 0.0);
    }
  }
  p.state = make_grains(pos, radii);
  return p;
}

// Adds Gaussian velocity and spin fluctuations of scale `scale` with zero total momentum.
inline void add_fluctuations(GrainState& s, double scale, std::uint64_t seed) {
  Rng rng(seed);
  Vec2 momentum = Vec2::Zero();
  double mass = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const Vec2 dv(scale * rng.normal(), scale * rng.normal());
    s.velocity[i] += dv;
    s.angular_velocity[i] += scale * rng.normal() / s.radius[i];
    momentum += s.mass[i] * dv;
    mass += s.mass[i];
  }
  for (std::size_t i = 0; i < s.size(); ++i) s.velocity[i] -= momentum / mass;
}

// A square box of side l, periodic in x and y, without shear.
inline Box periodic_square(double l) {
  Box b;
  b.lx = b.ly = l;
  b.periodic_y = true;
  return b;
}

inline double kinetic_energy(const GrainState& s) {
  double e = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double inertia = 0.5 * s.mass[i] * s.radius[i] * s.radius[i];
    e += 0.5 * s.mass[i] * s.velocity[i].squaredNorm() + 0.5 * inertia * s.angular_velocity[i] * s.angular_velocity[i];
  }
  return e;
}

// Σ m ṽ: the momentum of the fluctuating velocities (lab momentum when rate = 0).
inline Vec2 fluctuating_momentum(const GrainState& s, const Box& box, double rate) {
  Vec2 p = Vec2::Zero();
  for (std::size_t i = 0; i < s.size(); ++i) p += s.mass[i] * fluctuating_velocity(s, box, rate, i);
  return p;
}

// Smallest gap over all pairs (brute force, minimum image).
inline double min_gap(const GrainState& s, const Box& box) {
  double g = INFINITY;
  for (std::size_t i = 0; i < s.size(); ++i)
    for (std::size_t j = i + 1; j < s.size(); ++j)
      g = std::min(g, box.minimum_image(s.position[i] - s.position[j]).norm() - s.radius[i] - s.radius[j]);
  return g;
}

// Bit-for-bit equality of two grain states (positions, velocities, spins).
inline void expect_same_state(const GrainState& a, const GrainState& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t g = 0; g < a.size(); ++g) {
    ASSERT_EQ(a.position[g], b.position[g]) << "grain " << g;
    ASSERT_EQ(a.velocity[g], b.velocity[g]) << "grain " << g;
    ASSERT_EQ(a.angular_velocity[g], b.angular_velocity[g]) << "grain " << g;
  }
}

}  // namespace granflow::test
