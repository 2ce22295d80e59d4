// gf-xdmf as a user runs it: the XDMF text of a real gf-pack → gf-shear trajectory names
// the right datasets, blocks and shapes for every frame (ParaView's reading of it is
// paraview.GfXdmf), the reference to the .h5 is relative, a packing works, and bad input is
// refused (exit 2, one line, nothing left).
#include <gtest/gtest.h>

#include <hdf5.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <sstream>

#include "io/hdf5_handle.hpp"
#include "io/trajectory.hpp"
#include "programs/run_tool.hpp"

using namespace granflow;
using namespace granflow::testing;

namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::size_t count(const std::string& text, const std::string& piece) {
  std::size_t n = 0;
  for (auto at = text.find(piece); at != std::string::npos; at = text.find(piece, at + piece.size())) ++n;
  return n;
}

// A frictionless sheared flow (200 grains, ν = 0.8): frames at steps 0, 50, 100, 150, the
// first without contacts.
const std::string& flow() {
  static ScratchDir dir("xdmf_flow");
  static const std::string path = [] {
    const std::string pack = packed_once("xdmf_pack", "--grains 200 --packing-fraction 0.8 --seed 7");
    const std::string out = dir / "flow.h5";
    EXPECT_EQ(
        run_tool("gf-shear", "-i " + pack + " -o " + out + " --rate 1 --steps 150 --frame-every 50 --quiet").exit_code,
        0);
    return out;
  }();
  return path;
}

// The HyperSlab item of `count` elements starting at `start` of the dataset `path` of shape `dims`.
std::string slab(const std::string& file, const std::string& path, const std::string& dims, const std::string& start,
                 const std::string& stride, const std::string& count_text) {
  return "<DataItem Dimensions=\"3 " + std::to_string(std::count(stride.begin(), stride.end(), '1')) +
         "\" Format=\"XML\">" + start + " " + stride + " " + count_text + "</DataItem><DataItem Dimensions=\"" + dims +
         "\" " + (path.find("pair") != std::string::npos ? "NumberType=\"Int\" Precision=\"4\"" : "") +
         (path.find("pair") != std::string::npos ? "" : "NumberType=\"Float\" Precision=\"8\"") + " Format=\"HDF\">" +
         file + ":" + path + "</DataItem>";
}

}  // namespace

TEST(GfXdmf, DescribesEveryFrameWithReferencesIntoTheTrajectory) {
  ScratchDir dir("xdmf_describe");
  const std::string run = dir / "flow.h5";
  std::filesystem::copy_file(flow(), run);
  const std::string before = read_text(run);
  const ToolResult r = run_tool("gf-xdmf", "-i " + run);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("4 frame(s), 200 grains"), std::string::npos) << r.err;
  EXPECT_EQ(read_text(run), before) << "the trajectory was changed";
  const std::string xdmf = read_text(dir / "flow.xdmf2");  // the default output, beside the input
  ASSERT_FALSE(xdmf.empty());
  EXPECT_EQ(dir.entries(), 2) << "a temporary was left";

  io::TrajectoryReader reader(run);
  const std::size_t n = reader.frame_count(), N = reader.grain_count();
  ASSERT_EQ(n, 4u);
  std::vector<std::size_t> shape;
  const std::vector<double> offset = reader.array("/contacts/frame_offset", &shape);
  const std::size_t total = std::size_t(offset.back());
  const std::string frames = std::to_string(n), grains = std::to_string(N), rows = std::to_string(total);

  EXPECT_NE(xdmf.find("<Xdmf Version=\"2.0\">"), std::string::npos);
  for (const char* name : {"grains", "contacts", "box"}) {
    EXPECT_EQ(
        count(xdmf, "<Grid Name=\"" + std::string(name) + "\" GridType=\"Collection\" CollectionType=\"Temporal\">"),
        1u)
        << name;
    EXPECT_EQ(count(xdmf, "<Grid Name=\"" + std::string(name) + "\" GridType=\"Uniform\">"), n) << name;
  }
  // The .h5 by its name alone (beside the XDMF), never copied: no inline value longer than
  // the few constants of the box and the connectivity of one cell.
  EXPECT_EQ(count(xdmf, ">flow.h5:/"), count(xdmf, "Format=\"HDF\""));
  EXPECT_EQ(xdmf.find(dir.path.string()), std::string::npos) << "an absolute path";
  std::smatch m;
  const std::regex inline_values("Format=\"XML\">([^<]*)<");
  for (auto it = std::sregex_iterator(xdmf.begin(), xdmf.end(), inline_values); it != std::sregex_iterator(); ++it)
    EXPECT_LE((*it)[1].length(), 40) << (*it)[1];
  // Per-grain constants: whole datasets.
  EXPECT_EQ(count(xdmf, "<DataItem Dimensions=\"" + grains +
                            "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">flow.h5:/particles/grains/radius<"),
            n);
  EXPECT_EQ(count(xdmf, "<DataItem Dimensions=\"" + grains +
                            "\" NumberType=\"UChar\" Precision=\"1\" Format=\"HDF\">flow.h5:/particles/grains/fixed<"),
            n);
  const std::vector<double> times = reader.frame_times();
  for (std::size_t k = 0; k < n; ++k) {
    SCOPED_TRACE("frame " + std::to_string(k));
    const std::string K = std::to_string(k);
    char time[40];
    std::snprintf(time, sizeof time, "<Time Value=\"%.17g\"/>", times[k]);
    EXPECT_EQ(count(xdmf, time), 3u);
    // Grains: the frame's block of positions, velocities and spins.
    for (const char* element : {"position", "velocity"})
      EXPECT_NE(xdmf.find(slab("flow.h5", "/particles/grains/" + std::string(element) + "/value",
                               frames + " " + grains + " 2", K + " 0 0", "1 1 1", "1 " + grains + " 2")),
                std::string::npos)
          << element;
    EXPECT_NE(xdmf.find(slab("flow.h5", "/particles/grains/angular_velocity/value", frames + " " + grains, K + " 0",
                             "1 1", "1 " + grains)),
              std::string::npos);
    EXPECT_NE(
        xdmf.find(slab("flow.h5", "/particles/grains/box/edges/value", frames + " 2 2", K + " 0 0", "1 1 1", "1 2 2")),
        std::string::npos);
    // Contacts: the frame's rows of pair, branch and the forces.
    const std::size_t o = std::size_t(offset[k]), c = std::size_t(offset[k + 1] - offset[k]);
    if (k == 0) {
      EXPECT_EQ(c, 0u) << "a shear run's first frame has no contacts";
      continue;
    }
    ASSERT_GE(c, 2u);
    const std::string O = std::to_string(o), C = std::to_string(c);
    EXPECT_NE(xdmf.find("<Topology TopologyType=\"Polyline\" NumberOfElements=\"" + C + "\" NodesPerElement=\"2\">"),
              std::string::npos);
    EXPECT_NE(xdmf.find(slab("flow.h5", "/contacts/pair", rows + " 2", O + " 0", "1 1", C + " 1")), std::string::npos);
    EXPECT_NE(xdmf.find(slab("flow.h5", "/contacts/pair", rows + " 2", O + " 0", "1 1", C + " 2")), std::string::npos);
    for (const char* column : {"0", "1"})
      EXPECT_NE(xdmf.find(slab("flow.h5", "/contacts/branch", rows + " 2", O + " " + column, "1 1", C + " 1")),
                std::string::npos)
          << column;
    for (const char* force : {"normal_force", "tangential_force", "binary_force"})
      EXPECT_NE(xdmf.find(slab("flow.h5", "/contacts/" + std::string(force), rows, O, "1", C)), std::string::npos)
          << force;
  }
  EXPECT_EQ(count(xdmf, "Function=\"($0[$1 * 2] , ($0[$1 * 2] - $2)) , ($0[$1 * 2 + 1] , ($0[$1 * 2 + 1] - $3))\""),
            n - 1);

  // Written again: the same bytes (nothing in it depends on the time or the machine).
  ASSERT_EQ(run_tool("gf-xdmf", "-i " + run + " --quiet").exit_code, 0);
  EXPECT_EQ(read_text(dir / "flow.xdmf2"), xdmf);
}

TEST(GfXdmf, NamesTheTrajectoryRelativeToTheXdmfFile) {
  ScratchDir dir("xdmf_relative");
  std::filesystem::create_directories(dir.path / "runs");
  std::filesystem::create_directories(dir.path / "views");
  std::filesystem::copy_file(flow(), dir / "runs/flow.h5");
  const ToolResult r = run_tool("gf-xdmf", "-i " + (dir / "runs/flow.h5") + " -o " + (dir / "views/flow.xdmf") + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  const std::string xdmf = read_text(dir / "views/flow.xdmf");
  EXPECT_GT(count(xdmf, ">../runs/flow.h5:/particles/grains/position/value<"), 0u);
  EXPECT_EQ(count(xdmf, ">../runs/flow.h5:/"), count(xdmf, "Format=\"HDF\""));
}

// A packing has no contacts: grains and box only, and the last frame is the only one.
TEST(GfXdmf, PackingWithoutContacts) {
  ScratchDir dir("xdmf_packing");
  ASSERT_EQ(run_tool("gf-pack", "--grains 50 --seed 2 --quiet -o " + (dir / "p.h5")).exit_code, 0);
  const ToolResult r = run_tool("gf-xdmf", "-i " + (dir / "p.h5") + " -o " + (dir / "view.xdmf"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("1 frame(s), 50 grains, 0 contacts"), std::string::npos) << r.err;
  const std::string xdmf = read_text(dir / "view.xdmf");
  EXPECT_EQ(xdmf.find("contacts"), std::string::npos);
  EXPECT_EQ(count(xdmf, "<Grid Name=\"grains\" GridType=\"Uniform\">"), 1u);
  EXPECT_EQ(count(xdmf, "<Grid Name=\"box\" GridType=\"Uniform\">"), 1u);
}

// A frame with one contact names its first grain's position directly (an XDMF 2 Function
// takes an argument of one element for a number): the pair's grain i, the contact's row.
TEST(GfXdmf, FrameWithOneContact) {
  ScratchDir dir("xdmf_one_contact");
  const std::string run = dir / "one.h5";
  std::filesystem::copy_file(flow(), run);
  std::int64_t row = 0;
  {
    io::File f = io::open_file(run, true);
    io::Dataset offsets = io::open_dataset(f.get(), "/contacts/frame_offset");
    std::vector<std::int64_t> o = io::read_all<std::int64_t>(offsets.get());
    row = o[1];
    o[2] = o[1] + 1;  // frame 1 keeps its first contact only
    ASSERT_GE(H5Dwrite(offsets.get(), H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, o.data()), 0);
  }
  const int i = io::TrajectoryReader(run).frame(1).contacts.pair.at(0)[0];
  ASSERT_EQ(run_tool("gf-xdmf", "-i " + run + " -q").exit_code, 0);
  const std::string xdmf = read_text(dir / "one.xdmf2");
  const std::string n = std::to_string(io::TrajectoryReader(run).grain_count());
  EXPECT_NE(xdmf.find("Function=\"$0 ; ($0 - $1)\""), std::string::npos);
  EXPECT_NE(xdmf.find(slab("one.h5", "/particles/grains/position/value", "4 " + n + " 2",
                           "1 " + std::to_string(i) + " 0", "1 1 1", "1 1 2")),
            std::string::npos);
  std::vector<std::size_t> shape;
  io::TrajectoryReader(run).array("/contacts/pair", &shape);
  EXPECT_NE(xdmf.find(slab("one.h5", "/contacts/branch", std::to_string(shape[0]) + " 2", std::to_string(row) + " 0",
                           "1 1", "1 2")),
            std::string::npos);
}

TEST(GfXdmfUsage, HelpNamesEveryOption) {
  const ToolResult r = run_tool("gf-xdmf", "--help");
  EXPECT_EQ(r.exit_code, 0);
  // --help prints on stdout, which run_tool discards: run it through the shell instead.
  const std::string out = std::filesystem::temp_directory_path() / "granflow_xdmf_help.txt";
  ASSERT_EQ(std::system((tool_path("gf-xdmf") + " --help > " + out).c_str()), 0);
  const std::string help = read_text(out);
  std::filesystem::remove(out);
  for (const char* option : {"--input", "--output", "--quiet", "--help", "--version"})
    EXPECT_NE(help.find(option), std::string::npos) << option;
  EXPECT_NE(help.find("Xdmf Reader"), std::string::npos);
}

class GfXdmfBadInput : public ::testing::TestWithParam<BadInput> {};

TEST_P(GfXdmfBadInput, FailsWithExitTwoOneLineNoOutput) {
  static ScratchDir dir("xdmf_bad_inputs");
  static const std::string text = [] {
    const std::string path = dir / "text.h5";
    std::ofstream(path) << "not a trajectory\n";
    return path;
  }();
  static const std::string truncated = [] {
    const std::string path = dir / "truncated.h5";
    const std::string bytes = read_text(flow());
    std::ofstream(path, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    return path;
  }();
  // HDF5, but not a trajectory.
  static const std::string other = [] {
    const std::string path = dir / "other.h5";
    io::File f = io::create_file(path);
    io::create_group(f.get(), "/something");
    return path;
  }();
  static const std::string unfinished = [] {
    const std::string path = dir / "unfinished.h5";
    std::filesystem::copy_file(flow(), path);
    io::File f = io::open_file(path, true);
    io::write_attribute(f.get(), "unfinished", std::int64_t(1));
    return path;
  }();
  static const std::string run = [] {
    const std::string path = dir / "run.h5";
    std::filesystem::copy_file(flow(), path);
    return path;
  }();
  expect_refused(
      "gf-xdmf", GetParam(),
      {{"{text}", text}, {"{truncated}", truncated}, {"{other}", other}, {"{unfinished}", unfinished}, {"{run}", run}},
      " --quiet");
}

INSTANTIATE_TEST_SUITE_P(
    Cases, GfXdmfBadInput,
    ::testing::Values(BadInput{"missing_trajectory", "-i {out}.h5 -o {out}", "no such file"},
                      BadInput{"no_input", "-o {out}", "--input"},
                      BadInput{"not_hdf5", "-i {text} -o {out}", "not an HDF5 file"},
                      BadInput{"truncated", "-i {truncated} -o {out}", "truncated.h5"},
                      BadInput{"not_a_trajectory", "-i {other} -o {out}", "not an H5MD file"},
                      BadInput{"unfinished_run", "-i {unfinished} -o {out}", "unfinished run"},
                      BadInput{"output_is_the_input", "-i {run} -o {run}", "same file as the input"},
                      BadInput{"output_dir_missing", "-i {run} -o {out}/nodir/view.xdmf", "does not exist"},
                      BadInput{"unknown_option", "-i {run} -o {out} --frame 2", "--frame"}),
    bad_input_name);

// /proc refuses new files even to root; a chmod-ed directory covers ordinary users.
TEST(GfXdmfBadInput, UnwritableDirectory) {
  const ToolResult proc = run_tool("gf-xdmf", "-i " + flow() + " -o /proc/granflow_test.xdmf");
  EXPECT_EQ(proc.exit_code, 2) << proc.err;
  EXPECT_EQ(count_lines(proc.err), 1) << proc.err;
  EXPECT_NE(proc.err.find("cannot create"), std::string::npos) << proc.err;
  if (::geteuid() == 0) return;
  ScratchDir dir("xdmf_unwritable");
  std::filesystem::permissions(dir.path, std::filesystem::perms::owner_read | std::filesystem::perms::owner_exec);
  const ToolResult r = run_tool("gf-xdmf", "-i " + flow() + " -o " + (dir / "view.xdmf"));
  std::filesystem::permissions(dir.path, std::filesystem::perms::owner_all);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("not writable"), std::string::npos) << r.err;
  EXPECT_EQ(dir.entries(), 0);
}
