// The engine's reusable pair list (candidates within the alert distance plus a skin,
// rebuilt only when an unlisted pair could have come within the alert distance) against a
// fresh search every step. The cell list itself is tested in tests/unit/test_cell_list.cpp.
#include <gtest/gtest.h>

#include <cstddef>

#include "dynamics/engine.hpp"
#include "helpers.hpp"

namespace granflow {
namespace {

// The pair list only saves work: rebuilt every step (a vanishing skin) or only when needed,
// the candidates, hence the trajectories, are the same to the last bit.
TEST(PairList, SkinDoesNotChangeTrajectory) {
  for (const Material& mat : {Material{0.5, 0.0, 0.0}, Material{0.5, 0.2, 0.3}}) {
    SCOPED_TRACE(mat.friction);
    SolverSettings fresh, reused;
    fresh.skin = 1e-12;
    test::Packing p = test::random_packing(200, 0.75, 81);
    add_affine_flow(p.state, p.box, 1.0);
    test::add_fluctuations(p.state, 0.5, 82);
    Engine a(p.state, p.box, 1.0, mat, fresh, 1e-3), b(p.state, p.box, 1.0, mat, reused, 1e-3);
    int rebuilt_a = 0, rebuilt_b = 0;
    for (int k = 0; k < 300; ++k) {
      rebuilt_a += a.step().pairs_rebuilt;
      rebuilt_b += b.step().pairs_rebuilt;
      ASSERT_EQ(a.last_report().candidates, b.last_report().candidates) << "step " << k;
    }
    EXPECT_EQ(rebuilt_a, 300);
    EXPECT_LT(rebuilt_b, 60);
    EXPECT_GT(rebuilt_b, 0);
    for (std::size_t g = 0; g < p.state.size(); ++g) {
      ASSERT_EQ(a.state().position[g], b.state().position[g]);
      ASSERT_EQ(a.state().velocity[g], b.state().velocity[g]);
      ASSERT_EQ(a.state().angular_velocity[g], b.state().angular_velocity[g]);
    }
    EXPECT_EQ(a.contacts().normal_force, b.contacts().normal_force);
  }
}

}  // namespace
}  // namespace granflow
