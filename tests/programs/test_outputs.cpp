// Outputs, temporaries and resume across the programs, with real processes and real
// signals: a refused --resume changes nothing, a resume refuses a changed input, no
// program writes over one of its inputs, a second writer of the same output refuses at
// once and leaves the first one's work alone, and what a kill -9 leaves behind is
// cleaned up by the next run or refused by readers as unfinished.
#include <signal.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "core/sha256.hpp"
#include "io/trajectory.hpp"
#include "programs/run_tool.hpp"
#include "unit/expect_frame.hpp"

using namespace granflow::testing;
namespace io = granflow::io;
namespace fs = std::filesystem;

namespace {

const std::string& shear_packing() {
  return packed_once("outputs_shear_packing", "--grains 200 --packing-fraction 0.7 --seed 3");
}
const std::string& incline_packing() {
  return packed_once("outputs_incline_packing", "--incline --width 10 --height 5 --seed 3");
}

const std::string kShear = "--rate 0.01 --strain-step 1e-3 --restitution 0.5 --friction 0.4 --frame-every 100 --quiet";
const std::string kIncline = "--angle 20 --profile-block 500 --frame-every 500 --quiet";

// Everything gf-shear records per row, for the resume comparisons.
void expect_same_run(const std::string& ref_path, const std::string& cut_path) {
  granflow::test_support::expect_same_run(
      ref_path, cut_path,
      {"pressure", "shear_stress", "temperature", "solver_iterations", "collisions", "dissipated_energy"});
}

// Item 1: a --resume refused for other options leaves the partial output and the
// checkpoint as they were, and the right --resume then reproduces the uninterrupted run.
TEST(OutputsResume, RefusedResumeLeavesEverythingAsItWas) {
  ScratchDir dir("outputs_refused_resume");
  const std::string steps = " --steps 20000 ";
  ASSERT_EQ(run_tool("gf-shear", "-i " + shear_packing() + steps + kShear + " -o " + (dir / "ref.h5")).exit_code, 0);
  const std::string args = "-i " + shear_packing() + steps + kShear + " -o " + (dir / "cut.h5");
  const int code = interrupted_run("gf-shear", args, dir / "cut.h5", dir / "log", 300, SIGTERM);
  if (code == 0) GTEST_SKIP() << "the run finished before it could be interrupted";
  ASSERT_EQ(code, 1);
  fs::remove(dir / "log");
  ASSERT_TRUE(fs::exists(dir / ".cut.h5.checkpoint"));
  ASSERT_EQ(partials_of(dir / "cut.h5").size(), 1u);

  const FileSnapshot before = snapshot({dir.path.string()});
  auto refused = run_tool("gf-shear", args + " --restitution 0.6 --resume");
  EXPECT_EQ(refused.exit_code, 2) << refused.err;
  EXPECT_EQ(count_lines(refused.err), 1) << refused.err;
  EXPECT_NE(refused.err.find("other options"), std::string::npos) << refused.err;
  EXPECT_TRUE(snapshot({dir.path.string()}) == before) << "the refused --resume changed the directory";

  auto resumed = run_tool("gf-shear", args + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_TRUE(partials_of(dir / "cut.h5").empty());
  EXPECT_FALSE(fs::exists(dir / ".cut.h5.checkpoint"));
  expect_same_run(dir / "ref.h5", dir / "cut.h5");
}

// Item 2: the input regenerated between the interruption and the --resume.
TEST(OutputsResume, ResumeRefusesAChangedInput) {
  ScratchDir dir("outputs_changed_input");
  const std::string input = dir / "pack.h5";
  fs::copy_file(shear_packing(), input);
  const std::string args = "-i " + input + " --steps 20000 " + kShear + " -o " + (dir / "cut.h5");
  const int code = interrupted_run("gf-shear", args, dir / "cut.h5", dir / "log", 200, SIGTERM);
  if (code == 0) GTEST_SKIP() << "the run finished before it could be interrupted";
  ASSERT_EQ(code, 1);
  fs::remove(dir / "log");
  const std::string then = granflow::sha256_file(input);
  ASSERT_EQ(run_tool("gf-pack", "--grains 200 --packing-fraction 0.7 --seed 4 --quiet -o " + input).exit_code, 0);
  const std::string now = granflow::sha256_file(input);
  ASSERT_NE(now, then);

  const FileSnapshot before = snapshot({dir.path.string()});
  auto r = run_tool("gf-shear", args + " --resume");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(input), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(then), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(now), std::string::npos) << r.err;
  EXPECT_TRUE(snapshot({dir.path.string()}) == before) << "the refused --resume changed the directory";
}

// Item 3: the output is one of the inputs, however it is spelled.
TEST(OutputsSameFile, NoProgramWritesOverItsInput) {
  ScratchDir dir("outputs_same_file");
  // The programs' inputs, copied in: a packing, an incline packing, a short shear run.
  const std::string pack = dir / "pack.h5", incline = dir / "incline.h5", run = dir / "run.h5";
  fs::copy_file(shear_packing(), pack);
  fs::copy_file(incline_packing(), incline);
  ASSERT_EQ(run_tool("gf-shear", "-i " + pack + " --steps 200 " + kShear + " -o " + run).exit_code, 0);

  struct Case {
    const char* tool;
    std::string input;
    std::string args;  // {out} = the output path
  };
  const std::vector<Case> cases{
      {"gf-pack", pack, "-i " + pack + " --packing-fraction 0.75 --quiet -o {out}"},
      {"gf-shear", pack, "-i " + pack + " --steps 50 " + kShear + " -o {out}"},
      {"gf-incline", incline, "-i " + incline + " --steps 500 " + kIncline + " -o {out}"},
      {"gf-correlate", run, run + " --quiet -o {out}"},
      {"gf-correlate", run, dir / "other.h5" + std::string(" --reference ") + run + " --quiet -o {out}"},
      {"gf-kinetic", run, run + " --from-strain 0 --quiet -o {out}"},
  };
  for (const Case& c : cases) {
    const fs::path input(c.input);
    const std::string name = input.filename().string();
    const std::string symlink = dir / ("link_" + name), hardlink = dir / ("hard_" + name);
    fs::remove(symlink);
    fs::remove(hardlink);
    fs::create_symlink(input, symlink);
    fs::create_hard_link(input, hardlink);
    for (const std::string& output :
         {c.input, (input.parent_path() / "." / name).string(),
          (input.parent_path() / ".." / input.parent_path().filename() / name).string(), symlink, hardlink}) {
      SCOPED_TRACE(std::string(c.tool) + " -o " + output);
      std::string args = c.args;
      args.replace(args.find("{out}"), 5, output);
      const FileSnapshot before = snapshot({dir.path.string()});
      auto r = run_tool(c.tool, args);
      EXPECT_EQ(r.exit_code, 2) << r.err;
      EXPECT_EQ(count_lines(r.err), 1) << r.err;
      EXPECT_NE(r.err.find("same file as the input"), std::string::npos) << r.err;
      EXPECT_TRUE(snapshot({dir.path.string()}) == before) << "the refusal changed the input or the directory";
    }
    fs::remove(symlink);
    fs::remove(hardlink);
  }
}

// Item 4: a second run writing the same output while the first runs.
void expect_second_writer_refused(const std::string& tool, const std::string& args, const fs::path& output,
                                  const std::string& log) {
  const pid_t first = start_tool(tool, args, log);
  ASSERT_TRUE(wait_for_partial(output, first)) << "the first run never created its temporary";
  auto second = run_tool(tool, args);
  const bool first_still_running = ::waitpid(first, nullptr, WNOHANG) == 0;
  if (!first_still_running) GTEST_SKIP() << "the first run ended before the second one started";
  EXPECT_EQ(second.exit_code, 2) << second.err;
  EXPECT_EQ(count_lines(second.err), 1) << second.err;
  EXPECT_NE(second.err.find("another process (pid " + std::to_string(first) + ")"), std::string::npos) << second.err;
  EXPECT_NE(second.err.find(output.string()), std::string::npos) << second.err;
  EXPECT_EQ(wait_exit_code(first), 0) << "the first run failed after the second one started";
  EXPECT_TRUE(partials_of(output).empty());
  EXPECT_FALSE(fs::exists(checkpoint_of(output)));
  io::TrajectoryReader finished(output.string());
  EXPECT_GT(finished.frame_count(), 1u);
}

}  // namespace

TEST(OutputsConcurrent, SecondGfShearRefusesAndTheFirstFinishes) {
  ScratchDir dir("outputs_concurrent_shear");
  expect_second_writer_refused("gf-shear",
                               "-i " + shear_packing() + " --steps 20000 " + kShear + " -o " + (dir / "out.h5"),
                               dir.path / "out.h5", dir / "log");
}

TEST(OutputsConcurrent, SecondGfInclineRefusesAndTheFirstFinishes) {
  ScratchDir dir("outputs_concurrent_incline");
  expect_second_writer_refused("gf-incline",
                               "-i " + incline_packing() + " --steps 30000 " + kIncline + " -o " + (dir / "out.h5"),
                               dir.path / "out.h5", dir / "log");
}

// Item 14: gf-pack killed with SIGKILL leaves its temporary; the next run of the same
// output removes it.
TEST(OutputsStale, NextGfPackRemovesTheTemporaryOfAKilledOne) {
  ScratchDir dir("outputs_stale_pack");
  const fs::path output = dir.path / "p.h5";
  const pid_t pid =
      start_tool("gf-pack", "--grains 20000 --packing-fraction 0.84 --quiet -o " + output.string(), dir / "log");
  ASSERT_TRUE(wait_for_partial(output, pid)) << "gf-pack never created its temporary";
  ::kill(pid, SIGKILL);
  wait_exit_code(pid);
  const auto left = partials_of(output);
  ASSERT_EQ(left.size(), 1u);
  EXPECT_FALSE(fs::exists(output));

  auto r = run_tool("gf-pack", "--grains 50 --quiet -o " + output.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(output));
  EXPECT_TRUE(partials_of(output).empty()) << "the stale temporary " << left[0] << " is still there";
}

// Item 14: gf-shear killed with SIGKILL after a checkpoint: its partial output is refused
// by readers as unfinished, and --resume continues it to the uninterrupted run's result.
TEST(OutputsStale, PartialOfAKilledGfShearIsUnfinishedAndResumable) {
  ScratchDir dir("outputs_killed_shear");
  // A fast shear (many frames and contacts per second of wall time), killed shortly after
  // a checkpoint: chunks flushed by the checkpoint are being rewritten and moved then,
  // and HDF5 flushes some metadata of the rows written since (extents, chunk indexes).
  const std::string run = " --steps 3000 --rate 1 --frame-every 20 --quiet";
  ASSERT_EQ(run_tool("gf-shear", "-i " + shear_packing() + run + " -o " + (dir / "ref.h5")).exit_code, 0);
  const fs::path output = dir.path / "cut.h5";
  const std::string args = "-i " + shear_packing() + run + " -o " + output.string() + " --checkpoint-every 0.01";
  int killed = 0, refused = 0;
  for (int trial = 0; trial < 6; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    fs::remove(output);
    const pid_t pid = start_tool("gf-shear", args, dir / "log");
    bool ended = false;
    for (int k = 0; k < 500 && !fs::exists(checkpoint_of(output)) && !ended; ++k) {
      ended = ::waitpid(pid, nullptr, WNOHANG) == pid;
      if (!ended) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (!ended) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20 + 15 * trial));
      ::kill(pid, SIGKILL);
      wait_exit_code(pid);
    }
    if (fs::exists(output) || !fs::exists(checkpoint_of(output))) continue;  // ended before the kill
    ++killed;
    const auto left = partials_of(output);
    ASSERT_EQ(left.size(), 1u);

    if (trial == 0) {
      // A reader refuses the partial output, naming it and saying what it is.
      for (const std::string& reader :
           {std::string("gf-shear -i ") + left[0].string() + " --steps 10 " + kShear + " -o " + (dir / "branch.h5"),
            std::string("gf-correlate ") + left[0].string() + " --quiet -o " + (dir / "corr.h5")}) {
        const std::string tool = reader.substr(0, reader.find(' '));
        auto r = run_tool(tool, reader.substr(reader.find(' ') + 1));
        EXPECT_EQ(r.exit_code, 2) << tool << ": " << r.err;
        EXPECT_EQ(count_lines(r.err), 1) << r.err;
        EXPECT_NE(r.err.find(left[0].string()), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("unfinished"), std::string::npos) << r.err;
      }
    }

    // --resume continues the run to the file the uninterrupted run writes. A kill that
    // lands inside a flush (a checkpoint's own write of HDF5 metadata, every 10 ms here)
    // can still leave metadata of two flushes mixed: that partial output is refused,
    // naming it and changing nothing. With HDF5's default file-space reuse most kills
    // here damage it (18 of 20); now at most one of these trials may.
    const FileSnapshot before = snapshot({dir.path.string()});
    auto resumed = run_tool("gf-shear", args + " --resume");
    if (resumed.exit_code == 2 && resumed.err.find("is damaged") != std::string::npos && refused == 0) {
      ++refused;
      EXPECT_EQ(count_lines(resumed.err), 1) << resumed.err;
      EXPECT_NE(resumed.err.find(left[0].string()), std::string::npos) << resumed.err;
      EXPECT_TRUE(snapshot({dir.path.string()}) == before) << "the refusal changed a file";
      fs::remove(checkpoint_of(output));
      fs::remove(left[0]);
      continue;
    }
    ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
    EXPECT_TRUE(partials_of(output).empty());
    EXPECT_FALSE(fs::exists(checkpoint_of(output)));
    expect_same_run(dir / "ref.h5", output.string());
  }
  if (killed == 0) GTEST_SKIP() << "every run ended before it could be killed after a checkpoint";
}

// Item 12: a directory that refuses new files for another reason than permissions
// (/proc: ENOENT) is named with the real reason, not called "not writable".
TEST(OutputsMessages, UncreatableTemporaryNamesTheDirectoryAndTheReason) {
  auto r = run_tool("gf-pack", "--grains 10 -o /proc/granflow_test.h5");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("cannot create"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("'/proc'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("No such file or directory"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("not writable"), std::string::npos) << r.err;
}
