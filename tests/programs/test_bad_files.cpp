// Every program that reads grains refuses a file with impossible values: one crafted file
// per defect (a valid file with one value changed in place), run through every program
// that reads it. Each refusal: exit 2, one line naming the file and what is wrong in it,
// nothing written, the input unchanged byte for byte.
#include <gtest/gtest.h>

#include <hdf5.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "io/hdf5_handle.hpp"
#include "io/trajectory.hpp"
#include "programs/run_tool.hpp"

using namespace granflow;
using namespace granflow::testing;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Element `flat` (row-major) of a dataset, overwritten in place.
template <class T>
void poke(const std::string& path, const std::string& dataset, std::size_t flat, T value) {
  io::File file = io::open_file(path, true);
  io::Dataset d = io::open_dataset(file.get(), dataset);
  std::vector<T> all = io::read_all<T>(d.get());
  ASSERT_LT(flat, all.size()) << dataset;
  all[flat] = value;
  ASSERT_GE(H5Dwrite(d.get(), io::native_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, all.data()), 0) << dataset;
}

void remove_group(const std::string& path, const std::string& group) {
  io::File file = io::open_file(path, true);
  ASSERT_GE(H5Ldelete(file.get(), group.c_str(), H5P_DEFAULT), 0) << group;
}

std::string bytes_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The sources every crafted file starts from, made once by the real programs.
struct Sources {
  ScratchDir dir{"bad_files_sources"};
  std::string packing = dir / "packing.h5", shear = dir / "shear.h5", incline = dir / "incline.h5",
              incline_run = dir / "incline_run.h5";
  Sources() {
    EXPECT_EQ(run_tool("gf-pack", "--grains 200 --packing-fraction 0.7 --seed 3 --quiet -o " + packing).exit_code, 0);
    EXPECT_EQ(run_tool("gf-shear", "-i " + packing + " -o " + shear +
                                       " --rate 0.01 --strain-step 1e-3 --friction 0.4 --steps 300 "
                                       "--frame-every 100 --quiet")
                  .exit_code,
              0);
    EXPECT_EQ(run_tool("gf-pack", "--incline --width 10 --height 5 --seed 3 --quiet -o " + incline).exit_code, 0);
    EXPECT_EQ(run_tool("gf-incline", "-i " + incline + " -o " + incline_run +
                                         " --angle 20 --steps 40 --profile-block 20 --frame-every 20 --quiet")
                  .exit_code,
              0);
  }
};

const Sources& sources() {
  static Sources s;
  return s;
}

// How each program is run on a file F, writing OUT.
const std::map<std::string, std::string> kCommand = {
    {"gf-pack", "-i F -o OUT --quiet"},
    {"gf-shear", "-i F -o OUT --steps 2 --quiet"},
    {"gf-incline", "-i F -o OUT --angle 20 --steps 20 --profile-block 10 --quiet"},
    {"gf-correlate", "F -o OUT --from-strain 0 --quiet"},
    {"gf-kinetic", "F -o OUT --from-strain 0 --quiet"},
    {"gf-xdmf", "-i F -o OUT --quiet"},
};

ToolResult run_on(const std::string& program, const std::string& file, const std::string& out) {
  std::string args = kCommand.at(program);
  args.replace(args.find("OUT"), 3, out);
  args.replace(args.find('F'), 1, file);
  return run_tool(program, args);
}

// Row of /contacts holding the last contact of the last frame of a trajectory.
std::size_t last_contact_row(const std::string& path) {
  io::TrajectoryReader reader(path);
  const io::Frame last = reader.frame(reader.frame_count() - 1);
  EXPECT_GT(last.contacts.size(), 0u) << "the last frame of " << path << " has no contacts";
  std::vector<std::size_t> dims;
  reader.array("/contacts/normal_force", &dims);
  return dims.at(0) - 1;
}

// The first two mobile grains of an incline start.
std::pair<std::size_t, std::size_t> two_mobile_grains(const std::string& path) {
  const io::GrainProperties g = io::TrajectoryReader(path).grains();
  std::vector<std::size_t> mobile;
  for (std::size_t i = 0; i < g.fixed.size() && mobile.size() < 2; ++i)
    if (!g.fixed[i]) mobile.push_back(i);
  EXPECT_EQ(mobile.size(), 2u);
  return {mobile.at(0), mobile.at(1)};
}

// Grain b moved to grain a's centre plus shift (zero: coincident centres) in frame `frame`.
void move_onto(const std::string& path, std::size_t frame, std::size_t a, std::size_t b, Vec2 shift) {
  Vec2 target;
  std::size_t n = 0;
  {
    io::TrajectoryReader reader(path);
    n = reader.grain_count();
    target = reader.frame(frame).position.at(a) + shift;
  }
  poke(path, "/particles/grains/position/value", 2 * (frame * n + b), target.x());
  poke(path, "/particles/grains/position/value", 2 * (frame * n + b) + 1, target.y());
}

struct Crafted {
  std::string name;
  const std::string* source;
  std::function<void(const std::string&)> damage;
  std::vector<std::string> programs;
  std::vector<std::string> expected;  // pieces of the one-line message (besides the file name)
};

void expect_every_program_refuses(const Crafted& c) {
  ScratchDir dir("bad_file_" + c.name);
  ScratchDir out("bad_file_" + c.name + "_out");
  const std::string file = dir / (c.name + ".h5");
  std::filesystem::copy_file(*c.source, file);
  c.damage(file);
  const std::string before = bytes_of(file);
  for (const std::string& program : c.programs) {
    SCOPED_TRACE(program + " on " + c.name);
    const ToolResult r = run_on(program, file, out / "out.h5");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(program + ": error: '" + file + "'"), std::string::npos) << r.err;
    for (const std::string& piece : c.expected) EXPECT_NE(r.err.find(piece), std::string::npos) << r.err;
    EXPECT_EQ(out.entries(), 0) << "output, partial file or checkpoint left behind";
    EXPECT_EQ(bytes_of(file), before) << "the input was changed";
  }
}

const std::string kPosition = "/particles/grains/position/value";
const std::string kVelocity = "/particles/grains/velocity/value";
const std::string kEdges = "/particles/grains/box/edges/value";
const std::string kRadius = "/particles/grains/radius";
const std::string kMass = "/particles/grains/mass";

std::vector<Crafted> crafted_cases() {
  const Sources& s = sources();
  const std::vector<std::string> starts = {"gf-pack", "gf-shear"};
  // gf-xdmf reads no frame's grains, only the per-grain constants and the boxes.
  const std::vector<std::string> constants = {"gf-pack", "gf-shear", "gf-xdmf"};
  const std::vector<std::string> runs = {"gf-shear", "gf-correlate", "gf-kinetic"};
  auto set = [](std::string dataset, std::size_t flat, double value) {
    return [=](const std::string& f) { poke(f, dataset, flat, value); };
  };
  // Frames of the shear run: 4 (steps 0, 100, 200, 300) of 200 grains; the last is read.
  const std::size_t last = 3, n = 200;
  std::vector<Crafted> c = {
      {"coincident",
       &s.packing,
       [](const std::string& f) { move_onto(f, 0, 0, 1, Vec2::Zero()); },
       starts,
       {"grains 0 and 1", "same position"}},
      {"deep_overlap",
       &s.packing,
       [](const std::string& f) {
         const io::GrainProperties g = io::TrajectoryReader(f).grains();
         move_onto(f, 0, 0, 1, Vec2(0.3 * (g.radius[0] + g.radius[1]), 0));
       },
       starts,
       {"grains 0 and 1", "overlap"}},
      {"position_nan", &s.packing, set(kPosition, 2 * 5, kNaN), starts, {kPosition, "grain 5"}},
      {"position_inf", &s.packing, set(kPosition, 2 * 5 + 1, kInf), starts, {kPosition, "grain 5"}},
      {"box_width_nan", &s.packing, set(kEdges, 0, kNaN), constants, {kEdges, "width"}},
      {"box_width_zero", &s.packing, set(kEdges, 0, 0.0), constants, {kEdges, "width"}},
      {"box_width_negative", &s.packing, set(kEdges, 0, -17.0), constants, {kEdges, "width"}},
      {"box_offset_nan", &s.packing, set(kEdges, 2, kNaN), constants, {kEdges, "offset"}},
      {"box_height_zero", &s.packing, set(kEdges, 3, 0.0), constants, {kEdges, "height"}},
      {"box_height_nan", &s.packing, set(kEdges, 3, kNaN), constants, {kEdges, "height"}},
      {"radius_nan", &s.packing, set(kRadius, 3, kNaN), constants, {kRadius, "grain 3"}},
      {"radius_negative", &s.packing, set(kRadius, 3, -0.5), constants, {kRadius, "grain 3"}},
      {"radius_zero", &s.packing, set(kRadius, 3, 0.0), constants, {kRadius, "grain 3"}},
      {"mass_zero", &s.packing, set(kMass, 4, 0.0), constants, {kMass, "grain 4"}},
      {"mass_nan", &s.packing, set(kMass, 4, kNaN), constants, {kMass, "grain 4"}},
      {"velocity_nan", &s.shear, set(kVelocity, 2 * (last * n + 7), kNaN), runs, {kVelocity, "grain 7", "frame 3"}},
      {"normal_force_nan",
       &s.shear,
       [](const std::string& f) { poke(f, "/contacts/normal_force", last_contact_row(f), kNaN); },
       runs,
       {"/contacts/normal_force", "frame 3"}},
      {"normal_force_negative",
       &s.shear,
       [](const std::string& f) { poke(f, "/contacts/normal_force", last_contact_row(f), -1.0); },
       runs,
       {"/contacts/normal_force", "frame 3"}},
      {"tangential_force_inf",
       &s.shear,
       [](const std::string& f) { poke(f, "/contacts/tangential_force", last_contact_row(f), kInf); },
       runs,
       {"/contacts/tangential_force", "frame 3"}},
      {"contact_pair_out_of_range",
       &s.shear,
       [](const std::string& f) { poke(f, "/contacts/pair", 2 * last_contact_row(f) + 1, std::int32_t(100000)); },
       runs,
       {"/contacts/pair", "frame 3"}},
      {"contact_pair_self",
       &s.shear,
       [](const std::string& f) {
         const std::size_t row = last_contact_row(f);
         const io::Frame frame = io::TrajectoryReader(f).frame(last);
         poke(f, "/contacts/pair", 2 * row + 1, frame.contacts.pair.back()[0]);
       },
       runs,
       {"/contacts/pair", "frame 3"}},
      {"contact_age_zero",
       &s.shear,
       [](const std::string& f) { poke(f, "/contacts/age", last_contact_row(f), std::int64_t(0)); },
       {"gf-shear"},
       {"/contacts/age", "frame 3"}},
      {"contact_pairs_reversed",
       &s.shear,
       [](const std::string& f) {
         const std::size_t row = last_contact_row(f);
         const auto pair = io::TrajectoryReader(f).frame(last).contacts.pair.back();
         poke(f, "/contacts/pair", 2 * row, pair[1]);
         poke(f, "/contacts/pair", 2 * row + 1, pair[0]);
       },
       {"gf-shear"},
       {"/contacts/pair", "frame 3", "i < j"}},
      {"shear_run_without_contacts",
       &s.shear,
       [](const std::string& f) { remove_group(f, "/contacts"); },
       {"gf-shear"},
       {"/contacts", "gf-shear"}},
      {"incline_run_without_contacts",
       &s.incline_run,
       [](const std::string& f) { remove_group(f, "/contacts"); },
       {"gf-incline"},
       {"/contacts", "gf-incline"}},
      {"incline_coincident",
       &s.incline,
       [](const std::string& f) {
         const auto [a, b] = two_mobile_grains(f);
         move_onto(f, 0, a, b, Vec2::Zero());
       },
       {"gf-incline"},
       {"same position"}},
      {"incline_radius_nan", &s.incline, set(kRadius, 0, kNaN), {"gf-incline"}, {kRadius, "grain 0"}},
      {"incline_position_nan",
       &s.incline,
       [](const std::string& f) { poke(f, kPosition, 2 * two_mobile_grains(f).first + 1, kNaN); },
       {"gf-incline"},
       {kPosition}},
  };
  return c;
}

class BadFiles : public ::testing::TestWithParam<std::size_t> {};

TEST_P(BadFiles, EveryProgramRefusesWithExitTwoNamingTheFile) {
  expect_every_program_refuses(crafted_cases()[GetParam()]);
}

std::string crafted_name(const ::testing::TestParamInfo<std::size_t>& info) {
  // Names without building the sources (discovery runs the binary with --gtest_list_tests).
  static const char* const names[] = {"coincident",
                                      "deep_overlap",
                                      "position_nan",
                                      "position_inf",
                                      "box_width_nan",
                                      "box_width_zero",
                                      "box_width_negative",
                                      "box_offset_nan",
                                      "box_height_zero",
                                      "box_height_nan",
                                      "radius_nan",
                                      "radius_negative",
                                      "radius_zero",
                                      "mass_zero",
                                      "mass_nan",
                                      "velocity_nan",
                                      "normal_force_nan",
                                      "normal_force_negative",
                                      "tangential_force_inf",
                                      "contact_pair_out_of_range",
                                      "contact_pair_self",
                                      "contact_age_zero",
                                      "contact_pairs_reversed",
                                      "shear_run_without_contacts",
                                      "incline_run_without_contacts",
                                      "incline_coincident",
                                      "incline_radius_nan",
                                      "incline_position_nan"};
  return names[info.param];
}

}  // namespace

INSTANTIATE_TEST_SUITE_P(Crafted, BadFiles, ::testing::Range<std::size_t>(0, 28), crafted_name);

// The sources themselves are accepted by every program (the refusals above are about the
// damage, not the files), and a dense packing whose overlaps are real but bounded still starts.
TEST(BadFilesControl, UndamagedSourcesAreAccepted) {
  const Sources& s = sources();
  ScratchDir out("bad_files_control_out");
  for (const auto& [program, file] : std::vector<std::pair<std::string, std::string>>{{"gf-pack", s.packing},
                                                                                      {"gf-shear", s.packing},
                                                                                      {"gf-pack", s.shear},
                                                                                      {"gf-shear", s.shear},
                                                                                      {"gf-correlate", s.shear},
                                                                                      {"gf-kinetic", s.shear},
                                                                                      {"gf-incline", s.incline},
                                                                                      {"gf-incline", s.incline_run},
                                                                                      {"gf-xdmf", s.packing},
                                                                                      {"gf-xdmf", s.shear},
                                                                                      {"gf-xdmf", s.incline_run}}) {
    const ToolResult r = run_on(program, file, out / "out.h5");
    EXPECT_EQ(r.exit_code, 0) << program << " on " << file << ": " << r.err;
    std::filesystem::remove(out / "out.h5");
  }
}

TEST(BadFilesControl, DensePackingWithResidualOverlapsStarts) {
  ScratchDir dir("bad_files_dense");
  const std::string dense = dir / "dense.h5";
  ASSERT_EQ(run_tool("gf-pack", "--grains 200 --packing-fraction 0.9 --seed 3 --quiet -o " + dense).exit_code, 0);
  // The start is what is tested, not the convergence of a first step from ν = 0.9.
  const ToolResult r =
      run_tool("gf-shear", "-i " + dense + " -o " + (dir / "out.h5") + " --steps 2 --max-unconverged 1 -q");
  EXPECT_EQ(r.exit_code, 0) << r.err;
}
