// gf-pack on bad usage: exit code 2, one clear line naming the problem, no output left.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "io/trajectory.hpp"
#include "programs/run_tool.hpp"

using namespace granflow::testing;

class GfPackBadInput : public ::testing::TestWithParam<BadInput> {};

TEST_P(GfPackBadInput, FailsWithExitTwoOneLineNoOutput) { expect_refused("gf-pack", GetParam(), {}); }

INSTANTIATE_TEST_SUITE_P(
    Cases, GfPackBadInput,
    ::testing::Values(BadInput{"nu_zero", "--packing-fraction 0 -o {out}", "--packing-fraction"},
                      BadInput{"nu_negative", "--packing-fraction -0.1 -o {out}", "--packing-fraction"},
                      BadInput{"nu_too_high", "--packing-fraction 0.91 -o {out}", "--packing-fraction"},
                      BadInput{"nu_nan", "--packing-fraction nan -o {out}", "--packing-fraction"},
                      BadInput{"one_grain", "--grains 1 -o {out}", "--grains"},
                      BadInput{"grains_not_integer", "--grains 10.5 -o {out}", "--grains"},
                      BadInput{"polydispersity_one", "--polydispersity 1 -o {out}", "--polydispersity"},
                      BadInput{"diameter_zero", "--mean-diameter 0 -o {out}", "--mean-diameter"},
                      BadInput{"unknown_option", "--frobnicate -o {out}", "--frobnicate"},
                      BadInput{"missing_output", "--grains 10", "--output"},
                      BadInput{"output_dir_missing", "--grains 10 -o {out}/nodir/p.h5", "does not exist"},
                      BadInput{"incline_width_zero", "--incline --width 0 -o {out}", "--width"},
                      BadInput{"seed_negative", "--seed -3 -o {out}", "--seed"},
                      BadInput{"tile_without_input", "--tile 2 -o {out}", "--tile needs --input"}),
    bad_input_name);

TEST(GfPackBadInput, UnwritableDirectory) {
  // /proc refuses new files even to root; a chmod-ed directory covers ordinary users.
  auto proc = run_tool("gf-pack", "--grains 10 -o /proc/granflow_test.h5");
  EXPECT_EQ(proc.exit_code, 2) << proc.err;
  EXPECT_NE(proc.err.find("cannot create"), std::string::npos) << proc.err;
  if (::geteuid() == 0) return;
  ScratchDir dir("pack_unwritable");
  std::filesystem::permissions(dir.path, std::filesystem::perms::owner_read | std::filesystem::perms::owner_exec);
  auto r = run_tool("gf-pack", "--grains 10 -o " + (dir / "p.h5"));
  std::filesystem::permissions(dir.path, std::filesystem::perms::owner_all);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("not writable"), std::string::npos) << r.err;
}

TEST(GfPackUsage, HelpAndVersion) {
  auto r = run_tool("gf-pack", "--help");
  EXPECT_EQ(r.exit_code, 0);
  auto v = run_tool("gf-pack", "--version");
  EXPECT_EQ(v.exit_code, 0);
}

// --input files that are not packings: missing, not HDF5, truncated, lacking a group,
// a frame out of range. The message names the file; nothing is written.
TEST(GfPackBadInput, BadInputFiles) {
  ScratchDir dir("pack_bad_inputs");
  ScratchDir out_dir("pack_bad_inputs_out");
  const std::string good = dir / "good.h5";
  ASSERT_EQ(run_tool("gf-pack", "--grains 100 --quiet -o " + good).exit_code, 0);

  const std::string text = dir / "text.h5";
  std::ofstream(text) << "not hdf5\n";
  const std::string truncated = dir / "truncated.h5";
  std::filesystem::copy_file(good, truncated);
  std::filesystem::resize_file(truncated, std::filesystem::file_size(good) / 2);
  const std::string no_grains = dir / "no_grains.h5";
  granflow::io::TrajectoryWriter(no_grains).close();

  struct BadFile {
    std::string path, args, expected;
  };
  for (const BadFile& b : {BadFile{dir / "missing.h5", "", "missing.h5"}, BadFile{text, "", "text.h5"},
                           BadFile{truncated, "", "truncated.h5"}, BadFile{no_grains, "", "/particles/grains"},
                           BadFile{good, "--frame 3", "--frame"}, BadFile{good, "--tile 0", "--tile"},
                           BadFile{good, "--tile 2 --packing-fraction 0.7", "--packing-fraction"},
                           BadFile{good, "--tile 2 --tolerance 1e-6", "--tolerance"},
                           BadFile{good, "--tile 5000", "2147483647"}}) {
    auto r = run_tool("gf-pack", "-i " + b.path + " " + b.args + " -o " + (out_dir / "out.h5"));
    EXPECT_EQ(r.exit_code, 2) << b.path << ": " << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(b.expected), std::string::npos) << r.err;
    EXPECT_EQ(out_dir.entries(), 0) << "output left behind for " << b.path;
  }
}

// --tile: a sheared frame of a small run, copied K × K into a packing that gf-shear starts
// from. The counts, the box and the packing fraction follow from the frame; an incline
// start (open in y) is refused.
TEST(GfPackTile, TilesAShearedFrameIntoAStartForGfShear) {
  ScratchDir dir("pack_tile");
  const std::string pack = dir / "pack.h5", run = dir / "run.h5", big = dir / "big.h5";
  ASSERT_EQ(run_tool("gf-pack", "--grains 200 --quiet -o " + pack).exit_code, 0);
  auto sheared = run_tool("gf-shear", "-i " + pack + " -o " + run + " --strain 0.3 --frame-every 300 --quiet");
  ASSERT_EQ(sheared.exit_code, 0) << sheared.err;
  auto r = run_tool("gf-pack", "-i " + run + " --tile 3 --quiet -o " + big);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  granflow::io::TrajectoryReader small_file(run), big_file(big);
  const auto small_frame = small_file.frame(small_file.frame_index(-1));
  const auto big_frame = big_file.frame(0);
  EXPECT_EQ(big_frame.position.size(), 9 * small_frame.position.size());
  EXPECT_DOUBLE_EQ(big_frame.box.lx, 3 * small_frame.box.lx);
  EXPECT_DOUBLE_EQ(big_frame.box.ly, 3 * small_frame.box.ly);
  EXPECT_NEAR(big_frame.box.offset, std::fmod(3 * small_frame.box.offset, big_frame.box.lx), 1e-9);
  EXPECT_GT(small_frame.box.offset, 0);  // a sheared frame: the offset is what is tested
  auto shear = run_tool("gf-shear", "-i " + big + " -o " + (dir / "big_run.h5") + " --steps 20 --frame-every 20 --quiet");
  EXPECT_EQ(shear.exit_code, 0) << shear.err;

  const std::string incline = dir / "incline.h5";
  ASSERT_EQ(run_tool("gf-pack", "--incline --width 10 --height 5 --quiet -o " + incline).exit_code, 0);
  auto open = run_tool("gf-pack", "-i " + incline + " --tile 2 --quiet -o " + (dir / "no.h5"));
  EXPECT_EQ(open.exit_code, 2) << open.err;
  EXPECT_NE(open.err.find("open in y"), std::string::npos) << open.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "no.h5"));
}
