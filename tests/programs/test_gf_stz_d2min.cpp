// gf-stz d2min as a user runs it, on real gf-pack → gf-shear runs and branches: every grain's
// D²min and F against a test-side brute force over all periodic images (forwards, backwards in
// time, across a branch sheared the other way, over an interval whose Lees–Edwards offset
// wraps); the output's schema; bad input (exit 2, one line, nothing left).
#include <gtest/gtest.h>

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <utility>

#include "core/sha256.hpp"
#include "io/hdf5_handle.hpp"
#include "io/trajectory.hpp"
#include "programs/run_tool.hpp"

using namespace granflow;
using namespace granflow::testing;

namespace {

// A dense packing (ν = 0.8, N = 200) shared by the runs below.
const std::string& dense_packing() {
  return packed_once("d2min_dense", "--grains 200 --packing-fraction 0.8 --seed 7");
}

// The output of `gf-shear ARGS -o <path>`, made once per name.
const std::string& made_once(const std::string& name, const std::string& args) {
  static std::map<std::string, std::pair<std::unique_ptr<ScratchDir>, std::string>> made;
  auto it = made.find(name);
  if (it == made.end()) {
    auto dir = std::make_unique<ScratchDir>("d2min_run_" + name);
    const std::string path = *dir / "run.h5";
    const ToolResult r = run_tool("gf-shear", args + " -o " + path + " --quiet");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    it = made.emplace(name, std::make_pair(std::move(dir), path)).first;
  }
  return it->second.second;
}

// 50 steps to strain 0.05, a frame at every step.
const std::string& every_step_run() {
  return made_once("every_step", "-i " + dense_packing() + " --strain 0.05 --strain-step 1e-3 --frame-every 1");
}
// Frame 20 of it sheared the other way (rate −1) to strain 0.03, a frame every step.
const std::string& backward_branch() {
  return made_once("backward",
                   "-i " + every_step_run() + " --frame 20 --rate -1 --strain 0.03 --strain-step 1e-3 --frame-every 1");
}
// Strain 0.7 at rate 2, a frame every 5 steps: the offset changes by 0.7 Ly > Lx/2 (square box).
const std::string& long_run() {
  return made_once("long", "-i " + dense_packing() + " --rate 2 --strain 0.7 --strain-step 2e-3 --frame-every 5");
}

std::vector<double> read_doubles(const std::string& file, const std::string& dataset) {
  io::File f = io::open_file(file, false);
  io::Dataset d = io::open_dataset(f.get(), dataset);
  return io::read_all<double>(d.get());
}
template <class T>
std::vector<T> read_column(const std::string& file, const std::string& dataset) {
  io::File f = io::open_file(file, false);
  io::Dataset d = io::open_dataset(f.get(), dataset);
  return io::read_all<T>(d.get());
}
double double_attribute(const std::string& file, const std::string& object, const std::string& name) {
  io::File f = io::open_file(file, false);
  io::Group g = io::open_group(f.get(), object);
  io::Attribute a = io::open_attribute(g.get(), name);
  return io::read_double_attribute(a.get());
}

// Unwrapped positions of every grain, followed frame by frame in the test's own way: each
// grain carries image counters (c: rows up, m: columns right), its unwrapped position is
// r + c (δ, Ly) + m Lx with the frame's own offset δ, and from one frame to the next the
// counters change by −1, 0 or +1 each, whichever puts the grain nearest its last place.
struct Follower {
  std::vector<Vec2> unwrapped;
  std::vector<int> c, m;
  explicit Follower(const io::Frame& first) : unwrapped(first.position), c(first.position.size(), 0), m(c) {}
  void next(const io::Frame& f) {
    for (std::size_t i = 0; i < unwrapped.size(); ++i) {
      double best = std::numeric_limits<double>::infinity();
      int bc = 0, bm = 0;
      for (int dc = -1; dc <= 1; ++dc)
        for (int dm = -1; dm <= 1; ++dm) {
          const int cc = c[i] + dc, mm = m[i] + dm;
          const Vec2 r = f.position[i] + Vec2(cc * f.box.offset + mm * f.box.lx, cc * f.box.ly);
          const double d = (r - unwrapped[i]).norm();
          if (d < best) best = d, bc = cc, bm = mm;
        }
      c[i] = bc;
      m[i] = bm;
      unwrapped[i] = f.position[i] + Vec2(bc * f.box.offset + bm * f.box.lx, bc * f.box.ly);
    }
  }
};

struct Expected {
  std::vector<double> value;
  std::vector<int> neighbours;
  std::vector<int> valid;
  std::vector<Mat2> F;
};

// D²min from the definition over all periodic images, O(N²): neighbours of grain i are the
// images (rows −1..1, columns −2..2) of every grain within the cutoff of i in the reference
// frame; a neighbour image in row k moves with the grain and with the offset, k·Δδ.
Expected brute_force(const io::Frame& reference, const std::vector<Vec2>& displacement, double offset_change,
                     double cutoff) {
  const std::size_t n = reference.position.size();
  const Box& box = reference.box;
  Expected e;
  for (std::size_t i = 0; i < n; ++i) {
    Mat2 X = Mat2::Zero(), Y = Mat2::Zero();
    std::vector<std::pair<Vec2, Vec2>> bonds;
    for (std::size_t j = 0; j < n; ++j)
      for (int k = -1; k <= 1; ++k)
        for (int col = -2; col <= 2; ++col) {
          if (j == i && k == 0 && col == 0) continue;
          const Vec2 shift(k * box.offset + col * box.lx, k * box.ly);
          const Vec2 d0 = reference.position[j] + shift - reference.position[i];
          if (!(d0.norm() < cutoff)) continue;
          const Vec2 d = d0 + displacement[j] - displacement[i] + Vec2(k * offset_change, 0);
          bonds.emplace_back(d0, d);
          X += d * d0.transpose();
          Y += d0 * d0.transpose();
        }
    e.neighbours.push_back(int(bonds.size()));
    const double det = Y(0, 0) * Y(1, 1) - Y(0, 1) * Y(1, 0);
    const bool valid = bonds.size() >= 2 && det > 1e-6 * Y.trace() * Y.trace();
    e.valid.push_back(valid);
    if (!valid) {
      e.value.push_back(std::numeric_limits<double>::quiet_NaN());
      e.F.push_back(Mat2::Constant(std::numeric_limits<double>::quiet_NaN()));
      continue;
    }
    Mat2 inverse;
    inverse << Y(1, 1), -Y(0, 1), -Y(1, 0), Y(0, 0);
    const Mat2 F = X * inverse / det;
    double sum = 0;
    for (const auto& [d0, d] : bonds) sum += (d - F * d0).squaredNorm();
    e.value.push_back(sum);
    e.F.push_back(F);
  }
  return e;
}

double mean_diameter(const std::string& path) {
  const std::vector<double> r = io::TrajectoryReader(path).grains().radius;
  double s = 0;
  for (double x : r) s += x;
  return 2 * s / double(r.size());
}

// The program's output against the brute force, grain by grain.
void expect_matches(const std::string& out, const Expected& e) {
  const auto value = read_doubles(out, "/d2min/value");
  const auto per = read_doubles(out, "/d2min/per_neighbour");
  const auto F = read_doubles(out, "/d2min/F");
  const auto neighbours = read_column<std::int32_t>(out, "/d2min/neighbours");
  const auto valid = read_column<std::uint8_t>(out, "/d2min/valid");
  ASSERT_EQ(value.size(), e.value.size());
  ASSERT_EQ(F.size(), 4 * e.value.size());
  int compared = 0;
  double largest = 0;
  for (std::size_t i = 0; i < e.value.size(); ++i) {
    SCOPED_TRACE("grain " + std::to_string(i));
    ASSERT_EQ(neighbours[i], e.neighbours[i]);
    ASSERT_EQ(int(valid[i]), e.valid[i]);
    if (!e.valid[i]) {
      EXPECT_TRUE(std::isnan(value[i]) && std::isnan(per[i]) && std::isnan(F[4 * i]));
      continue;
    }
    ++compared;
    largest = std::max(largest, e.value[i]);
    EXPECT_NEAR(value[i], e.value[i], 1e-10 * e.value[i]);
    EXPECT_NEAR(per[i], e.value[i] / e.neighbours[i], 1e-10 * e.value[i] / e.neighbours[i]);
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        EXPECT_NEAR(F[4 * i + std::size_t(2 * a + b)], e.F[i](a, b), 1e-10 * std::max(1.0, std::abs(e.F[i](a, b))));
  }
  EXPECT_GT(compared, int(e.value.size()) * 9 / 10) << "most grains of a dense packing have a D2min";
  EXPECT_GT(largest, 1e-6) << "no non-affine motion: the comparison shows nothing";
}

// The displacement from frame a to frame b of one file (b < a: backwards), followed frame by
// frame, and the offset change from the rate and the times.
std::pair<std::vector<Vec2>, double> followed(const std::string& path, std::size_t a, std::size_t b) {
  io::TrajectoryReader reader(path);
  const std::size_t lo = std::min(a, b), hi = std::max(a, b);
  const io::Frame first = reader.frame(lo);
  Follower f(first);
  io::Frame last = first;
  for (std::size_t k = lo + 1; k <= hi; ++k) {
    last = reader.frame(k);
    f.next(last);
  }
  std::vector<Vec2> u(first.position.size());
  for (std::size_t i = 0; i < u.size(); ++i) u[i] = f.unwrapped[i] - first.position[i];
  double dd = reader.lees_edwards_rate() * first.box.ly * (last.time - first.time);
  if (b < a) {
    for (Vec2& x : u) x = -x;
    dd = -dd;
  }
  return {u, dd};
}

}  // namespace

TEST(GfStzD2min, AgreesWithBruteForceOverAllImagesForwardsAndBackwards) {
  const std::string& run = every_step_run();
  ScratchDir dir("d2min_brute");
  const double cutoff = 2 * mean_diameter(run);
  const io::Frame reference0 = io::TrajectoryReader(run).frame(0);
  const io::Frame reference50 = io::TrajectoryReader(run).frame(50);
  struct Case {
    std::string frames;
    std::size_t a, b;
    const io::Frame* reference;
  };
  for (const Case& c :
       {Case{"0 -1", 0, 50, &reference0}, Case{"-1,0", 50, 0, &reference50}, Case{"0 17", 0, 17, &reference0}}) {
    SCOPED_TRACE("--frames " + c.frames);
    const std::string out = dir / "out.h5";
    const ToolResult r = run_tool("gf-stz", "d2min -i " + run + " --frames " + c.frames + " -o " + out + " -q");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto [u, dd] = followed(run, c.a, c.b);
    expect_matches(out, brute_force(*c.reference, u, dd, cutoff));
    EXPECT_NEAR(double_attribute(out, "/d2min", "offset_change"), dd, 1e-12 * c.reference->box.lx);
    EXPECT_EQ(double_attribute(out, "/d2min", "reference_time"), io::TrajectoryReader(run).frame(c.a).time);
    EXPECT_EQ(double_attribute(out, "/d2min", "current_time"), io::TrajectoryReader(run).frame(c.b).time);
    std::filesystem::remove(out);
  }
}

TEST(GfStzD2min, AgreesWithBruteForceAcrossABranchShearedTheOtherWay) {
  const std::string& run = every_step_run();
  const std::string& branch = backward_branch();
  ScratchDir dir("d2min_branch");
  const std::string out = dir / "out.h5";
  const ToolResult r = run_tool("gf-stz", "d2min -i " + run + " --frames 20 -1 --branch " + branch + " -o " + out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("strain -0.03"), std::string::npos) << r.err;

  // The branch's frame 0 is frame 20 of the run; the test follows the branch's frames.
  const io::Frame reference = io::TrajectoryReader(run).frame(20);
  io::TrajectoryReader b(branch);
  ASSERT_LT(b.lees_edwards_rate(), 0);
  Follower f(reference);
  io::Frame last = reference;
  bool offset_crosses_zero = false;
  for (std::size_t k = 1; k < b.frame_count(); ++k) {
    const double before = last.box.offset;
    f.next(last = b.frame(k));
    // The offset returns to 0 from above at the branch's frame 20 (round-off leaves it a hair
    // below 0 before it is wrapped): it must be stored inside [0, Lx), as the format says.
    EXPECT_GE(last.box.offset, 0) << "frame " << k;
    EXPECT_LT(last.box.offset, last.box.lx) << "frame " << k;
    offset_crosses_zero = offset_crosses_zero || last.box.offset > before;
  }
  EXPECT_TRUE(offset_crosses_zero) << "the branch's offset never wraps through 0: that case is not covered";
  std::vector<Vec2> u(reference.position.size());
  for (std::size_t i = 0; i < u.size(); ++i) u[i] = f.unwrapped[i] - reference.position[i];
  const double dd = b.lees_edwards_rate() * reference.box.ly * (last.time - b.frame(0).time);
  EXPECT_LT(dd, 0);
  expect_matches(out, brute_force(reference, u, dd, 2 * mean_diameter(run)));
  EXPECT_NEAR(double_attribute(out, "/d2min", "strain"), dd / reference.box.ly, 1e-12);
}

TEST(GfStzD2min, AgreesWithBruteForceOverAWrappedOffset) {
  const std::string& run = long_run();
  ScratchDir dir("d2min_wrapped");
  const std::string out = dir / "out.h5";
  const ToolResult r = run_tool("gf-stz", "d2min -i " + run + " --frames 0 -1 -o " + out + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  io::TrajectoryReader reader(run);
  const io::Frame reference = reader.frame(0);
  const auto [u, dd] = followed(run, 0, reader.frame_count() - 1);
  ASSERT_GT(dd, 0.5 * reference.box.lx) << "the offset does not wrap past Lx/2: the test shows nothing";
  EXPECT_NEAR(double_attribute(out, "/d2min", "offset_change"), dd, 1e-9 * reference.box.lx);
  expect_matches(out, brute_force(reference, u, dd, 2 * mean_diameter(run)));
}

TEST(GfStzD2min, SameFrameTwiceGivesZeroAndIdentity) {
  const std::string& run = every_step_run();
  ScratchDir dir("d2min_same");
  const std::string out = dir / "out.h5";
  ASSERT_EQ(run_tool("gf-stz", "d2min -i " + run + " --frames 7 7 -o " + out + " -q").exit_code, 0);
  const auto value = read_doubles(out, "/d2min/value");
  const auto F = read_doubles(out, "/d2min/F");
  const auto valid = read_column<std::uint8_t>(out, "/d2min/valid");
  for (std::size_t i = 0; i < value.size(); ++i) {
    if (!valid[i]) continue;
    EXPECT_LT(value[i], 1e-24);
    EXPECT_NEAR(F[4 * i], 1, 1e-12);
    EXPECT_NEAR(F[4 * i + 1], 0, 1e-12);
    EXPECT_NEAR(F[4 * i + 2], 0, 1e-12);
    EXPECT_NEAR(F[4 * i + 3], 1, 1e-12);
  }
}

// Every dataset and attribute of the format, with its type and shape.
TEST(GfStzD2min, OutputHasTheDocumentedSchemaAndProvenance) {
  const std::string& run = every_step_run();
  const std::string& branch = backward_branch();
  ScratchDir dir("d2min_schema");
  const std::string out = dir / "out.h5";
  ASSERT_EQ(
      run_tool("gf-stz", "d2min -i " + run + " --frames 20 5 --branch " + branch + " --cutoff 1.5 -o " + out + " -q")
          .exit_code,
      0);
  io::File f = io::open_file(out, false);
  const std::size_t n = 200;
  auto dataset = [&](const std::string& path, H5T_class_t type_class, std::size_t bytes,
                     const std::vector<hsize_t>& shape) {
    SCOPED_TRACE(path);
    ASSERT_TRUE(io::exists(f.get(), path));
    io::Dataset d = io::open_dataset(f.get(), path);
    io::Datatype t(H5Dget_type(d.get()));
    EXPECT_EQ(H5Tget_class(t.get()), type_class);
    EXPECT_EQ(H5Tget_size(t.get()), bytes);
    EXPECT_EQ(io::shape(d.get()), shape);
    EXPECT_TRUE(io::has_attribute(d.get(), "meaning"));
    EXPECT_TRUE(io::has_attribute(d.get(), "units"));
  };
  dataset("/d2min/value", H5T_FLOAT, 8, {n});
  dataset("/d2min/per_neighbour", H5T_FLOAT, 8, {n});
  dataset("/d2min/neighbours", H5T_INTEGER, 4, {n});
  dataset("/d2min/valid", H5T_INTEGER, 1, {n});
  dataset("/d2min/F", H5T_FLOAT, 8, {n, 2, 2});
  dataset("/reference/position", H5T_FLOAT, 8, {n, 2});
  dataset("/reference/radius", H5T_FLOAT, 8, {n});

  auto attribute = [&](const std::string& object, const std::string& name, H5T_class_t type_class,
                       std::size_t elements = 1) {
    SCOPED_TRACE(object + " " + name);
    io::Group g = io::open_group(f.get(), object);
    ASSERT_TRUE(io::has_attribute(g.get(), name));
    io::Attribute a = io::open_attribute(g.get(), name);
    EXPECT_EQ(io::attribute_class(a.get()), type_class);
    hsize_t count = 1;
    for (hsize_t d : io::shape(a.get())) count *= d;
    EXPECT_EQ(count, elements);
  };
  for (const char* name :
       {"cutoff", "cutoff_diameters", "mean_diameter", "reference_time", "current_time", "strain", "offset_change"})
    attribute("/d2min", name, H5T_FLOAT);
  for (const char* name : {"reference_frame", "current_frame", "valid_count"}) attribute("/d2min", name, H5T_INTEGER);
  attribute("/d2min", "current_source", H5T_STRING);
  attribute("/reference", "box", H5T_FLOAT, 2);
  attribute("/reference", "offset", H5T_FLOAT);
  for (const char* name :
       {"program", "command", "command_line", "version", "input", "input_sha256", "branch", "branch_sha256", "frames"})
    attribute("/parameters", name, H5T_STRING);
  attribute("/parameters", "cutoff", H5T_FLOAT);

  // The values that identify the run, the frames and the branch.
  auto text = [&](const std::string& object, const std::string& name) {
    io::Group g = io::open_group(f.get(), object);
    io::Attribute a = io::open_attribute(g.get(), name);
    return io::read_string_attribute(a.get());
  };
  auto integer = [&](const std::string& object, const std::string& name) {
    io::Group g = io::open_group(f.get(), object);
    io::Attribute a = io::open_attribute(g.get(), name);
    return io::read_int_attribute(a.get());
  };
  EXPECT_EQ(text("/parameters", "program"), "gf-stz");
  EXPECT_EQ(text("/parameters", "command"), "d2min");
  EXPECT_EQ(text("/parameters", "frames"), "20,5");
  EXPECT_EQ(text("/parameters", "input_sha256"), sha256_file(run));
  EXPECT_EQ(text("/parameters", "branch_sha256"), sha256_file(branch));
  EXPECT_EQ(text("/parameters", "command_line").rfind("gf-stz d2min ", 0), 0u);
  EXPECT_EQ(text("/d2min", "current_source"), "branch");
  EXPECT_EQ(integer("/d2min", "reference_frame"), 20);
  EXPECT_EQ(integer("/d2min", "current_frame"), 5);
  const auto valid = read_column<std::uint8_t>(out, "/d2min/valid");
  EXPECT_EQ(integer("/d2min", "valid_count"), std::count(valid.begin(), valid.end(), std::uint8_t(1)));
  EXPECT_EQ(double_attribute(out, "/d2min", "cutoff_diameters"), 1.5);
  EXPECT_NEAR(double_attribute(out, "/d2min", "mean_diameter"), mean_diameter(run), 1e-12);
  EXPECT_NEAR(double_attribute(out, "/d2min", "cutoff"), 1.5 * mean_diameter(run), 1e-12);
  const io::Frame reference = io::TrajectoryReader(run).frame(20);
  EXPECT_EQ(double_attribute(out, "/d2min", "reference_time"), reference.time);
  EXPECT_EQ(double_attribute(out, "/d2min", "current_time"), io::TrajectoryReader(branch).frame(5).time);
  EXPECT_EQ(double_attribute(out, "/reference", "offset"), reference.box.offset);
  {
    io::Group g = io::open_group(f.get(), "/reference");
    io::Attribute a = io::open_attribute(g.get(), "box");
    double box[2] = {0, 0};
    ASSERT_GE(H5Aread(a.get(), H5T_NATIVE_DOUBLE, box), 0);
    EXPECT_EQ(box[0], reference.box.lx);
    EXPECT_EQ(box[1], reference.box.ly);
  }
  const auto position = read_doubles(out, "/reference/position");
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_EQ(position[2 * i], reference.position[i].x());
    EXPECT_EQ(position[2 * i + 1], reference.position[i].y());
  }
}

namespace {

// Element `flat` (row-major) of a dataset of doubles, overwritten in place.
void poke(const std::string& path, const std::string& dataset, std::size_t flat, double value) {
  io::File file = io::open_file(path, true);
  io::Dataset d = io::open_dataset(file.get(), dataset);
  std::vector<double> all = io::read_all<double>(d.get());
  ASSERT_LT(flat, all.size()) << dataset;
  all[flat] = value;
  ASSERT_GE(H5Dwrite(d.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, all.data()), 0) << dataset;
}

// Inputs of the refusals, made once: the runs above, damaged copies of them, other files.
struct BadSources {
  ScratchDir dir{"d2min_bad_sources"};
  std::string run, branch, other_branch, moved, other_radii, nan_frame, truncated, text, table, incline_run, existing;
  BadSources() {
    run = every_step_run();
    branch = backward_branch();
    // A branch of another run (the long one), from its frame 3.
    other_branch = dir / "other_branch.h5";
    EXPECT_EQ(
        run_tool("gf-shear", "-i " + long_run() + " --frame 3 --strain 0.003 --strain-step 1e-3 -q -o " + other_branch)
            .exit_code,
        0);
    const std::size_t n = 200;
    // The branch with grain 5 moved in its frame 0, and with grain 3's radius changed.
    moved = dir / "moved.h5";
    std::filesystem::copy_file(branch, moved);
    poke(moved, "/particles/grains/position/value", 2 * 5,
         io::TrajectoryReader(branch).frame(0).position[5].x() + 1e-9);
    other_radii = dir / "other_radii.h5";
    std::filesystem::copy_file(branch, other_radii);
    poke(other_radii, "/particles/grains/radius", 3, 1.01 * io::TrajectoryReader(branch).grains().radius[3]);
    // The run with a NaN position in frame 10, between the frames compared.
    nan_frame = dir / "nan_frame.h5";
    std::filesystem::copy_file(run, nan_frame);
    poke(nan_frame, "/particles/grains/position/value", 2 * (10 * n + 5), std::numeric_limits<double>::quiet_NaN());
    truncated = dir / "truncated.h5";
    {
      std::ifstream in(run, std::ios::binary);
      std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      std::ofstream(truncated, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    }
    text = dir / "text.h5";
    std::ofstream(text) << "not a trajectory\n";
    // An HDF5 file of another schema: a gf-stz d2min output.
    table = dir / "table.h5";
    EXPECT_EQ(run_tool("gf-stz", "d2min -i " + run + " --frames 0 1 -q -o " + table).exit_code, 0);
    const std::string incline = dir / "incline.h5";
    incline_run = dir / "incline_run.h5";
    EXPECT_EQ(run_tool("gf-pack", "--incline --width 10 --height 5 --seed 3 --quiet -o " + incline).exit_code, 0);
    EXPECT_EQ(run_tool("gf-incline", "-i " + incline + " -o " + incline_run +
                                         " --angle 20 --steps 40 --profile-block 20 --frame-every 20 --quiet")
                  .exit_code,
              0);
    existing = dir / "existing.h5";
    std::ofstream(existing) << "a previous output\n";
  }
};

const BadSources& bad_sources() {
  static BadSources s;
  return s;
}

std::vector<std::pair<std::string, std::string>> bad_values() {
  const BadSources& s = bad_sources();
  return {{"{run}", s.run},
          {"{branch}", s.branch},
          {"{other_branch}", s.other_branch},
          {"{moved}", s.moved},
          {"{other_radii}", s.other_radii},
          {"{nan_frame}", s.nan_frame},
          {"{truncated}", s.truncated},
          {"{text}", s.text},
          {"{table}", s.table},
          {"{incline}", s.incline_run},
          {"{existing}", s.existing},
          {"{pack}", dense_packing()}};
}

class GfStzD2minBadInput : public ::testing::TestWithParam<BadInput> {};

TEST_P(GfStzD2minBadInput, RefusedWithExitTwoAndNothingLeft) {
  expect_refused("gf-stz", GetParam(), bad_values(), " -q");
}

INSTANTIATE_TEST_SUITE_P(
    Cases, GfStzD2minBadInput,
    ::testing::Values(
        BadInput{"frame_out_of_range", "d2min -i {run} --frames 0 51 -o {out}", "--frames: "},
        BadInput{"negative_frame_out_of_range", "d2min -i {run} --frames -52 0 -o {out}", "frame -52 is out of range"},
        BadInput{"branch_frame_out_of_range", "d2min -i {run} --frames 20 31 --branch {branch} -o {out}",
                 "frame 31 is out of range"},
        BadInput{"reference_frame_out_of_range_with_branch", "d2min -i {run} --frames 51 0 --branch {branch} -o {out}",
                 "frame 51 is out of range"},
        BadInput{"branch_of_another_run", "d2min -i {run} --frames 3 -1 --branch {other_branch} -o {out}",
                 "it started from another file"},
        BadInput{"branch_of_another_frame", "d2min -i {run} --frames 10 -1 --branch {branch} -o {out}",
                 "it started from frame 20"},
        BadInput{"branch_frame_zero_differs", "d2min -i {run} --frames 20 -1 --branch {moved} -o {out}",
                 "grain 5 is elsewhere in its frame 0"},
        BadInput{"branch_of_other_grains", "d2min -i {run} --frames 20 -1 --branch {other_radii} -o {out}",
                 "not the same grains"},
        BadInput{"branch_is_a_packing", "d2min -i {run} --frames 0 0 --branch {pack} -o {out}", "is a packing"},
        BadInput{"trajectory_is_a_packing", "d2min -i {pack} --frames 0 0 -o {out}", "is a packing"},
        BadInput{"trajectory_is_an_incline_run", "d2min -i {incline} --frames 0 1 -o {out}", "incline_run.h5"},
        BadInput{"nan_position_between_the_frames", "d2min -i {nan_frame} --frames 0 20 -o {out}", "grain 5"},
        BadInput{"missing_file", "d2min -i {out}.missing --frames 0 1 -o {out}", "missing"},
        BadInput{"missing_branch", "d2min -i {run} --frames 20 1 --branch {out}.missing -o {out}", "missing"},
        BadInput{"truncated_file", "d2min -i {truncated} --frames 0 1 -o {out}", "truncated.h5"},
        BadInput{"not_hdf5", "d2min -i {text} --frames 0 1 -o {out}", "text.h5"},
        BadInput{"wrong_schema", "d2min -i {table} --frames 0 1 -o {out}", "table.h5"},
        BadInput{"one_frame", "d2min -i {run} --frames 0 -o {out}", "--frames"},
        BadInput{"three_frames", "d2min -i {run} --frames 0,1,2 -o {out}", "--frames"},
        BadInput{"frame_not_a_number", "d2min -i {run} --frames 0,b -o {out}", "--frames"},
        BadInput{"no_frames", "d2min -i {run} -o {out}", "--frames"},
        BadInput{"no_input", "d2min --frames 0 1 -o {out}", "--input"},
        BadInput{"no_output", "d2min -i {run} --frames 0 1", "--output"},
        BadInput{"cutoff_zero", "d2min -i {run} --frames 0 1 --cutoff 0 -o {out}", "--cutoff"},
        BadInput{"cutoff_negative", "d2min -i {run} --frames 0 1 --cutoff -1 -o {out}", "--cutoff"},
        BadInput{"cutoff_past_half_the_box", "d2min -i {run} --frames 0 1 --cutoff 8 -o {out}", "--cutoff"},
        BadInput{"unknown_option", "d2min -i {run} --frames 0 1 -o {out} --bogus", "--bogus"},
        BadInput{"output_is_the_trajectory", "d2min -i {run} --frames 0 1 -o {run}", "--output"},
        BadInput{"output_is_the_branch", "d2min -i {run} --frames 20 1 --branch {branch} -o {branch}", "--output"},
        BadInput{"existing_output_untouched", "d2min -i {pack} --frames 0 0 -o {existing}", "is a packing"}),
    bad_input_name);

// The same commands with good inputs are accepted: the refusals are about what was changed.
TEST(GfStzD2minBadInputControl, GoodInputsAreAccepted) {
  const BadSources& s = bad_sources();
  ScratchDir dir("d2min_control");
  for (const std::string& args : {"-i " + s.run + " --frames 0 50", "-i " + s.run + " --frames -51 0",
                                  "-i " + s.run + " --frames 20 30 --branch " + s.branch,
                                  "-i " + s.run + " --frames 20 -1 --branch " + s.branch + " --cutoff 1.2",
                                  "-i " + s.run + " --frames=-1 -2", "-i " + s.run + " --frames=0,1"}) {
    SCOPED_TRACE(args);
    const ToolResult r = run_tool("gf-stz", "d2min " + args + " -q -o " + (dir / "out.h5"));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    std::filesystem::remove(dir / "out.h5");
  }
}

}  // namespace
