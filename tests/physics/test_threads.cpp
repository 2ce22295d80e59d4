// Determinism under threads (SolverSettings::threads): any thread count gives the same
// trajectory bit for bit, which is what lets --threads change on --resume. The thread
// split of the sparse factorisation alone is tested in tests/unit/test_sparse_ldl.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "dynamics/engine.hpp"
#include "helpers.hpp"
#include "packing/packing.hpp"

namespace granflow {
namespace {

using test::expect_same_state;

// Threads share the sweeps strip by strip and every other loop element by element, in an
// order that does not depend on their number: 1 and 2 threads, run twice each, give one
// trajectory, bit for bit.
TEST(Threads, SameTrajectoryForAnyThreadCount) {
  for (const Material& mat : {Material{0.5, 0.0, 0.0}, Material{0.5, 0.2, 0.3}}) {
    SCOPED_TRACE(mat.friction);
    test::Packing p = test::random_packing(400, 0.78, 91);
    add_affine_flow(p.state, p.box, 1.0);
    test::add_fluctuations(p.state, 0.3, 92);
    std::vector<GrainState> finals;
    std::vector<std::vector<double>> forces;
    for (int threads : {1, 2, 1, 2}) {
      SolverSettings settings;
      settings.threads = threads;
      Engine engine(p.state, p.box, 1.0, mat, settings, 1e-3);
      for (int k = 0; k < 200; ++k) ASSERT_TRUE(engine.step().converged);
      finals.push_back(engine.state());
      forces.push_back(engine.contacts().normal_force);
    }
    EXPECT_GT(forces[0].size(), 50u);
    for (std::size_t run = 1; run < finals.size(); ++run) {
      SCOPED_TRACE(run);
      EXPECT_EQ(forces[run], forces[0]);
      expect_same_state(finals[run], finals[0]);
    }
  }
}

// From the affine start at ν = 0.82 the active contacts percolate: clusters of thousands of
// rows, whose factorisation the threads share (SparseLdl by subtrees), give the same
// trajectory for any thread count too.
TEST(Threads, SameTrajectoryWithSharedClusterFactor) {
  PackingParams params;
  params.grains = 5000;
  params.packing_fraction = 0.82;
  const Packing packing = make_biperiodic_packing(params);
  GrainState start = make_grains(packing.position, packing.radius);
  add_affine_flow(start, packing.box, 1.0);
  std::vector<GrainState> finals;
  int largest = 0;
  for (int threads : {1, 2, 3}) {
    SolverSettings settings;
    settings.threads = threads;
    Engine engine(start, packing.box, 1.0, Material{0.5, 0.0, 0.0}, settings, 1e-3);
    for (int k = 0; k < 10; ++k) {
      const StepReport& r = engine.step();
      ASSERT_TRUE(r.converged);
      largest = std::max(largest, r.largest_cluster);
    }
    finals.push_back(engine.state());
  }
  EXPECT_GE(largest, 2000);  // kSharedClusterRows: the shared factorisation was used
  for (std::size_t run = 1; run < finals.size(); ++run) {
    SCOPED_TRACE(run);
    expect_same_state(finals[run], finals[0]);
  }
}

}  // namespace
}  // namespace granflow
