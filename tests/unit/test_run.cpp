// lib/run directly: a checkpoint holds every field a resume needs (read back exactly, and
// an engine rebuilt from it continues bit for bit), the run signature holds exactly the
// options that change a trajectory, a resume is refused when the options or the partial
// output do not match, and start_or_resume + run_steps interrupted and resumed give the
// uninterrupted output. The programs' own resume (signals, real processes) is tested in
// tests/programs.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/cli.hpp"
#include "core/error.hpp"
#include "core/output_file.hpp"
#include "core/sha256.hpp"
#include "dynamics/engine.hpp"
#include "io/trajectory.hpp"
#include "packing/packing.hpp"
#include "run/checkpoint.hpp"
#include "run/driver.hpp"
#include "run/frames.hpp"
#include "run/runner.hpp"
#include "unit/expect_frame.hpp"

namespace granflow {
namespace {

namespace fs = std::filesystem;

// A fresh directory under the system's temporary one, removed at the end of the test.
struct Scratch {
  fs::path dir;
  explicit Scratch(const std::string& name) : dir(fs::temp_directory_path() / ("granflow_test_run_" + name)) {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  ~Scratch() { fs::remove_all(dir); }
  std::string operator/(const std::string& file) const { return (dir / file).string(); }
};

// A small sheared packing with friction: contacts with tangential forces and ages > 1.
struct Start {
  GrainState grains;
  Box box;
};
Start sheared_start(double packing_fraction = 0.78) {
  PackingParams params;
  params.grains = 120;
  params.packing_fraction = packing_fraction;
  params.seed = 4;
  const Packing packing = make_biperiodic_packing(params);
  Start s{make_grains(packing.position, packing.radius), packing.box};
  add_affine_flow(s.grains, s.box, 0.5);
  return s;
}
const Material kMaterial{0.5, 0.2, 0.4};

// The run options of gf-shear and gf-incline on a small program's command line.
CommandLine run_cli(const std::string& output, std::vector<std::string> args) {
  CommandLine cli("gf-test", "[options]", "lib/run test");
  cli.text_option("output", 'o', "FILE", "trajectory to write");
  cli.integer_option("steps", 0, "N", "steps", "60");
  add_contact_options(cli);
  add_run_options(cli, "1");
  args.insert(args.begin(), {"gf-test", "-o", output, "--quiet"});
  std::vector<const char*> argv;
  for (const auto& a : args) argv.push_back(a.c_str());
  EXPECT_TRUE(cli.parse(int(argv.size()), argv.data()));
  return cli;
}

using test_support::expect_same_contacts;
using test_support::expect_same_grains;

TEST(RunCheckpoint, PathIsAHiddenFileBesideTheOutput) {
  EXPECT_EQ(checkpoint_path("runs/a/shear.h5"), "runs/a/.shear.h5.checkpoint");
  EXPECT_EQ(checkpoint_path("shear.h5"), ".shear.h5.checkpoint");
}

// Every field written is read back exactly, the caller's extra state included, and an
// engine rebuilt from the checkpoint steps on exactly as the one that wrote it.
TEST(RunCheckpoint, RoundTripKeepsEveryFieldAndTheTrajectory) {
  Scratch dir("round_trip");
  const Start s = sheared_start();
  Engine engine(s.grains, s.box, 0.5, kMaterial, SolverSettings{}, 1e-3);
  for (int k = 0; k < 40; ++k) engine.step();
  ASSERT_GT(engine.contacts().size(), 20u);
  bool long_lived = false, tangential = false;
  for (std::size_t c = 0; c < engine.contacts().size(); ++c) {
    long_lived = long_lived || engine.contacts().age[c] > 1;
    tangential = tangential || engine.contacts().tangential_force[c] != 0;
  }
  ASSERT_TRUE(long_lived && tangential) << "the start does not exercise the warm start";

  RunStats stats;
  stats.frames_written = 7;
  stats.unconverged_steps = 3;
  stats.region_solves = 5;
  stats.iterations = 123456789012;
  stats.contact_updates = 987654321098;
  stats.max_residual = 1.25e-11;
  stats.row_unconverged_steps = 2;
  stats.row_unconverged_residual = 3.5e-9;
  stats.wall_seconds = 3.75;
  const std::string signature = "friction=0.4;output=x.h5;rate=0.5;";
  const std::string path = dir / "run.checkpoint";
  io::Parameters extra;
  extra.set("answer", std::int64_t(42));
  write_checkpoint(path, engine, stats, signature,
                   [&](io::TrajectoryWriter& w) { w.write_attributes("/extra", extra); });
  EXPECT_FALSE(fs::exists(path + ".new"));

  const Checkpoint c = read_checkpoint(path);
  EXPECT_EQ(c.step, 40);
  EXPECT_EQ(c.signature, signature);
  EXPECT_EQ(c.stats.frames_written, stats.frames_written);
  EXPECT_EQ(c.stats.unconverged_steps, stats.unconverged_steps);
  EXPECT_EQ(c.stats.region_solves, stats.region_solves);
  EXPECT_EQ(c.stats.iterations, stats.iterations);
  EXPECT_EQ(c.stats.contact_updates, stats.contact_updates);
  EXPECT_EQ(c.stats.max_residual, stats.max_residual);
  EXPECT_EQ(c.stats.row_unconverged_steps, stats.row_unconverged_steps);
  EXPECT_EQ(c.stats.row_unconverged_residual, stats.row_unconverged_residual);
  EXPECT_EQ(c.stats.wall_seconds, stats.wall_seconds);
  EXPECT_EQ(c.frame.step, 40);
  EXPECT_EQ(c.frame.time, engine.time());
  const io::Frame now = frame_of(engine, engine.step_count(), engine.time());
  expect_same_grains(c.frame, now);
  ASSERT_TRUE(c.frame.has_contacts);
  expect_same_contacts(c.frame.contacts, engine.contacts());
  const io::GrainProperties props = properties_of(engine.state());
  EXPECT_EQ(c.grains.radius, props.radius);
  EXPECT_EQ(c.grains.mass, props.mass);
  EXPECT_EQ(c.grains.fixed, props.fixed);
  EXPECT_EQ(io::TrajectoryReader(path).attributes("/extra").get_int("answer"), 42);
  EXPECT_EQ(io::TrajectoryReader(path).lees_edwards_rate(), 0.5);

  // A checkpoint of an older version, without the unconverged steps since the last row, is
  // refused rather than resumed with a wrong count.
  {
    const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    ASSERT_GE(H5Adelete_by_name(file, "/checkpoint", "row_unconverged_steps", H5P_DEFAULT), 0);
    H5Fclose(file);
    try {
      read_checkpoint(path);
      ADD_FAILURE() << "an older checkpoint was read";
    } catch (const UsageError& e) {
      EXPECT_NE(std::string(e.what()).find("older version"), std::string::npos) << e.what();
    }
  }

  Engine resumed(grains_of(c.frame, c.grains), c.frame.box, 0.5, kMaterial, SolverSettings{}, 1e-3);
  resumed.restore(c.step, memory_of(c.frame.contacts));
  for (int k = 0; k < 30; ++k) {
    engine.step();
    resumed.step();
  }
  EXPECT_EQ(resumed.step_count(), engine.step_count());
  expect_same_grains(frame_of(resumed, 70, resumed.time()), frame_of(engine, 70, engine.time()));
  expect_same_contacts(resumed.contacts(), engine.contacts());
}

TEST(RunCheckpoint, ATrajectoryIsNotACheckpoint) {
  Scratch dir("not_checkpoint");
  const Start s = sheared_start();
  Engine engine(s.grains, s.box, 0.5, kMaterial, SolverSettings{}, 1e-3);
  {
    io::TrajectoryWriter w(dir / "traj.h5");
    w.write_grains(properties_of(engine.state()), engine.box());
    w.append_frame(frame_of(engine, 0, 0.0));
  }
  EXPECT_THROW(read_checkpoint(dir / "traj.h5"), UsageError);
  EXPECT_THROW(read_checkpoint(dir / "missing.h5"), UsageError);
}

// What makes a resume compatible: every option that can change the trajectory, given or
// defaulted; not --resume, --checkpoint-every or --threads (the trajectory is the same
// for any thread count).
TEST(RunSignature, HoldsTheOptionsThatChangeTheTrajectory) {
  const std::string base = run_signature(run_cli("a.h5", {}));
  EXPECT_NE(base.find("friction=0;"), std::string::npos) << base;
  EXPECT_NE(base.find("steps=60;"), std::string::npos) << base;
  EXPECT_NE(base.find("output=a.h5;"), std::string::npos) << base;
  EXPECT_EQ(base.find("threads"), std::string::npos) << base;
  EXPECT_EQ(base.find("resume"), std::string::npos) << base;
  EXPECT_EQ(base.find("checkpoint-every"), std::string::npos) << base;
  EXPECT_EQ(base.find("quiet"), std::string::npos) << base;

  // A default given explicitly is the same run.
  EXPECT_EQ(run_signature(run_cli("a.h5", {"--friction", "0"})), base);
  EXPECT_EQ(run_signature(run_cli("a.h5", {"--threads", "2", "--checkpoint-every", "5", "--resume"})), base);
  for (const std::vector<std::string>& changed : {std::vector<std::string>{"--friction", "0.1"},
                                                  {"--restitution", "0.9"},
                                                  {"--steps", "61"},
                                                  {"--tolerance", "1e-9"},
                                                  {"--alert-distance", "0.05"},
                                                  {"--frame-every", "3"},
                                                  {"--observe-every", "2"}}) {
    SCOPED_TRACE(changed[0]);
    EXPECT_NE(run_signature(run_cli("a.h5", changed)), base);
  }
  EXPECT_NE(run_signature(run_cli("b.h5", {})), base);
}

// A run of `steps` steps from sheared_start() through start_or_resume and run_resumable,
// as gf-shear does (`input` stands for its input file); with `stop_at` > 0 it stops there
// as a signal would leave it (partial output and checkpoint kept) and returns false.
bool run(const CommandLine& cli, const std::string& input, std::int64_t steps, std::int64_t stop_at = 0) {
  const Start s = sheared_start();
  RunPlan plan = run_plan(cli);
  set_length(plan, steps);
  const RunStart start{
      .grains = s.grains,
      .box = s.box,
      .contacts = {},
      .rate = 0.5,
      .gravity = Vec2::Zero(),
      .material = material_option(cli),
      .settings = solver_option(cli),
      .dt = 1e-3,
      .input_path = input,
      .add_parameters = [](io::Parameters& p) { p.set("extra_parameter", 1.5); },
      .restore = {},
  };
  // The program's observables: here the first grain's height.
  const Observer observe = [](const Engine& e, io::TrajectoryWriter& w) {
    w.append_observable("height", e.step_count(), e.time(), e.state().position[0].y());
  };
  OutputFile out(cli.text("output"), /*resumable=*/true);
  StartedRun r = start_or_resume(cli, plan, out, start);
  if (stop_at > 0) {
    RunPlan first = plan;
    first.total_steps = stop_at;
    const RunStats stats = run_resumable(r.engine, r.writer, out, first, r.stats, observe);
    r.writer.flush();
    write_checkpoint(plan.checkpoint_path, r.engine, stats, plan.signature, {}, plan.output_path);
    out.keep_partial();
    r.writer.close_unfinished();
    return false;
  }
  const RunStats stats = run_resumable(r.engine, r.writer, out, plan, r.stats, observe);
  finish_run(cli, r.writer, out, r.engine, stats, plan);
  return true;
}

TEST(RunResume, InterruptedAndResumedEqualsUninterrupted) {
  Scratch dir("resume");
  const std::vector<std::string> options{"--friction", "0.4", "--frame-every", "10", "--tolerance", "1e-8"};
  const std::string input = dir / "input";
  std::ofstream(input) << "the start state";
  ASSERT_TRUE(run(run_cli(dir / "ref.h5", options), input, 60));

  EXPECT_FALSE(run(run_cli(dir / "cut.h5", options), input, 60, 30));
  EXPECT_FALSE(fs::exists(dir / "cut.h5"));
  ASSERT_EQ(output_temporaries(dir / "cut.h5").size(), 1u);
  ASSERT_TRUE(fs::exists(dir / ".cut.h5.checkpoint"));
  std::vector<std::string> resume = options;
  resume.insert(resume.end(), {"--resume", "--threads", "2"});
  ASSERT_TRUE(run(run_cli(dir / "cut.h5", resume), input, 60));
  EXPECT_TRUE(output_temporaries(dir / "cut.h5").empty());
  EXPECT_FALSE(fs::exists(dir / ".cut.h5.checkpoint"));

  io::TrajectoryReader ref(dir / "ref.h5"), cut(dir / "cut.h5");
  EXPECT_EQ(cut.parameters().get_double("extra_parameter"), 1.5);
  EXPECT_EQ(cut.parameters().get_string("input"), input);
  EXPECT_EQ(cut.parameters().get_string("input_sha256"), ref.parameters().get_string("input_sha256"));
  ASSERT_EQ(ref.frame_count(), 7u);
  for (std::size_t k : {3, 6}) ASSERT_GT(ref.frame(k).contacts.size(), 10u) << "frame " << k << ": too few contacts";
  ASSERT_EQ(cut.frame_count(), ref.frame_count());
  for (std::size_t k = 0; k < ref.frame_count(); ++k) {
    SCOPED_TRACE(k);
    const io::Frame a = ref.frame(k), b = cut.frame(k);
    EXPECT_EQ(a.step, b.step);
    expect_same_grains(a, b);
    expect_same_contacts(a.contacts, b.contacts);
  }
  for (const char* name : {"height", "contacts", "solver_iterations", "solver_residual", "max_overlap",
                           "unconverged_steps", "unconverged_residual"}) {
    EXPECT_EQ(ref.observable_step(name), cut.observable_step(name)) << name;
    EXPECT_EQ(ref.observable_scalar(name), cut.observable_scalar(name)) << name;
  }
  EXPECT_EQ(ref.attributes("/run").get_int("steps"), cut.attributes("/run").get_int("steps"));
  EXPECT_EQ(ref.attributes("/run").get_int("unconverged_steps"), cut.attributes("/run").get_int("unconverged_steps"));
  EXPECT_EQ(ref.attributes("/run").get_int("region_solves"), cut.attributes("/run").get_int("region_solves"));
  EXPECT_EQ(ref.attributes("/run").get_double("max_residual"), cut.attributes("/run").get_double("max_residual"));
  EXPECT_EQ(ref.attributes("/run").get_double("mean_iterations"), cut.attributes("/run").get_double("mean_iterations"));
}

// A resume must be asked for, match the checkpoint's options, find the partial output
// and be started from the same input; without a checkpoint it starts over. A refusal
// changes no file.
TEST(RunResume, RefusalsAndFreshStarts) {
  Scratch dir("refusals");
  const std::vector<std::string> options{"--friction", "0.4", "--frame-every", "10", "--tolerance", "1e-8"};
  const std::string out_path = dir / "cut.h5";
  const std::string input = dir / "input";
  std::ofstream(input) << "the start state";
  {
    const CommandLine cli = run_cli(out_path, {"--resume"});
    OutputFile out(out_path, true);
    EXPECT_FALSE(resume_point(cli, run_plan(cli), out).has_value()) << "no checkpoint: start over";
  }
  EXPECT_FALSE(run(run_cli(out_path, options), input, 60, 30));
  const std::vector<std::string> partials = output_temporaries(out_path);
  ASSERT_EQ(partials.size(), 1u);
  const std::string partial = partials[0];
  const auto unchanged = [&] {
    EXPECT_EQ(output_temporaries(out_path), partials);
    EXPECT_TRUE(fs::exists(dir / ".cut.h5.checkpoint"));
  };

  std::vector<std::string> resume = options;
  resume.push_back("--resume");
  {
    const CommandLine cli = run_cli(out_path, options);
    OutputFile out(out_path, true);
    EXPECT_FALSE(resume_point(cli, run_plan(cli), out).has_value()) << "without --resume the checkpoint is ignored";
    EXPECT_EQ(out.stale(), partials);
  }
  unchanged();
  for (const std::vector<std::string>& changed :
       {std::vector<std::string>{"--friction", "0.3"}, {"--steps", "80"}, {"--frame-every", "20"}}) {
    SCOPED_TRACE(changed[0]);
    std::vector<std::string> args = resume;
    args.insert(args.end(), changed.begin(), changed.end());
    const CommandLine cli = run_cli(out_path, args);
    {
      OutputFile out(out_path, true);
      try {
        resume_point(cli, run_plan(cli), out, input);
        ADD_FAILURE() << "a resume with other options was accepted";
      } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("other options"), std::string::npos) << e.what();
      }
    }
    unchanged();
  }
  {
    const CommandLine cli = run_cli(out_path, resume);
    OutputFile out(out_path, true);
    const auto checkpoint = resume_point(cli, run_plan(cli), out, input);
    ASSERT_TRUE(checkpoint.has_value());
    EXPECT_EQ(checkpoint->step, 30);
    EXPECT_EQ(checkpoint->stats.frames_written, 4);
    EXPECT_EQ(checkpoint->partial_path, partial);
    EXPECT_EQ(checkpoint->partial, fs::path(partial).filename().string());
  }
  unchanged();
  // Copied (a new inode under the same name, as after a move to another file system):
  // still found.
  fs::copy_file(partial, dir / "copy");
  fs::rename(dir / "copy", partial);
  {
    const CommandLine cli = run_cli(out_path, resume);
    OutputFile out(out_path, true);
    const auto checkpoint = resume_point(cli, run_plan(cli), out, input);
    ASSERT_TRUE(checkpoint.has_value());
    EXPECT_EQ(checkpoint->partial_path, partial);
  }
  unchanged();
  // The input changed since the run started: refused, naming both hashes.
  std::ofstream(input) << "another start state";
  {
    const CommandLine cli = run_cli(out_path, resume);
    OutputFile out(out_path, true);
    try {
      resume_point(cli, run_plan(cli), out, input);
      ADD_FAILURE() << "a resume from a changed input was accepted";
    } catch (const UsageError& e) {
      EXPECT_NE(std::string(e.what()).find(sha256_file(input)), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("has changed"), std::string::npos) << e.what();
    }
  }
  unchanged();
  std::ofstream(input) << "the start state";
  // The partial output removed: the message says it is missing.
  fs::remove(partial);
  {
    const CommandLine cli = run_cli(out_path, resume);
    OutputFile out(out_path, true);
    try {
      resume_point(cli, run_plan(cli), out, input);
      ADD_FAILURE() << "a resume without its partial output was accepted";
    } catch (const UsageError& e) {
      EXPECT_NE(std::string(e.what()).find("is missing"), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(output_temporaries(out_path).empty());
  EXPECT_TRUE(fs::exists(dir / ".cut.h5.checkpoint"));
}

// A resume adopts the partial output under its own temporary name; killed before its
// next checkpoint, the checkpoint still finds it (by inode), and the next resume ends as
// the uninterrupted run.
TEST(RunResume, AdoptedPartialIsFoundAfterARenameWithoutCheckpoint) {
  Scratch dir("adopted");
  const std::vector<std::string> options{"--friction", "0.4", "--frame-every", "10", "--tolerance", "1e-8"};
  const std::string input = dir / "input";
  std::ofstream(input) << "the start state";
  ASSERT_TRUE(run(run_cli(dir / "ref.h5", options), input, 60));
  const std::string out_path = dir / "cut.h5";
  EXPECT_FALSE(run(run_cli(out_path, options), input, 60, 30));
  const std::vector<std::string> before = output_temporaries(out_path);
  ASSERT_EQ(before.size(), 1u);
  std::vector<std::string> resume = options;
  resume.push_back("--resume");
  {
    // A resume adopts it and dies (kill -9) before writing anything.
    const CommandLine cli = run_cli(out_path, resume);
    const RunPlan plan = run_plan(cli);
    OutputFile out(out_path, true);
    EXPECT_NE(out.temp_path(), before[0]) << "a dead process's temporary of the same pid is kept";
    const auto checkpoint = resume_point(cli, plan, out, input);
    ASSERT_TRUE(checkpoint.has_value());
    out.adopt(checkpoint->partial_path);
    EXPECT_FALSE(fs::exists(before[0]));
    EXPECT_EQ(output_temporaries(out_path), std::vector<std::string>{out.temp_path()});
    out.keep_partial();
  }
  ASSERT_TRUE(run(run_cli(out_path, resume), input, 60));
  EXPECT_TRUE(output_temporaries(out_path).empty());
  io::TrajectoryReader ref(dir / "ref.h5"), cut(out_path);
  ASSERT_EQ(cut.frame_count(), ref.frame_count());
  for (std::size_t k = 0; k < ref.frame_count(); ++k) expect_same_grains(ref.frame(k), cut.frame(k));
}

// The lock of an output's temporary is an OFD lock on a descriptor OutputFile keeps: HDF5
// creating, flock()ing, writing and closing the same file in the same process neither
// conflicts with it nor releases it, and a second writer of the same output refuses.
TEST(RunOutputLock, SurvivesHdf5OpeningAndClosingTheTemporary) {
  Scratch dir("lock");
  const std::string out_path = dir / "out.h5";
  {
    OutputFile out(out_path);
    EXPECT_TRUE(temporary_locked(out.temp_path()));
    {
      const Start s = sheared_start();
      const Engine engine(s.grains, s.box, 0.5, kMaterial, SolverSettings{}, 1e-3);
      io::TrajectoryWriter writer(out.temp_path());
      writer.write_grains(properties_of(engine.state()), engine.box());
      writer.append_frame(frame_of(engine, 0, 0.0));
      writer.close();
    }
    EXPECT_TRUE(temporary_locked(out.temp_path())) << "HDF5 closing the file released the lock";
    { io::TrajectoryReader reader(out.temp_path(), true); }
    EXPECT_TRUE(temporary_locked(out.temp_path())) << "HDF5 reading the file released the lock";
    try {
      OutputFile second(out_path);
      ADD_FAILURE() << "a second writer of the same output was accepted";
    } catch (const UsageError& e) {
      EXPECT_NE(std::string(e.what()).find("another process"), std::string::npos) << e.what();
    }
    EXPECT_EQ(output_temporaries(out_path), std::vector<std::string>{out.temp_path()});
    out.commit();
    EXPECT_FALSE(temporary_locked(out_path)) << "only temporaries are locked once committed";
  }
  EXPECT_TRUE(output_temporaries(out_path).empty());
}

// Temporaries of dead writers are removed when the next writer of the output commits,
// unless a checkpoint beside it may name one of them.
TEST(RunOutputLock, StaleTemporariesGoAtTheNextCommit) {
  Scratch dir("stale");
  const std::string out_path = dir / "out.h5";
  const std::string stale = dir / ".out.h5.part-999999999";
  std::ofstream(stale) << "left by a kill -9";
  // Not a program's temporary: a pipeline script's (Python tempfile) of the same name.
  const std::string other = dir / ".out.h5.part-8x2k_1.h5";
  std::ofstream(other) << "someone else's";
  {
    OutputFile out(out_path);
    EXPECT_EQ(out.stale(), std::vector<std::string>{stale});
    EXPECT_TRUE(fs::exists(stale)) << "removed before the run succeeded";
  }
  EXPECT_TRUE(fs::exists(stale));
  std::ofstream(dir / ".out.h5.checkpoint") << "an interrupted run's";
  {
    OutputFile out(out_path);
    out.commit();
  }
  EXPECT_TRUE(fs::exists(stale)) << "a checkpoint beside the output may name it";
  fs::remove(dir / ".out.h5.checkpoint");
  {
    OutputFile out(out_path);
    out.commit();
  }
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(other));
}

// An unfinished run's file is refused by readers, except for a resume; close() removes
// the mark.
TEST(RunOutputLock, UnfinishedMarkIsRefusedByReaders) {
  Scratch dir("mark");
  const Start s = sheared_start();
  Engine engine(s.grains, s.box, 0.5, kMaterial, SolverSettings{}, 1e-3);
  for (bool finished : {false, true}) {
    const std::string path = dir / (finished ? "finished.h5" : "partial.h5");
    {
      io::TrajectoryWriter writer(path);
      writer.mark_unfinished();
      writer.write_grains(properties_of(engine.state()), engine.box());
      writer.append_frame(frame_of(engine, 0, 0.0));
      if (finished) writer.close();
      else writer.close_unfinished();
    }
    if (finished) {
      EXPECT_NO_THROW(io::TrajectoryReader{path});
      continue;
    }
    try {
      io::TrajectoryReader reader(path);
      ADD_FAILURE() << "an unfinished run was read";
    } catch (const UsageError& e) {
      EXPECT_NE(std::string(e.what()).find("unfinished"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
    EXPECT_EQ(io::TrajectoryReader(path, true).frame_count(), 1u);
  }
}

}  // namespace
}  // namespace granflow
