// gf-shear as a user runs it: bad input, and the exactness of checkpoint/resume and of
// branching from a stored frame (both must reproduce the uninterrupted run bit for bit).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "io/trajectory.hpp"
#include "programs/run_tool.hpp"
#include "unit/expect_frame.hpp"

using namespace granflow::testing;
namespace io = granflow::io;

namespace {
// One packing shared by the tests of this file.
const std::string& packing() { return packed_once("shear_packing", "--grains 200 --packing-fraction 0.7 --seed 3"); }

void expect_same_frame(const io::Frame& a, const io::Frame& b, const std::string& what) {
  ASSERT_EQ(a.position.size(), b.position.size()) << what;
  for (std::size_t i = 0; i < a.position.size(); ++i) {
    ASSERT_EQ(a.position[i], b.position[i]) << what << " grain " << i;
    ASSERT_EQ(a.velocity[i], b.velocity[i]) << what << " grain " << i;
    ASSERT_EQ(a.angular_velocity[i], b.angular_velocity[i]) << what << " grain " << i;
    ASSERT_EQ(a.orientation[i], b.orientation[i]) << what << " grain " << i;
  }
  EXPECT_EQ(a.box.offset, b.box.offset) << what;
  EXPECT_EQ(a.contacts.pair, b.contacts.pair) << what;
  EXPECT_EQ(a.contacts.normal_force, b.contacts.normal_force) << what;
  EXPECT_EQ(a.contacts.tangential_force, b.contacts.tangential_force) << what;
  EXPECT_EQ(a.contacts.age, b.contacts.age) << what;
}

const std::string kRun = "--rate 0.01 --strain-step 1e-3 --restitution 0.5 --friction 0.4 --frame-every 100 --quiet";
}  // namespace

// The interrupted runs are 20 000 steps (about 2 s on an idle machine) so that the interruption, 300 ms after the
// partial output appears, lands before the end however fast the machine is: a skip would assert nothing.

TEST(GfShearResume, InterruptedAndResumedEqualsUninterrupted) {
  ScratchDir dir("shear_resume");
  const std::string steps = " --steps 20000 ";
  ASSERT_EQ(run_tool("gf-shear", "-i " + packing() + steps + kRun + " -o " + (dir / "ref.h5")).exit_code, 0);

  const std::string args = "-i " + packing() + steps + kRun + " -o " + (dir / "cut.h5");
  const int code = interrupted_run("gf-shear", args, dir / "cut.h5", dir / "log1", 300);
  if (code == 0) GTEST_SKIP() << "the run finished before it could be interrupted";
  ASSERT_EQ(code, 1);
  EXPECT_FALSE(std::filesystem::exists(dir / "cut.h5")) << "an interrupted run left a finished-looking output";
  ASSERT_TRUE(std::filesystem::exists(dir / ".cut.h5.checkpoint"));
  ASSERT_EQ(partials_of(dir.path / "cut.h5").size(), 1u);

  auto resumed = run_tool("gf-shear", args + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_FALSE(std::filesystem::exists(dir / ".cut.h5.checkpoint"));
  EXPECT_TRUE(partials_of(dir.path / "cut.h5").empty());

  granflow::test_support::expect_same_run(
      dir / "ref.h5", dir / "cut.h5",
      {"pressure", "shear_stress", "temperature", "solver_iterations", "collisions", "dissipated_energy"});
}

// The collisions, velocity products and dissipated energy accumulated since the last observable row are part of
// the checkpoint: with rows 250 steps apart, an interruption almost surely falls between two.
TEST(GfShearResume, TalliesBetweenRowsSurviveAResume) {
  ScratchDir dir("shear_resume_tally");
  const std::string steps = " --steps 20000 --observe-every 250 ";
  ASSERT_EQ(run_tool("gf-shear", "-i " + packing() + steps + kRun + " -o " + (dir / "ref.h5")).exit_code, 0);
  const std::string args = "-i " + packing() + steps + kRun + " -o " + (dir / "cut.h5");
  const int code = interrupted_run("gf-shear", args, dir / "cut.h5", dir / "log1", 300);
  if (code == 0) GTEST_SKIP() << "the run finished before it could be interrupted";
  ASSERT_EQ(code, 1);
  auto resumed = run_tool("gf-shear", args + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  granflow::test_support::expect_same_run(dir / "ref.h5", dir / "cut.h5",
                                          {"collisions", "collision_velocity_product", "dissipated_energy"});
}

// Each row holds what happened since the previous one: the rows sum to the same totals
// whatever --observe-every is.
TEST(GfShearObservables, TalliesSumToTheSameTotalsWhateverObserveEvery) {
  ScratchDir dir("shear_tally_rows");
  const std::string run = "-i " + packing() + " --steps 700 " + kRun;
  ASSERT_EQ(run_tool("gf-shear", run + " --observe-every 1 -o " + (dir / "every.h5")).exit_code, 0);
  ASSERT_EQ(run_tool("gf-shear", run + " --observe-every 7 -o " + (dir / "seventh.h5")).exit_code, 0);
  io::TrajectoryReader every(dir / "every.h5"), seventh(dir / "seventh.h5");
  auto sum = [](const std::vector<double>& x) {
    double s = 0;
    for (double v : x) s += v;
    return s;
  };
  ASSERT_EQ(every.observable_scalar("collisions").size(), 700u);
  ASSERT_EQ(seventh.observable_scalar("collisions").size(), 100u);
  const double collisions = sum(every.observable_scalar("collisions"));
  EXPECT_GT(collisions, 100);
  EXPECT_EQ(collisions, sum(seventh.observable_scalar("collisions")));
  const double lost = sum(every.observable_scalar("dissipated_energy"));
  EXPECT_GT(lost, 0);
  EXPECT_NEAR(lost, sum(seventh.observable_scalar("dissipated_energy")), 1e-12 * lost);
  const double product = sum(every.observable_scalar("collision_velocity_product"));
  EXPECT_NE(product, 0);
  EXPECT_NEAR(product, sum(seventh.observable_scalar("collision_velocity_product")), 1e-12 * std::fabs(product));
}

TEST(GfShearResume, ResumeWithOtherOptionsIsRefused) {
  ScratchDir dir("shear_resume_other");
  const std::string args = "-i " + packing() + " --steps 20000 " + kRun + " -o " + (dir / "cut.h5");
  if (interrupted_run("gf-shear", args, dir / "cut.h5", dir / "log", 100, SIGTERM) != 1)
    GTEST_SKIP() << "the run finished before it could be interrupted";
  auto r = run_tool("gf-shear", args + " --friction 0.1 --resume");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("other options"), std::string::npos) << r.err;
}

TEST(GfShearBranch, FromAStoredFrameEqualsTheOriginalRun) {
  ScratchDir dir("shear_branch");
  ASSERT_EQ(run_tool("gf-shear", "-i " + packing() + " --steps 1500 " + kRun + " -o " + (dir / "ref.h5")).exit_code, 0);
  // Frame 5 is step 500; 1000 more steps end where the reference ends.
  auto r =
      run_tool("gf-shear", "-i " + (dir / "ref.h5") + " --frame 5 --steps 1000 " + kRun + " -o " + (dir / "branch.h5"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  io::TrajectoryReader ref(dir / "ref.h5"), branch(dir / "branch.h5");
  ASSERT_EQ(branch.frame_count(), 11u);
  for (std::size_t k = 0; k < branch.frame_count(); ++k)
    expect_same_frame(ref.frame(k + 5), branch.frame(k), "branch frame " + std::to_string(k));
  auto p_ref = ref.observable_scalar("pressure"), p_branch = branch.observable_scalar("pressure");
  ASSERT_EQ(p_branch.size(), 1000u);
  for (std::size_t k = 0; k < p_branch.size(); ++k) ASSERT_EQ(p_branch[k], p_ref[k + 500]) << k;
}

// --threads splits the solver's work without changing its order: the same file content.
TEST(GfShearThreads, TwoThreadsGiveTheSameTrajectory) {
  ScratchDir dir("shear_threads");
  for (const char* threads : {"1", "2"})
    ASSERT_EQ(run_tool("gf-shear", "-i " + packing() + " --steps 300 " + kRun + " --threads " + threads + " -o " +
                                       (dir / (std::string("t") + threads + ".h5")))
                  .exit_code,
              0);
  io::TrajectoryReader one(dir / "t1.h5"), two(dir / "t2.h5");
  ASSERT_EQ(one.frame_count(), two.frame_count());
  for (std::size_t k = 0; k < one.frame_count(); ++k)
    expect_same_frame(one.frame(k), two.frame(k), "frame " + std::to_string(k));
  EXPECT_EQ(one.observable_scalar("pressure"), two.observable_scalar("pressure"));
}

TEST(GfShearBranch, BagnoldRescalingOnRateChange) {
  // Branching a run at 100× the rate is the same trajectory played 100× faster:
  // positions identical step for step up to round-off, stresses ×10⁴.
  ScratchDir dir("shear_bagnold_branch");
  ASSERT_EQ(run_tool("gf-shear", "-i " + packing() + " --steps 300 " + kRun + " -o " + (dir / "ref.h5")).exit_code, 0);
  const std::string common =
      " --steps 100 --strain-step 1e-3 --restitution 0.5 --friction 0.4 --frame-every 100 --quiet";
  ASSERT_EQ(
      run_tool("gf-shear", "-i " + (dir / "ref.h5") + " --frame 2 --rate 0.01" + common + " -o " + (dir / "slow.h5"))
          .exit_code,
      0);
  ASSERT_EQ(run_tool("gf-shear", "-i " + (dir / "ref.h5") + " --frame 2 --rate 1" + common + " -o " + (dir / "fast.h5"))
                .exit_code,
            0);
  io::TrajectoryReader slow(dir / "slow.h5"), fast(dir / "fast.h5");
  auto a = slow.frame(1), b = fast.frame(1);
  double worst = 0;
  for (std::size_t i = 0; i < a.position.size(); ++i) worst = std::max(worst, (a.position[i] - b.position[i]).norm());
  EXPECT_LT(worst, 1e-9);
  auto pa = slow.observable_scalar("pressure"), pb = fast.observable_scalar("pressure");
  for (std::size_t k = 0; k < pa.size(); ++k) ASSERT_NEAR(pb[k] / 1e4, pa[k], 1e-6 * std::fabs(pa[k])) << k;
}

// --branch-velocities: recorded in /parameters for a branch (scale by default), not for a
// packing start; frame 0 of a reversed branch holds the rule's velocities: scale −v, keep
// the stored fluctuations about the reversed mean flow, reset the affine flow of −γ̇₀.
TEST(GfShearBranch, VelocityModesRecordedAndApplied) {
  ScratchDir dir("shear_branch_modes");
  ASSERT_EQ(run_tool("gf-shear", "-i " + packing() + " --steps 200 " + kRun + " -o " + (dir / "ref.h5")).exit_code, 0);
  EXPECT_FALSE(io::TrajectoryReader(dir / "ref.h5").parameters().has("branch-velocities"));
  const std::string common = " --steps 10 --strain-step 1e-3 --restitution 0.5 --friction 0.4 --quiet";
  io::TrajectoryReader ref(dir / "ref.h5");
  const io::Frame stored = ref.frame(2);
  const double ly = stored.box.ly, rate = 0.01;
  for (const std::string mode : {"", "scale", "keep", "reset"}) {
    SCOPED_TRACE(mode);
    const std::string out = dir / ("back_" + mode + ".h5");
    auto r = run_tool("gf-shear", "-i " + (dir / "ref.h5") + " --frame 2 --rate -0.01" + common +
                                      (mode.empty() ? "" : " --branch-velocities " + mode) + " -o " + out);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    io::TrajectoryReader branch(out);
    EXPECT_EQ(branch.parameters().get_string("branch-velocities"), mode.empty() ? "scale" : mode);
    const io::Frame f = branch.frame(0);
    for (std::size_t i = 0; i < f.velocity.size(); ++i) {
      const double u = stored.position[i].y() - 0.5 * ly;  // the mean flow is ±rate·u
      granflow::Vec2 v;
      double w;
      if (mode == "keep") {
        v = stored.velocity[i] - granflow::Vec2(rate * u, 0) + granflow::Vec2(-rate * u, 0);
        w = stored.angular_velocity[i] + 0.5 * rate - 0.5 * -rate;
      } else if (mode == "reset") {
        v = granflow::Vec2(-rate * u, 0);
        w = 0.5 * rate;
      } else {
        v = -stored.velocity[i];
        w = -stored.angular_velocity[i];
      }
      ASSERT_EQ(f.velocity[i], v) << "grain " << i;
      ASSERT_EQ(f.angular_velocity[i], w) << "grain " << i;
    }
    EXPECT_EQ(f.contacts.pair, stored.contacts.pair);
    EXPECT_EQ(f.contacts.normal_force, stored.contacts.normal_force);  // a² = 1
    EXPECT_EQ(f.contacts.age, stored.contacts.age);
  }
}

// --activation: recorded in /parameters (predicted-gap by default); under the thesis' rule
// (overlap) pairs overlap before they bounce, by orders of magnitude more than the
// tolerance that bounds the default's overlaps.
TEST(GfShearActivation, RecordedAndOverlapsOnlyUnderTheThesisRule) {
  ScratchDir dir("shear_activation");
  const std::string common = "-i " + packing() + " --steps 300 --rate 0.01 --strain-step 1e-3 --restitution 0.5 --quiet";
  ASSERT_EQ(run_tool("gf-shear", common + " -o " + (dir / "gap.h5")).exit_code, 0);
  auto r = run_tool("gf-shear", common + " --activation overlap -o " + (dir / "overlap.h5"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  io::TrajectoryReader gap(dir / "gap.h5"), overlap(dir / "overlap.h5");
  EXPECT_EQ(gap.parameters().get_string("activation"), "predicted-gap");
  EXPECT_EQ(overlap.parameters().get_string("activation"), "overlap");
  const auto a = gap.observable_scalar("max_overlap"), b = overlap.observable_scalar("max_overlap");
  const double worst_gap = *std::max_element(a.begin(), a.end());
  const double worst_overlap = *std::max_element(b.begin(), b.end());
  EXPECT_LT(worst_gap, 1e-8);
  EXPECT_GT(worst_overlap, 1e3 * std::max(worst_gap, 1e-10));
}

// ---- bad input: exit 2, one line naming the problem, no output file left ----

class GfShearBadInput : public ::testing::TestWithParam<BadInput> {};

TEST_P(GfShearBadInput, FailsWithExitTwoOneLineNoOutput) {
  expect_refused("gf-shear", GetParam(), {{"{in}", packing()}});  // {in}: a valid packing
}

INSTANTIATE_TEST_SUITE_P(
    Cases, GfShearBadInput,
    ::testing::Values(BadInput{"restitution_above_one", "-i {in} -o {out} --restitution 1.5", "--restitution"},
                      BadInput{"restitution_negative", "-i {in} -o {out} --restitution -0.1", "--restitution"},
                      BadInput{"friction_negative", "-i {in} -o {out} --friction -1", "--friction"},
                      BadInput{"dt_zero", "-i {in} -o {out} --dt 0", "--dt"},
                      BadInput{"dt_negative", "-i {in} -o {out} --dt -1e-3", "--dt"},
                      BadInput{"strain_step_nan", "-i {in} -o {out} --strain-step nan", "--strain-step"},
                      BadInput{"strain_step_too_large", "-i {in} -o {out} --strain-step 0.5", "--strain-step"},
                      BadInput{"rate_nan", "-i {in} -o {out} --rate nan", "--rate"},
                      BadInput{"tolerance_zero", "-i {in} -o {out} --tolerance 0", "--tolerance"},
                      BadInput{"threads_zero", "-i {in} -o {out} --threads 0", "--threads"},
                      BadInput{"missing_input_option", "-o {out}", "--input"},
                      BadInput{"missing_input_file", "-i {out}.missing -o {out}", "missing"},
                      BadInput{"rate_zero_without_temperature", "-i {in} -o {out} --rate 0 --steps 10",
                               "--temperature"},
                      BadInput{"frame_out_of_range", "-i {in} -o {out} --frame 4", "--frame"},
                      BadInput{"region_solve_after_negative", "-i {in} -o {out} --region-solve-after -1",
                               "--region-solve-after"},
                      BadInput{"region_solve_after_with_no_cluster_solves",
                               "-i {in} -o {out} --region-solve-after 10 --no-cluster-solves", "--region-solve-after"},
                      BadInput{"branch_velocities_unknown", "-i {in} -o {out} --branch-velocities reverse",
                               "--branch-velocities"},
                      BadInput{"branch_velocities_empty", "-i {in} -o {out} --branch-velocities ''",
                               "--branch-velocities"},
                      BadInput{"branch_velocities_with_a_packing", "-i {in} -o {out} --branch-velocities keep",
                               "--branch-velocities"},
                      BadInput{"activation_unknown", "-i {in} -o {out} --activation moreau", "--activation"},
                      BadInput{"activation_empty", "-i {in} -o {out} --activation ''", "--activation"},
                      BadInput{"unknown_option", "-i {in} -o {out} --shear 3", "--shear"}),
    bad_input_name);

TEST(GfShearBadInput, BadFiles) {
  ScratchDir dir("shear_bad_files");
  ScratchDir out_dir("shear_bad_files_out");
  const std::string text = dir / "text.h5";
  std::ofstream(text) << "not hdf5\n";
  const std::string truncated = dir / "truncated.h5";
  std::filesystem::copy_file(packing(), truncated);
  std::filesystem::resize_file(truncated, std::filesystem::file_size(packing()) / 2);
  const std::string no_grains = dir / "no_grains.h5";
  io::TrajectoryWriter(no_grains).close();
  const std::string incline = dir / "incline.h5";
  ASSERT_EQ(run_tool("gf-pack", "--incline --width 10 --height 5 --quiet -o " + incline).exit_code, 0);
  for (auto [path, expected] : {std::pair<std::string, std::string>{text, "text.h5"},
                                {truncated, "truncated.h5"},
                                {no_grains, "/particles/grains"},
                                {incline, "gf-incline"}}) {
    auto r = run_tool("gf-shear", "-i " + path + " -o " + (out_dir / "out.h5"));
    EXPECT_EQ(r.exit_code, 2) << path << ": " << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
    EXPECT_EQ(out_dir.entries(), 0) << "output left behind for " << path;
  }
}

// A gf-pack packing is a network of exactly touching pairs: Newton's restitution law on
// those simultaneous contacts injects energy in the first step of an "elastic" gas started
// from it. gf-shear records the kinetic energy before and after that step in /run and
// warns on stderr, also with --quiet (a warning is not progress).
TEST(GfShearFirstStep, EnergyInjectedFromAPackingIsReported) {
  ScratchDir dir("shear_first_step");
  const std::string dense = packed_once("shear_packing_075", "--grains 200 --packing-fraction 0.75 --seed 5");
  auto r = run_tool("gf-shear", "-i " + dense + " --rate 0 --temperature 1 --restitution 1 --steps 20 --quiet -o " +
                                    (dir / "dense.h5"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("gf-shear: warning: the first step"), std::string::npos) << r.err;
  const io::Parameters run = io::TrajectoryReader(dir / "dense.h5").attributes("/run");
  ASSERT_TRUE(run.has("first_step_kinetic_energy_before"));
  ASSERT_TRUE(run.has("first_step_kinetic_energy_after"));
  ASSERT_TRUE(run.has("first_step_kinetic_energy_ratio"));
  const double before = run.get_double("first_step_kinetic_energy_before");
  const double after = run.get_double("first_step_kinetic_energy_after");
  EXPECT_GT(before, 0);
  EXPECT_DOUBLE_EQ(run.get_double("first_step_kinetic_energy_ratio"), after / before);
  EXPECT_GT(after / before, 1.01);
}

// A dilute start (ν = 0.1, no touching pairs): the first step keeps the energy, no warning.
TEST(GfShearFirstStep, DiluteStartHasNoWarning) {
  ScratchDir dir("shear_first_step_dilute");
  const std::string dilute = packed_once("shear_packing_010", "--grains 200 --packing-fraction 0.1 --seed 5");
  auto r = run_tool("gf-shear", "-i " + dilute + " --rate 0 --temperature 1 --restitution 1 --steps 20 --quiet -o " +
                                    (dir / "dilute.h5"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
  const io::Parameters run = io::TrajectoryReader(dir / "dilute.h5").attributes("/run");
  ASSERT_TRUE(run.has("first_step_kinetic_energy_ratio"));
  EXPECT_NEAR(run.get_double("first_step_kinetic_energy_ratio"), 1, 1e-9);
}

// --no-cluster-solves: Gauss–Seidel alone. With friction it takes many more sweeps per step
// than the default solver to meet the same tolerance; without friction as well. The option
// is part of the run's signature (a resume may not change it).
TEST(GfShearSolver, NoClusterSolvesTakesMoreSweeps) {
  ScratchDir dir("shear_no_cluster_solves");
  const std::string dense = packed_once("shear_packing_076", "--grains 200 --packing-fraction 0.76 --seed 3");
  for (const std::string friction : {"0", "0.4"}) {
    SCOPED_TRACE(friction);
    double sweeps[2] = {0, 0};
    for (int plain = 0; plain < 2; ++plain) {
      const std::string out = dir / ("run_" + friction + "_" + std::to_string(plain) + ".h5");
      auto r = run_tool("gf-shear", "-i " + dense + " --rate 0.01 --strain-step 1e-3 --restitution 0 --friction " +
                                        friction + " --steps 200 --quiet" + (plain ? " --no-cluster-solves" : "") +
                                        " -o " + out);
      ASSERT_EQ(r.exit_code, 0) << r.err;
      const io::Parameters run = io::TrajectoryReader(out).attributes("/run");
      EXPECT_EQ(run.get_int("unconverged_steps"), 0);
      sweeps[plain] = run.get_double("mean_iterations");
    }
    std::cout << "gf-shear mu = " << friction << ": " << sweeps[0] << " sweeps per step, " << sweeps[1]
              << " with --no-cluster-solves\n";
    EXPECT_GT(sweeps[1], 3 * sweeps[0]);
  }
}

// --region-solve-after N: with friction, a step not done after N sweeps solves its stalled
// regions exactly; /run counts those solves. After 1 sweep they happen in many steps of a
// dense frictional start; with 0, never; without friction, never either.
TEST(GfShearSolver, RegionSolvesCountedInRun) {
  ScratchDir dir("shear_region_solves");
  const std::string dense = packed_once("shear_packing_076", "--grains 200 --packing-fraction 0.76 --seed 3");
  auto region_solves = [&](const std::string& friction, const std::string& after) {
    const std::string out = dir / ("run_" + friction + "_" + after + ".h5");
    auto r = run_tool("gf-shear", "-i " + dense + " --rate 0.01 --strain-step 1e-3 --restitution 0 --friction " +
                                      friction + " --steps 50 --quiet --region-solve-after " + after + " -o " + out);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    if (r.exit_code != 0) return std::int64_t(-1);
    const io::Parameters run = io::TrajectoryReader(out).attributes("/run");
    EXPECT_EQ(run.get_int("unconverged_steps"), 0);
    return run.get_int("region_solves");
  };
  const std::int64_t after_one = region_solves("0.4", "1");
  std::cout << "gf-shear mu = 0.4, --region-solve-after 1: " << after_one << " region solves in 50 steps\n";
  EXPECT_GE(after_one, 10);
  EXPECT_EQ(region_solves("0.4", "0"), 0);
  EXPECT_EQ(region_solves("0", "1"), 0);
}
