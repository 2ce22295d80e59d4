// gf-network as a user runs it, on real gf-pack → gf-shear (→ gf-correlate) chains: the
// long-lived coordination against the two-frame intersection of the stored contacts, the
// collisional identity s^bc/p^bc = −2χ12, the prediction columns against network::predict of
// the stored ingredients, the matching of a correlation table, and bad input (exit 2, one
// line, nothing left).
#include <gtest/gtest.h>

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <utility>

#include "io/hdf5_handle.hpp"
#include "io/trajectory.hpp"
#include "network/network.hpp"
#include "programs/run_tool.hpp"

using namespace granflow;
using namespace granflow::testing;

namespace {

std::vector<double> read_doubles(const std::string& file, const std::string& dataset) {
  io::File f = io::open_file(file, false);
  io::Dataset d = io::open_dataset(f.get(), dataset);
  return io::read_all<double>(d.get());
}

std::vector<std::int32_t> read_ints(const std::string& file, const std::string& dataset) {
  io::File f = io::open_file(file, false);
  io::Dataset d = io::open_dataset(f.get(), dataset);
  return io::read_all<std::int32_t>(d.get());
}

// A dense packing (ν = 0.8, N = 200) shared by the runs below.
const std::string& dense_packing() {
  return packed_once("network_dense", "--grains 200 --packing-fraction 0.8 --seed 5");
}

// The output of `gf-shear -i dense_packing() ARGS`, made once per name.
const std::string& sheared_once(const std::string& name, const std::string& args) {
  static std::map<std::string, std::pair<std::unique_ptr<ScratchDir>, std::string>> made;
  auto it = made.find(name);
  if (it == made.end()) {
    auto dir = std::make_unique<ScratchDir>("network_run_" + name);
    const std::string path = *dir / "run.h5";
    EXPECT_EQ(run_tool("gf-shear", "-i " + dense_packing() + " -o " + path + " " + args + " --quiet").exit_code, 0);
    it = made.emplace(name, std::make_pair(std::move(dir), path)).first;
  }
  return it->second.second;
}

// 50 steps, a frame at every step: every frame's predecessor is stored.
const std::string& every_step_run() {
  return sheared_once("every_step", "--strain 0.05 --strain-step 1e-3 --frame-every 1");
}
// 1000 steps to strain 2, a frame every 5 steps (window from strain 0.5: 151 frames).
const std::string& steady_run() { return sheared_once("steady", "--strain 2 --strain-step 2e-3 --frame-every 5"); }
// Frames at steps 0, 40 and 50 only.
const std::string& sparse_run() { return sheared_once("sparse", "--strain 0.05 --strain-step 1e-3 --frame-every 40"); }

using PairSet = std::set<std::pair<std::int32_t, std::int32_t>>;

PairSet pairs_of(const ContactRecords& c) {
  PairSet s;
  for (const auto& p : c.pair) s.insert({p[0], p[1]});
  return s;
}

}  // namespace

TEST(GfNetwork, CoordinationCountsTheContactsOfTwoConsecutiveFramesOnce) {
  const std::string& run = every_step_run();
  ScratchDir dir("network_coordination");
  const std::string out = dir / "out.h5";
  // The window starts at step 10 (strain 0.01): every frame in it has its predecessor.
  auto r = run_tool("gf-network", run + " -o " + out + " --from-strain 0.01 --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;

  io::TrajectoryReader reader(run);
  const std::vector<std::int64_t> steps = reader.frame_steps();
  ASSERT_EQ(steps.size(), 51u);
  const double n = double(reader.grain_count());
  double counted = 0, frames = 0;
  bool crossing = false;
  io::Frame previous = reader.frame(1);
  for (std::size_t k = 2; k < steps.size(); ++k) {
    ASSERT_EQ(steps[k], steps[k - 1] + 1);
    const io::Frame frame = reader.frame(k);
    PairSet long_lived;
    for (std::size_t c = 0; c < frame.contacts.size(); ++c)
      if (frame.contacts.age[c] >= 2) long_lived.insert({frame.contacts.pair[c][0], frame.contacts.pair[c][1]});
    const PairSet now = pairs_of(frame.contacts), before = pairs_of(previous.contacts);
    ASSERT_EQ(now.size(), frame.contacts.size()) << "frame " << k << ": a pair stored twice";
    PairSet both;
    std::set_intersection(now.begin(), now.end(), before.begin(), before.end(), std::inserter(both, both.end()));
    EXPECT_EQ(long_lived, both) << "frame " << k << ": age >= 2 is not 'in contact in this step and the previous'";
    if (steps[k] >= 10) {
      counted += double(both.size());
      frames += 1;
      for (const auto& [i, j] : both)
        if (std::fabs(frame.position[std::size_t(i)].y() - frame.position[std::size_t(j)].y()) > 0.5 * frame.box.ly)
          crossing = true;
    }
    previous = frame;
  }
  EXPECT_TRUE(crossing) << "no long-lived contact across the Lees-Edwards boundary: the test shows nothing";
  EXPECT_EQ(read_ints(out, "/runs/frames")[0], std::int32_t(frames));
  EXPECT_NEAR(read_doubles(out, "/runs/long_lived")[0], counted / frames, 1e-12 * counted);
  EXPECT_NEAR(read_doubles(out, "/runs/coordination")[0], 2 * counted / (n * frames), 1e-12);
}

// --contact-gap against consecutive stored frames: a contact is a pair within the gap at a
// frame's positions (brute force over all pairs, minimum image), long-lived when within it in
// the frame of the step before too; gf-network takes the step before from the frame alone.
TEST(GfNetwork, GeometricContactsMatchConsecutiveFrames) {
  const std::string& run = every_step_run();
  ScratchDir dir("network_geometric");
  io::TrajectoryReader reader(run);
  const std::vector<double> radius = reader.grains().radius;
  double mean_diameter = 0;
  for (double r : radius) mean_diameter += 2 * r / double(radius.size());
  for (const double h : {1e-4, 1e-2}) {
    const std::string out = dir / ("out" + std::to_string(h) + ".h5");
    auto r = run_tool("gf-network", run + " -o " + out + " --from-strain 0.01 --contact-gap " + std::to_string(h) +
                                        " --quiet");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const double gap = h * mean_diameter;
    auto within = [&](const io::Frame& f) {
      PairSet s;
      for (std::size_t i = 0; i < radius.size(); ++i)
        for (std::size_t j = i + 1; j < radius.size(); ++j)
          if (f.box.minimum_image(f.position[i] - f.position[j]).norm() - radius[i] - radius[j] <= gap)
            s.insert({std::int32_t(i), std::int32_t(j)});
      return s;
    };
    const std::vector<std::int64_t> steps = reader.frame_steps();
    double contacts = 0, long_lived = 0, frames = 0;
    PairSet before = within(reader.frame(9));
    for (std::size_t k = 10; k < steps.size(); ++k) {
      ASSERT_EQ(steps[k], steps[k - 1] + 1);
      const PairSet now = within(reader.frame(k));
      PairSet both;
      std::set_intersection(now.begin(), now.end(), before.begin(), before.end(), std::inserter(both, both.end()));
      contacts += double(now.size());
      long_lived += double(both.size());
      frames += 1;
      before = now;
    }
    EXPECT_GT(long_lived, 0) << "no geometric contact lasts: the test shows nothing";
    EXPECT_EQ(read_ints(out, "/runs/frames")[0], std::int32_t(frames));
    EXPECT_NEAR(read_doubles(out, "/runs/contacts")[0], contacts / frames, 1e-12 * contacts);
    EXPECT_NEAR(read_doubles(out, "/runs/long_lived")[0], long_lived / frames, 1e-12 * long_lived);
  }
}

// A dilute flow may hold no long-lived contact at all: that is a measurement (z = 0), not bad
// input; what needs such contacts is NaN, the stresses are still measured.
TEST(GfNetwork, RunWithoutLongLivedContactsHasZeroCoordinationAndNaNDeflections) {
  ScratchDir dir("network_newborn");
  const std::string newborn = dir / "newborn.h5", out = dir / "out.h5";
  std::filesystem::copy_file(every_step_run(), newborn);
  {
    io::File f = io::open_file(newborn, true);
    io::Dataset age = io::open_dataset(f.get(), "/contacts/age");
    const std::vector<std::int64_t> ones(io::shape(age.get())[0], 1);
    ASSERT_GE(H5Dwrite(age.get(), H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, ones.data()), 0);
  }
  const ToolResult r = run_tool("gf-network", newborn + " -o " + out + " --from-strain 0 --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_doubles(out, "/runs/coordination")[0], 0.0);
  EXPECT_GT(read_doubles(out, "/runs/contacts")[0], 0.0);
  for (const char* name : {"/runs/coordination_active", "/runs/Phi", "/runs/Psi", "/runs/mean_cos_deflection"})
    EXPECT_TRUE(std::isnan(read_doubles(out, name)[0])) << name;
  EXPECT_TRUE(std::isfinite(read_doubles(out, "/runs/a_c")[0]));
  EXPECT_TRUE(std::isfinite(read_doubles(out, "/prediction/lhs_pressure")[0]));
}

// More angle bins than a short run fills: an empty bin has no F_bc(θ) (NaN), the others keep
// theirs, normalised by the average over the filled bins.
TEST(GfNetwork, EmptyAngleBinLeavesTheOtherBinsOfTheForceHistogram) {
  ScratchDir dir("network_empty_bin");
  const std::string out = dir / "out.h5";
  const ToolResult r =
      run_tool("gf-network", every_step_run() + " -o " + out + " --from-strain 0.04 --angle-bins 2000 --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<double> C = read_doubles(out, "/histograms/C"), F = read_doubles(out, "/histograms/binary_force");
  ASSERT_EQ(C.size(), F.size());
  std::size_t empty = 0, filled = 0;
  double average = 0;
  for (std::size_t k = 0; k < C.size(); ++k) {
    if (C[k] == 0) {
      ++empty;
      EXPECT_TRUE(std::isnan(F[k])) << k;
    } else {
      ++filled;
      ASSERT_TRUE(std::isfinite(F[k])) << k;
      average += F[k];
    }
  }
  ASSERT_GT(empty, 0u) << "every bin holds a contact: the test shows nothing";
  EXPECT_NEAR(average / double(filled), 1.0, 1e-12);
}

TEST(GfNetwork, CollisionalShearRatioIsTwiceTheForceFabric) {
  const std::string& run = steady_run();
  ScratchDir dir("network_identity");
  const std::string out = dir / "out.h5";
  auto r = run_tool("gf-network", run + " -o " + out + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto v = [&](const char* name) { return read_doubles(out, std::string("/runs/") + name)[0]; };
  const double rows = v("shear_ratio_collisional"), rows_error = v("shear_ratio_collisional_error");
  const double frames = v("shear_ratio_collisional_frames"), frames_error = v("shear_ratio_collisional_frames_error");
  const double chi = -2 * v("chi_12"), chi_error = 2 * v("chi_12_error");
  // The identity needs σ(θ) constant: here the mean branch length varies by a few per cent
  // over the angle bins.
  EXPECT_LT(v("sigma_max_deviation"), 0.1);
  ASSERT_GT(rows, 0.05) << "a sheared run has s^bc > 0";
  EXPECT_GT(rows_error, 0);
  EXPECT_GT(chi_error, 0);
  EXPECT_NEAR(rows, chi, 3 * std::hypot(rows_error, chi_error)) << "s^bc/p^bc from the rows against -2 chi_12";
  EXPECT_NEAR(rows, frames, 3 * std::hypot(rows_error, frames_error)) << "rows against frames";
}

TEST(GfNetwork, PredictionColumnsAreThoseOfTheStoredIngredients) {
  const std::string& run = steady_run();
  const std::string& other = every_step_run();
  ScratchDir dir("network_prediction");
  const std::string table = dir / "correlation.h5", out = dir / "out.h5";
  auto r =
      run_tool("gf-correlate", run + " " + other + " -o " + table + " --reference " + run + " --from-strain 0 --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // The runs in the other order than the table's: matched by their files' sha256.
  r = run_tool("gf-network",
               other + " " + run + " -o " + out + " --correlation " + table + " --from-strain 0.01 --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<double> table_xi = read_doubles(table, "/correlation/xi_abs_ratio");
  const std::vector<double> table_xi_error = read_doubles(table, "/correlation/xi_abs_ratio_error");
  const std::vector<std::int32_t> table_measurable = read_ints(table, "/correlation/measurable");
  const std::vector<double> xi = read_doubles(out, "/prediction/xi_ratio");
  ASSERT_EQ(xi.size(), 2u);
  EXPECT_EQ(xi[0], table_xi[1]);
  EXPECT_EQ(xi[1], table_xi[0]);
  EXPECT_EQ(read_doubles(out, "/prediction/xi_ratio_error")[0], table_xi_error[1]);
  EXPECT_EQ(read_ints(out, "/prediction/xi_measurable")[1], table_measurable[0]);
  ASSERT_GT(std::fabs(xi[0] - 1), 0.1) << "a limit of the sums away from 0 tests more";

  auto col = [&](const std::string& name) {
    return read_doubles(out, (name.rfind("rhs", 0) == 0 || name.rfind("xi", 0) == 0 || name == "network_factor" ||
                                      name == "path_factor" || name == "sum_limit"
                                  ? "/prediction/"
                                  : "/runs/") +
                                 name);
  };
  const auto z = col("coordination"), z_active = col("coordination_active"), Phi = col("Phi"), Psi = col("Psi");
  const auto cos1 = col("mean_cos_deflection"), cos2 = col("mean_cos_cos2_deflection");
  const auto ac = col("a_c"), acp = col("a_c_prime"), af = col("a_f"), afp = col("a_f_prime");
  const auto continuation = read_ints(out, "/prediction/continuation_real");
  auto close = [](double a, double b) { return std::fabs(a - b) <= 1e-9 * std::max(1.0, std::fabs(b)); };
  for (std::size_t i = 0; i < 2; ++i) {
    using network::SumLimit;
    const std::pair<const char*, network::Prediction> readings[] = {
        {"", network::predict(z[i], Phi[i], Psi[i], ac[i], acp[i], af[i], afp[i], xi[i], SumLimit::continuation)},
        {"_floor", network::predict(z[i], Phi[i], Psi[i], ac[i], acp[i], af[i], afp[i], xi[i], SumLimit::floor)},
        {"_active",
         network::predict(z_active[i], Phi[i], Psi[i], ac[i], acp[i], af[i], afp[i], xi[i], SumLimit::continuation)},
        {"_unit",
         network::predict(z[i], cos1[i], cos2[i], ac[i], acp[i], af[i], afp[i], xi[i], SumLimit::continuation)}};
    for (const auto& [suffix, p] : readings) {
      const std::string s = suffix;
      EXPECT_TRUE(close(col("rhs_pressure" + s)[i], p.pressure)) << i << s << ": " << col("rhs_pressure" + s)[i];
      EXPECT_TRUE(close(col("rhs_shear" + s)[i], p.shear)) << i << s << ": " << col("rhs_shear" + s)[i];
      EXPECT_TRUE(close(col("rhs_xx" + s)[i], p.xx)) << i << s << ": " << col("rhs_xx" + s)[i];
      EXPECT_TRUE(std::isfinite(col("rhs_pressure" + s + "_error")[i])) << i << s;
    }
    EXPECT_EQ(continuation[i], readings[0].second.continuation_real ? 1 : 0);
    EXPECT_TRUE(close(col("network_factor")[i], std::min(Phi[i] * (z[i] - 1), 1.0)));
    EXPECT_TRUE(close(col("path_factor")[i], Psi[i] * (z[i] - 1)));
    EXPECT_TRUE(close(col("sum_limit")[i], std::max(xi[i] - 1, 0.0)));
    EXPECT_TRUE(close(Phi[i], 2 * cos1[i]));
    EXPECT_TRUE(close(Psi[i], 2 * cos2[i]));
  }

  // --xi signed reads the table's xi_ratio.
  const std::string out2 = dir / "signed.h5";
  r = run_tool("gf-network", run + " -o " + out2 + " --correlation " + table + " --xi signed --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_doubles(out2, "/prediction/xi_ratio")[0], read_doubles(table, "/correlation/xi_ratio")[0]);

  // --xi signed-length reads the table's xi_length_ratio (eq. 5.2 with C per unit length), here
  // of the run that is not the reference, whose two signed ratios differ.
  const std::string out_length = dir / "signed_length.h5";
  r = run_tool("gf-network", other + " -o " + out_length + " --correlation " + table +
                                 " --xi signed-length --from-strain 0.01 --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const double length_ratio = read_doubles(table, "/correlation/xi_length_ratio")[1];
  ASSERT_TRUE(std::isfinite(length_ratio));
  ASSERT_NE(length_ratio, read_doubles(table, "/correlation/xi_ratio")[1]);
  EXPECT_EQ(read_doubles(out_length, "/prediction/xi_ratio")[0], length_ratio);
  EXPECT_EQ(read_doubles(out_length, "/prediction/xi_ratio_error")[0],
            read_doubles(table, "/correlation/xi_length_ratio_error")[1]);
  EXPECT_EQ(read_ints(out_length, "/prediction/xi_measurable")[0], 1);
  EXPECT_EQ(read_doubles(out_length, "/prediction/sum_limit")[0], std::max(length_ratio - 1, 0.0));
  {
    io::File f = io::open_file(out_length, false);
    io::Group g = io::open_group(f.get(), "/prediction");
    EXPECT_EQ(io::read_string_attribute(io::open_attribute(g.get(), "xi_source").get()), "xi_length_ratio");
    io::Group p = io::open_group(f.get(), "/parameters");
    EXPECT_EQ(io::read_string_attribute(io::open_attribute(p.get(), "xi").get()), "signed-length");
  }

  // Without --correlation the predicted sides are NaN, the measured ones are not.
  const std::string out3 = dir / "none.h5";
  r = run_tool("gf-network", run + " -o " + out3 + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::isnan(read_doubles(out3, "/prediction/rhs_pressure")[0]));
  EXPECT_TRUE(std::isfinite(read_doubles(out3, "/prediction/lhs_pressure")[0]));
}

namespace {

// A copy of `run` without its last stored frame (every frame series and the contacts cut).
std::string without_last_frame(const std::string& run, const std::string& path) {
  std::filesystem::copy_file(run, path, std::filesystem::copy_options::overwrite_existing);
  io::File f = io::open_file(path, true);
  auto shrink = [&](const std::string& name, hsize_t rows) {
    io::Dataset d = io::open_dataset(f.get(), name);
    std::vector<hsize_t> dims = io::shape(d.get());
    dims[0] = rows;
    EXPECT_GE(H5Dset_extent(d.get(), dims.data()), 0) << name;
  };
  const std::vector<std::int64_t> offsets =
      io::read_all<std::int64_t>(io::open_dataset(f.get(), "/contacts/frame_offset").get());
  const hsize_t frames = offsets.size() - 1;
  for (const char* group :
       {"/particles/grains/position", "/particles/grains/velocity", "/particles/grains/orientation",
        "/particles/grains/angular_velocity", "/particles/grains/box/edges", "/lees_edwards/offset"})
    for (const char* part : {"/step", "/time", "/value"}) shrink(std::string(group) + part, frames - 1);
  shrink("/contacts/frame_offset", frames);
  for (const char* name :
       {"age", "binary_force", "branch", "normal_force", "pair", "pre_normal_velocity", "tangential_force"})
    shrink(std::string("/contacts/") + name, hsize_t(offsets[frames - 1]));
  return path;
}

}  // namespace

class GfNetworkBadInput : public ::testing::TestWithParam<BadInput> {};

TEST_P(GfNetworkBadInput, FailsWithExitTwoOneLineNoOutput) {
  static ScratchDir dir("network_bad_inputs");
  const std::string& run = every_step_run();
  static const std::string bare = [&] {
    const std::string path = dir / "bare.h5";
    std::filesystem::copy_file(run, path);
    io::File f = io::open_file(path, true);
    EXPECT_GE(H5Ldelete(f.get(), "/contacts", H5P_DEFAULT), 0);
    return path;
  }();
  // Frames at steps 0 and 40 only, rows to step 50: no frame from strain 0.045 on.
  static const std::string cut = without_last_frame(sparse_run(), dir / "cut.h5");
  static const std::string truncated = [&] {
    const std::string path = dir / "truncated.h5";
    std::ifstream in(run, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(path, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    return path;
  }();
  static const std::string text = [&] {
    const std::string path = dir / "text.h5";
    std::ofstream(path) << "not a trajectory\n";
    return path;
  }();
  // A gf-kinetic table: an HDF5 file of another schema.
  static const std::string kinetic = [&] {
    const std::string path = dir / "kinetic.h5";
    EXPECT_EQ(run_tool("gf-kinetic", run + " -o " + path + " --from-strain 0 --quiet").exit_code, 0);
    return path;
  }();
  // Correlation tables: on this run with --reference, on another run, without --reference.
  static const std::string correlation = [&] {
    const std::string path = dir / "correlation.h5";
    EXPECT_EQ(
        run_tool("gf-correlate", run + " -o " + path + " --reference " + run + " --from-strain 0 --quiet").exit_code,
        0);
    return path;
  }();
  static const std::string other_runs = [&] {
    const std::string path = dir / "other.h5";
    EXPECT_EQ(run_tool("gf-correlate",
                       sparse_run() + " -o " + path + " --reference " + sparse_run() + " --from-strain 0 --quiet")
                  .exit_code,
              0);
    return path;
  }();
  static const std::string no_reference = [&] {
    const std::string path = dir / "noref.h5";
    EXPECT_EQ(run_tool("gf-correlate", run + " -o " + path + " --from-strain 0 --quiet").exit_code, 0);
    return path;
  }();
  // A table without the per-length columns (as an older gf-correlate wrote them).
  static const std::string no_length = [&] {
    const std::string path = dir / "nolength.h5";
    std::filesystem::copy_file(correlation, path);
    io::File f = io::open_file(path, true);
    EXPECT_GE(H5Ldelete(f.get(), "/correlation/xi_length_ratio", H5P_DEFAULT), 0);
    return path;
  }();
  static const std::string existing = [&] {
    const std::string path = dir / "existing.h5";
    std::ofstream(path) << "a previous output\n";
    return path;
  }();
  expect_refused("gf-network", GetParam(),
                 {{"{run}", run},
                  {"{bare}", bare},
                  {"{cut}", cut},
                  {"{truncated}", truncated},
                  {"{text}", text},
                  {"{kinetic}", kinetic},
                  {"{correlation}", correlation},
                  {"{other}", other_runs},
                  {"{noref}", no_reference},
                  {"{nolength}", no_length},
                  {"{existing}", existing},
                  {"{pack}", dense_packing()}},
                 " --quiet");
}

INSTANTIATE_TEST_SUITE_P(
    Cases, GfNetworkBadInput,
    ::testing::Values(
        BadInput{"no_contacts_stored", "{bare} -o {out} --from-strain 0", "no contacts stored"},
        BadInput{"no_frame_in_window", "{cut} -o {out} --from-strain 0.045", "no stored frame in the window"},
        BadInput{"a_packing", "{pack} -o {out}", "is a packing"},
        BadInput{"from_strain_past_the_end", "{run} -o {out} --from-strain 1", "past the end of the run"},
        BadInput{"missing_file", "{out}.missing -o {out}", "no such file"},
        BadInput{"truncated_file", "{truncated} -o {out} --from-strain 0", "truncated.h5"},
        BadInput{"not_hdf5", "{text} -o {out}", "text.h5"},
        BadInput{"wrong_schema", "{kinetic} -o {out}", "kinetic.h5"},
        BadInput{"second_input_bad", "{run} {pack} -o {out} --from-strain 0", "is a packing"},
        BadInput{"run_not_in_correlation_table", "{run} -o {out} --from-strain 0 --correlation {other}",
                 "not among the runs of the correlation table"},
        BadInput{"correlation_without_reference", "{run} -o {out} --from-strain 0 --correlation {noref}",
                 "made without --reference"},
        BadInput{"correlation_not_gf_correlate", "{run} -o {out} --from-strain 0 --correlation {kinetic}",
                 "not a gf-correlate table"},
        BadInput{"correlation_missing", "{run} -o {out} --from-strain 0 --correlation {out}.missing", "missing"},
        BadInput{"xi_without_correlation", "{run} -o {out} --xi signed", "--xi"},
        BadInput{"xi_unknown", "{run} -o {out} --from-strain 0 --correlation {correlation} --xi both",
                 "--xi: must be abs, signed or signed-length"},
        BadInput{"xi_unknown_length", "{run} -o {out} --from-strain 0 --correlation {correlation} --xi abs-length",
                 "--xi: must be abs, signed or signed-length"},
        BadInput{"xi_length_not_in_table", "{run} -o {out} --from-strain 0 --correlation {nolength} --xi signed-length",
                 "older than xi_length"},
        BadInput{"angle_bins_too_few", "{run} -o {out} --from-strain 0 --angle-bins 3", "--angle-bins"},
        BadInput{"deflection_bins_too_few", "{run} -o {out} --from-strain 0 --deflection-bins 2", "--deflection-bins"},
        BadInput{"blocks_too_few", "{run} -o {out} --from-strain 0 --blocks 1", "--blocks"},
        BadInput{"contact_gap_negative", "{run} -o {out} --from-strain 0 --contact-gap -1e-3", "--contact-gap"},
        BadInput{"contact_gap_above_one", "{run} -o {out} --from-strain 0 --contact-gap 2", "--contact-gap"},
        BadInput{"contact_gap_not_a_number", "{run} -o {out} --from-strain 0 --contact-gap nan", "--contact-gap"},
        BadInput{"from_strain_negative", "{run} -o {out} --from-strain -1", "--from-strain"},
        BadInput{"no_input", "-o {out}", "missing RUN.h5"}, BadInput{"missing_output", "{run}", "--output"},
        BadInput{"unknown_option", "{run} -o {out} --bogus", "--bogus"},
        BadInput{"output_is_an_input", "{run} -o {run}", "--output"},
        BadInput{"output_is_the_correlation_table", "{run} -o {correlation} --correlation {correlation}", "--output"},
        BadInput{"existing_output_untouched", "{pack} -o {existing}", "is a packing"}),
    bad_input_name);
