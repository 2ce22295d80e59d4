// Runs whose steps do not converge are not results: beyond --max-unconverged (a fraction
// of the run's steps) gf-shear and gf-incline stop with exit code 1 and leave no output,
// partial file or checkpoint; within it they finish (exit 0) with a warning.
#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <string>
#include <vector>

#include "io/trajectory.hpp"
#include "programs/run_tool.hpp"

using namespace granflow::testing;
namespace io = granflow::io;

namespace {

const std::string& dense() { return packed_once("unconverged_dense", "--grains 100 --packing-fraction 0.8 --seed 4"); }
const std::string& medium() {
  return packed_once("unconverged_medium", "--grains 100 --packing-fraction 0.7 --seed 4");
}

void expect_stopped(const ToolResult& r, const ScratchDir& dir) {
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("did not converge"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("raise --max-iterations or --max-unconverged"), std::string::npos) << r.err;
  EXPECT_EQ(dir.entries(), 0) << "output, partial file or checkpoint left behind";
}

}  // namespace

// μ = 10 on a dense packing: (nearly) no step converges within the sweep cap (given: the
// frictional default, 10^5 sweeps, would take a minute or more to reach it twice).
TEST(Unconverged, HighFrictionShearStopsWithExitOneAndLeavesNothing) {
  ScratchDir dir("unconverged_mu10");
  auto r = run_tool("gf-shear", "-i " + dense() + " -o " + (dir / "run.h5") +
                                    " --rate 0.01 --steps 100 --friction 10 --max-iterations 10000 -q");
  expect_stopped(r, dir);
}

TEST(Unconverged, OrdinaryRunFinishesWithExitZero) {
  ScratchDir dir("unconverged_ordinary");
  auto r = run_tool("gf-shear", "-i " + medium() + " -o " + (dir / "run.h5") + " --rate 0.01 --steps 200 -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(io::TrajectoryReader(dir / "run.h5").attributes("/run").get_int("unconverged_steps"), 0);
}

// One sweep per step leaves a known share U/N of the steps unconverged (measured with
// --max-unconverged 1, which never stops); a limit just above U/N lets the run finish with
// the same count, one just below stops it.
TEST(Unconverged, TheLimitIsAFractionOfTheRunsSteps) {
  ScratchDir dir("unconverged_limit");
  const std::string args = "-i " + medium() + " --rate 0.01 --steps 200 --max-iterations 1 -q";
  auto all = run_tool("gf-shear", args + " -o " + (dir / "all.h5") + " --max-unconverged 1");
  ASSERT_EQ(all.exit_code, 0) << all.err;
  const io::Parameters run = io::TrajectoryReader(dir / "all.h5").attributes("/run");
  const std::int64_t unconverged = run.get_int("unconverged_steps"), steps = run.get_int("steps");
  ASSERT_EQ(steps, 200);
  ASSERT_GT(unconverged, 1);
  ASSERT_LT(unconverged, steps);
  EXPECT_NE(all.err.find("warning: " + std::to_string(unconverged) + " of 200 steps did not converge"),
            std::string::npos)
      << all.err;
  std::filesystem::remove(dir / "all.h5");

  const double share = double(unconverged) / double(steps);
  auto inside = run_tool("gf-shear", args + " -o " + (dir / "inside.h5") + " --max-unconverged " +
                                         std::to_string(share + 0.5 / double(steps)));
  ASSERT_EQ(inside.exit_code, 0) << inside.err;
  EXPECT_EQ(io::TrajectoryReader(dir / "inside.h5").attributes("/run").get_int("unconverged_steps"), unconverged);
  std::filesystem::remove(dir / "inside.h5");

  auto outside = run_tool("gf-shear", args + " -o " + (dir / "outside.h5") + " --max-unconverged " +
                                          std::to_string(share - 0.5 / double(steps)));
  expect_stopped(outside, dir);
  EXPECT_NE(outside.err.find(std::to_string(unconverged) + " of 200 steps"), std::string::npos) << outside.err;
}

// /observables counts the unconverged steps since the previous row and their largest residual:
// at every --observe-every the rows add up to /run's count and their largest residual is
// /run's, and the rows of a run observed every 7 steps are sums and maxima of blocks of 7 rows
// of the same run observed every step (the same trajectory).
TEST(Unconverged, ObservablesCountThemSinceThePreviousRow) {
  ScratchDir dir("unconverged_rows");
  const std::string args = "-i " + medium() + " --rate 0.01 --steps 210 --max-iterations 1 --max-unconverged 1 -q";
  ASSERT_EQ(run_tool("gf-shear", args + " -o " + (dir / "one.h5")).exit_code, 0);
  ASSERT_EQ(run_tool("gf-shear", args + " -o " + (dir / "seven.h5") + " --observe-every 7").exit_code, 0);
  const io::TrajectoryReader one(dir / "one.h5"), seven(dir / "seven.h5");
  const std::vector<double> count1 = one.observable_scalar("unconverged_steps"),
                            residual1 = one.observable_scalar("unconverged_residual"),
                            solver1 = one.observable_scalar("solver_residual"),
                            count7 = seven.observable_scalar("unconverged_steps"),
                            residual7 = seven.observable_scalar("unconverged_residual");
  ASSERT_EQ(count1.size(), 210u);
  ASSERT_EQ(count7.size(), 30u);
  for (const io::TrajectoryReader* f : {&one, &seven}) {
    const io::Parameters run = f->attributes("/run");
    const std::vector<double> c = f->observable_scalar("unconverged_steps"),
                              r = f->observable_scalar("unconverged_residual");
    double total = 0, largest = 0;
    for (std::size_t k = 0; k < c.size(); ++k) {
      total += c[k];
      largest = std::max(largest, r[k]);
      EXPECT_EQ(c[k] > 0, r[k] > 0) << k;
    }
    ASSERT_GT(run.get_int("unconverged_steps"), 20);
    EXPECT_EQ(total, double(run.get_int("unconverged_steps")));
    EXPECT_EQ(largest, run.get_double("max_residual"));
  }
  for (std::size_t k = 0; k < 210; ++k) {
    // Observed every step, a row's residual is its step's when that step is at the cap.
    EXPECT_EQ(residual1[k], count1[k] > 0 ? solver1[k] : 0.0) << k;
    EXPECT_TRUE(count1[k] == 0 || solver1[k] >= 1e-10) << k;
  }
  for (std::size_t b = 0; b < 30; ++b) {
    double c = 0, r = 0;
    for (std::size_t k = 7 * b; k < 7 * b + 7; ++k) {
      c += count1[k];
      r = std::max(r, residual1[k]);
    }
    EXPECT_EQ(count7[b], c) << b;
    EXPECT_EQ(residual7[b], r) << b;
  }
}

TEST(Unconverged, InclineStopsBeyondTheLimitToo) {
  ScratchDir dir("unconverged_incline");
  const std::string& pack = packed_once("unconverged_incline_pack", "--incline --width 10 --height 5 --seed 3");
  auto r = run_tool("gf-incline", "-i " + pack + " -o " + (dir / "run.h5") +
                                      " --angle 20 --steps 3000 --profile-block 500 --max-iterations 1 "
                                      "--max-unconverged 0 -q");
  expect_stopped(r, dir);
}

TEST(Unconverged, TheLimitIsCheckedAndNotPartOfTheResumeSignature) {
  ScratchDir dir("unconverged_resume");
  const std::string args = "-i " + medium() + " -o " + (dir / "run.h5") + " --rate 0.01 --steps 5000 -q";
  if (interrupted_run("gf-shear", args, dir / "run.h5", dir / "log", 0, SIGTERM) != 1)
    GTEST_SKIP() << "the run finished before it could be interrupted";
  std::filesystem::remove(dir / "log");
  // Like --threads, the limit cannot change the steps computed, so a resume may change it.
  auto r = run_tool("gf-shear", args + " --resume --max-unconverged 0.5");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "run.h5"));
}

TEST(Unconverged, BadLimitsAreRefused) {
  for (const char* bad : {"-0.1", "1.5", "nan", "x"}) {
    ScratchDir dir("unconverged_bad");
    auto r =
        run_tool("gf-shear", "-i " + medium() + " -o " + (dir / "run.h5") + " --steps 10 --max-unconverged " + bad);
    EXPECT_EQ(r.exit_code, 2) << bad << ": " << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("--max-unconverged"), std::string::npos) << r.err;
    EXPECT_EQ(dir.entries(), 0) << bad;
  }
}

// The count of a resumed run includes the steps before the interruption: a resume whose
// limit the count already exceeds stops at once, and removes the checkpoint and the
// partial output of the interrupted session too.
TEST(Unconverged, AResumeCountsTheStepsBeforeTheInterruption) {
  ScratchDir dir("unconverged_resume_count");
  const std::string args =
      "-i " + medium() + " -o " + (dir / "run.h5") + " --rate 0.01 --steps 5000 --max-iterations 1 -q";
  if (interrupted_run("gf-shear", args + " --max-unconverged 1", dir / "run.h5", dir / "log", 0, SIGTERM) != 1)
    GTEST_SKIP() << "the run finished before it could be interrupted";
  std::filesystem::remove(dir / "log");
  ASSERT_TRUE(std::filesystem::exists(dir / ".run.h5.checkpoint"));
  auto r = run_tool("gf-shear", args + " --resume --max-unconverged 0");
  expect_stopped(r, dir);
}
