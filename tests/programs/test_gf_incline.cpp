// gf-incline as a user runs it: checkpoint/resume reproduces the uninterrupted run bit
// for bit (profiles included), a grain leaving the layer fails the run (exit 1, no
// output), and bad input fails with exit 2, one line and no output.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "io/trajectory.hpp"
#include "programs/run_tool.hpp"

using namespace granflow::testing;
namespace io = granflow::io;

namespace {
// One incline start shared by the tests of this file.
const std::string& packing() { return packed_once("incline_packing", "--incline --width 10 --height 5 --seed 3"); }

const std::string kRun = "--angle 20 --profile-block 500 --frame-every 500 --quiet";

// Datasets of /profiles and /profiles/blocks that must come out bit for bit the same.
const char* const kProfileArrays[] = {"/profiles/y",
                                      "/profiles/packing_fraction",
                                      "/profiles/velocity_x",
                                      "/profiles/temperature",
                                      "/profiles/stress_yy",
                                      "/profiles/shear_stress",
                                      "/profiles/inertial",
                                      "/profiles/blocks/index",
                                      "/profiles/blocks/samples",
                                      "/profiles/blocks/flow_rate",
                                      "/profiles/blocks/contact_yy",
                                      "/profiles/blocks/fluctuation_xx",
                                      "/profiles/blocks/mass_above"};
}  // namespace

TEST(GfInclineResume, InterruptedAndResumedEqualsUninterrupted) {
  ScratchDir dir("incline_resume");
  const std::string steps = " --steps 30000 ";
  auto ref_run = run_tool("gf-incline", "-i " + packing() + steps + kRun + " -o " + (dir / "ref.h5"));
  ASSERT_EQ(ref_run.exit_code, 0) << ref_run.err;

  const std::string args = "-i " + packing() + steps + kRun + " -o " + (dir / "cut.h5");
  const int code = interrupted_run("gf-incline", args, dir / "cut.h5", dir / "log1", 100);
  if (code == 0) GTEST_SKIP() << "the run finished before it could be interrupted";
  ASSERT_EQ(code, 1);
  EXPECT_FALSE(std::filesystem::exists(dir / "cut.h5")) << "an interrupted run left a finished-looking output";
  ASSERT_TRUE(std::filesystem::exists(dir / ".cut.h5.checkpoint"));
  // The checkpoint must carry profile blocks, or their restoration goes untested.
  if (io::TrajectoryReader(dir / ".cut.h5.checkpoint").array("/profile_blocks/index").empty())
    GTEST_SKIP() << "interrupted before the first profile sample";

  auto resumed = run_tool("gf-incline", args + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_FALSE(std::filesystem::exists(dir / ".cut.h5.checkpoint"));
  EXPECT_TRUE(partials_of(dir.path / "cut.h5").empty());

  io::TrajectoryReader ref(dir / "ref.h5"), cut(dir / "cut.h5");
  ASSERT_EQ(ref.frame_count(), cut.frame_count());
  EXPECT_EQ(ref.frame_times(), cut.frame_times());
  for (std::size_t k = 0; k < ref.frame_count(); ++k) {
    const io::Frame a = ref.frame(k), b = cut.frame(k);
    ASSERT_EQ(a.position, b.position) << "frame " << k;
    ASSERT_EQ(a.velocity, b.velocity) << "frame " << k;
    ASSERT_EQ(a.angular_velocity, b.angular_velocity) << "frame " << k;
    ASSERT_EQ(a.contacts.normal_force, b.contacts.normal_force) << "frame " << k;
  }
  for (const char* name : {"flow_rate", "kinetic_energy", "height", "solver_iterations"}) {
    EXPECT_EQ(ref.observable_scalar(name), cut.observable_scalar(name)) << name;
    EXPECT_EQ(ref.observable_step(name), cut.observable_step(name)) << name;
    EXPECT_EQ(ref.observable_time(name), cut.observable_time(name)) << name;  // in τ after the resume too
  }
  for (const char* name : kProfileArrays) {
    std::vector<std::size_t> shape_ref, shape_cut;
    const auto a = ref.array(name, &shape_ref), b = cut.array(name, &shape_cut);
    EXPECT_EQ(shape_ref, shape_cut) << name;
    // Bit for bit, NaN included.
    ASSERT_EQ(a.size(), b.size()) << name;
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0) << name;
  }
  EXPECT_EQ(ref.attributes("/profiles").items(), cut.attributes("/profiles").items());
}

TEST(GfInclineProfiles, LayoutAndUnits) {
  ScratchDir dir("incline_layout");
  auto r = run_tool("gf-incline", "-i " + packing() + " --steps 2000 " + kRun + " -o " + (dir / "out.h5"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  io::TrajectoryReader out(dir / "out.h5");
  std::vector<std::size_t> shape;
  const auto y = out.array("/profiles/y", &shape);
  ASSERT_EQ(shape.size(), 1u);
  for (const char* name : {"packing_fraction", "velocity_x", "temperature", "pressure", "shear_stress", "stress_xx",
                           "stress_yy", "shear_rate", "s_over_p", "inertial", "mT_over_pR2", "weight_above"}) {
    std::vector<std::size_t> s;
    out.array(std::string("/profiles/") + name, &s);
    EXPECT_EQ(s, shape) << name;
  }
  const auto blocks = out.array("/profiles/blocks/contact_yy", &shape);
  EXPECT_EQ(shape[0], 4u);  // 2000 steps in blocks of 500
  const io::Parameters a = out.attributes("/profiles");
  for (const char* name : {"steady", "steady_from_time", "time_unit", "tau", "bin", "blocks_averaged"})
    EXPECT_TRUE(a.has(name)) << name;
  EXPECT_EQ(out.observable_step("flow_rate").front(), 10);  // --observe-every defaults to 10
}

// ---- a branch: another angle and friction from the last frame of a run ----

TEST(GfInclineBranch, NewAngleAndFrictionFromTheLastFrameRecordsTheParent) {
  ScratchDir dir("incline_branch");
  const std::string parent = dir / "parent.h5", branch = dir / "branch.h5";
  auto r = run_tool("gf-incline", "-i " + packing() + " --steps 1000 " + kRun + " -o " + parent);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_tool("gf-incline", "-i " + parent +
                                 " --frame -1 --angle 27 --friction 0.4 --steps 500 --profile-block 500 "
                                 "--frame-every 500 --quiet -o " +
                                 branch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  io::TrajectoryReader p(parent), b(branch);
  const io::Frame last = p.frame(p.frame_count() - 1), first = b.frame(0);
  EXPECT_EQ(last.step, 1000);
  EXPECT_EQ(first.position, last.position);  // the branch starts where the parent stopped,
  EXPECT_EQ(first.velocity, last.velocity);  // velocities kept
  const io::Parameters a = b.parameters();
  EXPECT_EQ(a.get_double("angle"), 27);
  EXPECT_EQ(a.get_double("friction"), 0.4);
  EXPECT_EQ(a.get_string("input"), parent);
  EXPECT_EQ(a.get_int("input_frame"), std::int64_t(p.frame_count() - 1));
  EXPECT_EQ(a.get_int("input_step"), 1000);
  EXPECT_DOUBLE_EQ(a.get_double("input_time"), last.time);
  EXPECT_EQ(a.get_string("input_time_unit"), "tau");
  EXPECT_NEAR(last.time, 1000 * 2e-3, 1e-9);  // the parent's default --time-step, in τ
  EXPECT_EQ(a.get_string("parent_program"), "gf-incline");
  EXPECT_EQ(a.get_double("parent_angle"), 20);
  EXPECT_EQ(a.get_double("parent_friction"), 0);
  EXPECT_EQ(a.get_string("parent_input"), packing());
  // A packing as input: frame 0, no parent run.
  const io::Parameters pa = p.parameters();
  EXPECT_EQ(pa.get_int("input_frame"), 0);
  EXPECT_EQ(pa.get_int("input_step"), 0);
  EXPECT_FALSE(pa.has("parent_angle"));
}

// ---- a grain leaving the layer: exit 1, a message naming it, no output ----

namespace {
// The shared packing with its highest grain launched upwards at vy; or, with a hole,
// base grain 2 replaced by a small mobile grain thrown down (vy < 0) through the gap it
// leaves. Writes it to path and returns the launched grain's index.
std::string modified_packing(const std::string& path, double vy, bool hole) {
  io::TrajectoryReader in(packing());
  io::Frame f = in.frame(0);
  io::GrainProperties g = in.grains();
  std::size_t grain = 0;
  if (hole) {
    const double x = f.position[2].x();
    f.position[2] = {x, 0.6};
    g.radius[2] = 0.25;
    g.mass[2] = M_PI * 0.25 * 0.25;
    g.fixed[2] = 0;
    grain = 2;
  } else {
    for (std::size_t i = 1; i < f.position.size(); ++i)
      if (f.position[i].y() > f.position[grain].y()) grain = i;
  }
  f.velocity[grain] = {0.0, vy};
  io::write_packing(path, f, g, io::Parameters{});
  return std::to_string(grain);
}
}  // namespace

TEST(GfInclineEscape, GrainThroughTheFreeSurfaceFailsTheRun) {
  ScratchDir dir("incline_escape_up");
  ScratchDir out("incline_escape_up_out");
  const std::string grain = modified_packing(dir / "up.h5", 100, false);
  auto r = run_tool("gf-incline", "-i " + (dir / "up.h5") + " --steps 2000 " + kRun + " -o " + (out / "out.h5"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("grain " + grain + " left through the free surface at step "), std::string::npos) << r.err;
  EXPECT_EQ(out.entries(), 0) << "output, partial file or checkpoint left behind";
}

TEST(GfInclineEscape, GrainThroughTheBaseFailsTheRun) {
  ScratchDir dir("incline_escape_down");
  ScratchDir out("incline_escape_down_out");
  const std::string grain = modified_packing(dir / "hole.h5", -50, true);
  auto r = run_tool("gf-incline", "-i " + (dir / "hole.h5") + " --steps 2000 " + kRun + " -o " + (out / "out.h5"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("grain " + grain + " crossed the base at step "), std::string::npos) << r.err;
  EXPECT_EQ(out.entries(), 0) << "output, partial file or checkpoint left behind";
}

// ---- bad input: exit 2, one line naming the problem, no output file left ----

class GfInclineBadInput : public ::testing::TestWithParam<BadInput> {};

TEST_P(GfInclineBadInput, FailsWithExitTwoOneLineNoOutput) {
  expect_refused("gf-incline", GetParam(), {{"{in}", packing()}});  // {in}: a valid incline packing
}

INSTANTIATE_TEST_SUITE_P(
    Cases, GfInclineBadInput,
    ::testing::Values(
        BadInput{"angle_missing", "-i {in} -o {out}", "--angle"},
        BadInput{"activation_unknown", "-i {in} -o {out} --angle 20 --activation moreau", "--activation"},
        BadInput{"angle_zero", "-i {in} -o {out} --angle 0", "--angle"},
        BadInput{"angle_ninety", "-i {in} -o {out} --angle 90", "--angle"},
        BadInput{"angle_negative", "-i {in} -o {out} --angle -5", "--angle"},
        BadInput{"angle_nan", "-i {in} -o {out} --angle nan", "--angle"},
        BadInput{"gravity_zero", "-i {in} -o {out} --angle 12 --gravity 0", "--gravity"},
        BadInput{"gravity_negative", "-i {in} -o {out} --angle 12 --gravity -1", "--gravity"},
        BadInput{"restitution_above_one", "-i {in} -o {out} --angle 12 --restitution 1.5", "--restitution"},
        BadInput{"restitution_negative", "-i {in} -o {out} --angle 12 --restitution -0.1", "--restitution"},
        BadInput{"friction_negative", "-i {in} -o {out} --angle 12 --friction -1", "--friction"},
        BadInput{"time_step_zero", "-i {in} -o {out} --angle 12 --time-step 0", "--time-step"},
        BadInput{"dt_negative", "-i {in} -o {out} --angle 12 --dt -1e-3", "--dt"},
        BadInput{"profile_bin_zero", "-i {in} -o {out} --angle 12 --profile-bin 0", "--profile-bin"},
        BadInput{"block_longer_than_run", "-i {in} -o {out} --angle 12 --steps 100 --profile-block 500",
                 "--profile-block"},
        BadInput{"from_time_after_run", "-i {in} -o {out} --angle 12 --time 100 --from-time 200", "--from-time"},
        BadInput{"frame_out_of_range", "-i {in} -o {out} --angle 12 --frame 3", "--frame"},
        BadInput{"missing_input_option", "-o {out} --angle 12", "--input"},
        BadInput{"missing_input_file", "-i {out}.missing -o {out} --angle 12", "missing"}),
    bad_input_name);

TEST(GfInclineBadInput, BadFiles) {
  ScratchDir dir("incline_bad_files");
  ScratchDir out_dir("incline_bad_files_out");
  const std::string text = dir / "text.h5";
  std::ofstream(text) << "not hdf5\n";
  const std::string biperiodic = dir / "biperiodic.h5";
  ASSERT_EQ(run_tool("gf-pack", "--grains 50 --packing-fraction 0.5 --quiet -o " + biperiodic).exit_code, 0);
  for (auto [path, expected] :
       {std::pair<std::string, std::string>{text, "text.h5"}, {biperiodic, "biperiodic packing"}}) {
    auto r = run_tool("gf-incline", "-i " + path + " --angle 12 -o " + (out_dir / "out.h5"));
    EXPECT_EQ(r.exit_code, 2) << path << ": " << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
    EXPECT_EQ(out_dir.entries(), 0) << "output left behind for " << path;
  }
}

// ---- one time unit: the interface, the files and stderr all speak τ ----

namespace {
// The `unit` attribute of a dataset ("" if absent).
std::string unit_of(const io::TrajectoryReader& file, const std::string& dataset) {
  const io::Parameters a = file.attributes(dataset);
  return a.has("unit") ? a.get_string("unit") : "";
}

// Every H5MD time dataset of a trajectory: the frame elements' and the observables'.
std::vector<std::string> time_datasets(const io::TrajectoryReader& file) {
  std::vector<std::string> paths;
  for (const char* element :
       {"/particles/grains/position", "/particles/grains/velocity", "/particles/grains/orientation",
        "/particles/grains/angular_velocity", "/particles/grains/box/edges"})
    paths.push_back(std::string(element) + "/time");
  for (const std::string& name : file.observable_names()) paths.push_back("/observables/" + name + "/time");
  return paths;
}

// Where stderr says the averaged part starts: the number after "t = " in "steady from
// t = X τ" or in the warning "... still drifts after t = X τ" (NaN if absent).
double steady_on_stderr(const std::string& err) {
  const std::string key = "t = ";
  const auto at = err.find(key);
  return at == std::string::npos ? std::nan("") : std::stod(err.substr(at + key.size()));
}
}  // namespace

TEST(GfInclineTime, FilesAndStderrInTauLikeTheOptions) {
  ScratchDir dir("incline_time");
  // 2000 steps of 2e-3 τ: --time 4 ends at 4 τ; frames every 1 τ; profiles from 1 τ on.
  auto r = run_tool("gf-incline", "-i " + packing() +
                                      " --angle 20 --time 4 --time-step 2e-3 --profile-block 500 --frame-every 500"
                                      " --from-time 1 -o " +
                                      (dir / "out.h5"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  io::TrajectoryReader out(dir / "out.h5");
  const double frame_interval = 500 * 2e-3;
  const std::vector<double> times = out.frame_times();
  ASSERT_EQ(times.size(), 5u);
  EXPECT_NEAR(times.back(), 4.0, 1e-9) << "the last frame is at the end of --time 4";
  EXPECT_NEAR(times[1], frame_interval, 1e-9);
  EXPECT_NEAR(out.observable_time("flow_rate").back(), 4.0, 1e-9);
  EXPECT_NEAR(out.array("/profiles/blocks/time_end").back(), 4.0, 1e-9);

  const io::Parameters p = out.attributes("/profiles");
  EXPECT_EQ(p.get_string("time_unit"), "tau");
  EXPECT_FALSE(p.has("steady_from_tau")) << "one name per quantity: steady_from_time";
  const double from = p.get_double("steady_from_time");
  EXPECT_GE(from, 1.0 - 1e-9);
  EXPECT_LE(from, 1.0 + frame_interval);
  EXPECT_NEAR(steady_on_stderr(r.err), from, 1e-3 * from) << r.err;

  for (const std::string& path : time_datasets(out)) EXPECT_EQ(unit_of(out, path), "tau") << path;
  EXPECT_EQ(out.attributes("/profiles/blocks/time_begin").get_string("units"), "tau");
  EXPECT_EQ(out.attributes("/profiles/blocks/time_end").get_string("units"), "tau");
  EXPECT_EQ(out.attributes("/profiles/blocks/time_begin").get_string("unit"), "tau");
  EXPECT_EQ(out.attributes("/profiles/blocks/time_end").get_string("unit"), "tau");
}

TEST(GfInclineTime, GfShearAndGfPackLabelCodeUnits) {
  ScratchDir dir("incline_time_code");
  const std::string pack = dir / "pack.h5", run = dir / "run.h5";
  ASSERT_EQ(run_tool("gf-pack", "--grains 50 --packing-fraction 0.5 --quiet -o " + pack).exit_code, 0);
  auto r = run_tool("gf-shear", "-i " + pack + " --strain 0.02 --strain-step 1e-3 --quiet -o " + run);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const std::string& path : {pack, run}) {
    io::TrajectoryReader file(path);
    for (const std::string& dataset : time_datasets(file)) EXPECT_EQ(unit_of(file, dataset), "T") << dataset;
    EXPECT_EQ(unit_of(file, "/lees_edwards/offset/time"), "T") << path;  // boxes periodic in y only
  }
}

// ---- defaults that fit the run ----

TEST(GfInclineDefaults, ShortRunWithoutProfileBlockHasProfiles) {
  ScratchDir dir("incline_short");
  auto r = run_tool("gf-incline", "-i " + packing() + " --angle 20 --steps 1000 --quiet -o " + (dir / "out.h5"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  io::TrajectoryReader out(dir / "out.h5");
  const io::Parameters p = out.attributes("/profiles");
  const std::int64_t block = p.get_int("block_steps");
  EXPECT_EQ(block, 50) << "automatic: min(5000, steps/20)";
  EXPECT_EQ(out.array("/profiles/blocks/index").size(), 20u);
  EXPECT_FALSE(out.array("/profiles/velocity_x").empty());
  EXPECT_EQ(out.parameters().get_int("profile-block"), block) << "/parameters records the block length used";
}

class GfInclineBadProfileBlock : public ::testing::TestWithParam<BadInput> {};

TEST_P(GfInclineBadProfileBlock, FailsWithExitTwoOneLineNoOutput) {
  expect_refused("gf-incline", GetParam(), {{"{in}", packing()}});
}

INSTANTIATE_TEST_SUITE_P(Cases, GfInclineBadProfileBlock,
                         ::testing::Values(BadInput{"block_negative",
                                                    "-i {in} -o {out} --angle 12 --steps 100 --profile-block -1",
                                                    "--profile-block"}),
                         bad_input_name);

// ---- an angle typed in radians ----

TEST(GfInclineAngle, BelowOneDegreeWarnsOnceAndRuns) {
  ScratchDir dir("incline_angle");
  auto r = run_tool("gf-incline", "-i " + packing() + " --angle 0.35 --steps 200 --quiet -o " + (dir / "small.h5"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "small.h5"));
  int warnings = 0;
  std::istringstream lines(r.err);
  for (std::string line; std::getline(lines, line);)
    if (line.find("--angle") != std::string::npos) {
      ++warnings;
      EXPECT_NE(line.find("gf-incline: warning:"), std::string::npos) << line;
      EXPECT_NE(line.find("0.35"), std::string::npos) << line;
      EXPECT_NE(line.find("degrees"), std::string::npos) << line;
      EXPECT_NE(line.find("20.1"), std::string::npos) << line;  // 0.35 rad in degrees
    }
  EXPECT_EQ(warnings, 1) << r.err;

  r = run_tool("gf-incline", "-i " + packing() + " --angle 20 --steps 200 --quiet -o " + (dir / "normal.h5"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("--angle"), std::string::npos) << r.err;
}
