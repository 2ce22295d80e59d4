// gf-correlate as a user runs it: known answers end to end on constructed trajectories
// (isolated binary contacts, whose ξ is known exactly), a sweep with ν_bc and clusters, a
// real gf-pack → gf-shear → gf-correlate chain, and bad input (exit 2, one line, no output).
#include <gtest/gtest.h>

#include <hdf5.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

#include "core/random.hpp"
#include "core/sha256.hpp"
#include "io/hdf5_handle.hpp"
#include "io/trajectory.hpp"
#include "programs/run_tool.hpp"

using namespace granflow;
using namespace granflow::testing;

namespace {

// A gf-shear-like trajectory of `frames` frames at strain 0, 0.1, 0.2, … (rate 1, dt 1e-3,
// a frame every 100 steps): 9 isolated pairs of grains at contact distance `distance` on a
// 3 × 3 lattice 25 apart in a 75 × 75 Lees–Edwards box, random forces per frame. Returns
// Σ F² and Σ F²/d over the frames from `first_used` on (eq. 5.2's sums for these pairs).
struct Sums {
  double w2 = 0, w2_over_d = 0, force = 0, contacts = 0;
};
// With transient_frames > 0 it also records T and p, rising linearly over that many frames,
// then constant (give or take a wiggle of 10⁻³); with series_frames ≥ 0, only for the first
// series_frames frames (a corrupt file: T and p shorter than the strain).
Sums write_pairs_run(const std::string& path, double nu, double e, double distance, int frames, int first_used,
                     bool with_contacts = true, std::uint64_t seed = 1, int transient_frames = 0,
                     int series_frames = -1) {
  Rng rng(seed);
  io::TrajectoryWriter w(path);
  io::Parameters p;
  p.set("program", "gf-shear");
  p.set("packing_fraction", nu);
  p.set("restitution", e);
  p.set("friction", 0.0);
  p.set("tangential-restitution", 0.0);
  w.write_parameters(p);
  const Box box{75, 75, true, 0};
  w.write_grains(io::GrainProperties{std::vector<double>(18, 0.5 * distance), std::vector<double>(18, 1.0),
                                     std::vector<std::uint8_t>(18, 0)},
                 box);
  w.set_lees_edwards_rate(1);
  Sums sums;
  for (int k = 0; k < frames; ++k) {
    io::Frame f;
    f.step = 100 * k;
    f.time = 0.1 * k;
    f.box = box;
    f.box.shift_offset(75 * f.time);
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        const double phi = rng.uniform(0, 2 * M_PI);
        const Vec2 branch = distance * Vec2(std::cos(phi), std::sin(phi)), centre(12 + 25 * a, 12 + 25 * b);
        f.position.push_back(centre + 0.5 * branch);
        f.position.push_back(centre - 0.5 * branch);
        const double fn = rng.uniform(0.5, 2);
        const std::int32_t i = std::int32_t(f.position.size()) - 2;
        f.contacts.pair.push_back({i, i + 1});
        f.contacts.branch.push_back(branch);
        f.contacts.normal_force.push_back(fn);
        f.contacts.tangential_force.push_back(0);
        f.contacts.binary_force.push_back(fn * rng.uniform(0.5, 1.5));
        f.contacts.pre_normal_velocity.push_back({0, 0});
        f.contacts.age.push_back(1);
        if (k >= first_used) {
          sums.w2 += fn * fn;
          sums.w2_over_d += fn * fn / distance;
          sums.force += fn;
          sums.contacts += 1;
        }
      }
    f.velocity.assign(18, Vec2::Zero());
    f.orientation.assign(18, 0);
    f.angular_velocity.assign(18, 0);
    f.has_contacts = with_contacts;
    if (!with_contacts) f.contacts.clear();
    w.append_frame(f);
    w.append_observable("strain", f.step, f.time, f.time);
    if (transient_frames > 0 && (series_frames < 0 || k < series_frames)) {
      const double level = std::min(1.0, double(k) / transient_frames);
      w.append_observable("temperature", f.step, f.time, level + 1e-3 * std::sin(0.7 * k));
      w.append_observable("pressure", f.step, f.time, 3 * level + 1e-3 * std::cos(0.3 * k));
    }
  }
  w.close();
  return sums;
}

std::vector<double> read_doubles(const std::string& file, const std::string& dataset) {
  io::File f = io::open_file(file, false);
  io::Dataset d = io::open_dataset(f.get(), dataset);
  return io::read_all<double>(d.get());
}

double read_scalar(const std::string& file, const std::string& dataset) {
  io::File f = io::open_file(file, false);
  io::Dataset d = io::open_dataset(f.get(), dataset);
  double value = 0;
  EXPECT_GE(H5Dread(d.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, &value), 0) << dataset;
  return value;
}

std::vector<std::int32_t> read_ints(const std::string& file, const std::string& dataset) {
  io::File f = io::open_file(file, false);
  io::Dataset d = io::open_dataset(f.get(), dataset);
  return io::read_all<std::int32_t>(d.get());
}

std::string string_attribute(const std::string& file, const std::string& object, const std::string& name) {
  io::File f = io::open_file(file, false);
  const H5O_type_t type = [&] {
    H5O_info_t info;
#if H5_VERSION_GE(1, 12, 0)
    H5Oget_info_by_name3(f.get(), object.c_str(), &info, H5O_INFO_BASIC, H5P_DEFAULT);
#else
    H5Oget_info_by_name(f.get(), object.c_str(), &info, H5P_DEFAULT);
#endif
    return info.type;
  }();
  if (type == H5O_TYPE_GROUP) {
    io::Group g = io::open_group(f.get(), object);
    io::Attribute a = io::open_attribute(g.get(), name);
    return io::read_string_attribute(a.get());
  }
  io::Dataset d = io::open_dataset(f.get(), object);
  io::Attribute a = io::open_attribute(d.get(), name);
  return io::read_string_attribute(a.get());
}

// One packing shared by the tests of this file.
const std::string& packing() {
  return packed_once("correlate_packing", "--grains 150 --packing-fraction 0.78 --seed 2");
}

}  // namespace

TEST(GfCorrelate, IsolatedPairsGiveTheirHarmonicMeanDistance) {
  ScratchDir dir("correlate_pairs");
  const std::string run = dir / "run.h5", out = dir / "out.h5";
  const Sums s = write_pairs_run(run, 0.6, 0.5, 1.3, 10, 5);
  auto r = run_tool("gf-correlate", run + " -o " + out + " --from-strain 0.5 --max-lag 10 --blocks 5 --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_ints(out, "/runs/frames")[0], 5);
  EXPECT_NEAR(read_doubles(out, "/runs/first_strain")[0], 0.5, 1e-12);
  EXPECT_NEAR(read_doubles(out, "/correlation/xi")[0], s.w2 / s.w2_over_d, 1e-12);
  EXPECT_LT(read_doubles(out, "/correlation/xi_error")[0], 1e-12) << "every block has ξ = d exactly";
  EXPECT_NEAR(read_doubles(out, "/forces/mean_force")[0], s.force / s.contacts, 1e-6);
  EXPECT_TRUE(std::isnan(read_scalar(out, "/correlation/xi_el")));
  // C per unit length: the pairs' distance too (one distance), and no ξ_el without a reference.
  EXPECT_NEAR(read_doubles(out, "/correlation/xi_length")[0], 1.3, 1e-12);
  EXPECT_LT(read_doubles(out, "/correlation/xi_length_error")[0], 1e-12);
  EXPECT_NEAR(read_doubles(out, "/correlation/xi_length_truncated").back(), 1.3, 1e-12);
  EXPECT_TRUE(std::isnan(read_scalar(out, "/correlation/xi_length_el")));
  EXPECT_TRUE(std::isnan(read_doubles(out, "/correlation/xi_length_ratio")[0]));
  // ξ_|C| of isolated pairs: all of |C| at d, so the same harmonic mean, measurable.
  EXPECT_NEAR(read_doubles(out, "/correlation/xi_abs")[0], s.w2 / s.w2_over_d, 1e-12);
  EXPECT_EQ(read_ints(out, "/correlation/measurable")[0], 1);
  EXPECT_EQ(read_doubles(out, "/correlation/xi_abs_tail")[0], 0);
  EXPECT_TRUE(std::isnan(read_scalar(out, "/correlation/xi_abs_el")));
  // Eq. 5.2 per direction: every sector holding pairs gives their distance d, the empty ones NaN.
  const auto xi_direction = read_doubles(out, "/correlation/xi_theta_direction");
  ASSERT_EQ(xi_direction.size(), 24u);
  int holding = 0;
  for (double x : xi_direction)
    if (!std::isnan(x)) {
      ++holding;
      EXPECT_NEAR(x, 1.3, 1e-12);
    }
  EXPECT_GE(holding, 12) << "45 pairs at random angles over 24 sectors";
  EXPECT_EQ(read_doubles(out, "/correlation/xi_theta_direction_error").size(), 24u);
  // C(ℓ) sits in the one bin holding ℓ = 1.3, and the whole C integrates to −1/2 (sum rule).
  const auto r_bins = read_doubles(out, "/correlation/r"), c = read_doubles(out, "/correlation/C");
  const double width = r_bins[1] - r_bins[0];
  double integral = 0;
  for (std::size_t b = 0; b < c.size(); ++b) {
    integral += c[b] * M_PI * width * width * double(2 * b + 1);
    if (std::fabs(r_bins[b] - 1.3) > width) {
      EXPECT_EQ(c[b], 0) << r_bins[b];
    }
  }
  EXPECT_NEAR(integral, -0.5, 1e-12);
  // Provenance and self-description.
  EXPECT_EQ(string_attribute(out, "/parameters", "program"), "gf-correlate");
  EXPECT_EQ(string_attribute(out, "/parameters", "input"), run);
  EXPECT_EQ(string_attribute(out, "/parameters", "input_sha256"), sha256_file(run));
  EXPECT_NE(string_attribute(out, "/parameters", "command_line").find("--from-strain 0.5"), std::string::npos);
  EXPECT_FALSE(string_attribute(out, "/parameters", "version").empty());
  for (const char* d :
       {"/correlation/C", "/correlation/xi_theta", "/correlation/map", "/forces/P", "/runs/restitution",
        "/correlation/xi_theta_direction", "/correlation/xi_theta_direction_error", "/correlation/a0_direction",
        "/correlation/a0_direction_error", "/correlation/theta0_direction", "/correlation/theta0_direction_error",
        "/correlation/fit_direction_chi2_dof", "/correlation/fit_direction_weighted", "/correlation/xi_length",
        "/correlation/xi_length_error", "/correlation/xi_length_truncated", "/correlation/xi_length_el",
        "/correlation/xi_length_el_error", "/correlation/xi_length_ratio", "/correlation/xi_length_ratio_error"}) {
    EXPECT_FALSE(string_attribute(out, d, "meaning").empty()) << d;
    EXPECT_FALSE(string_attribute(out, d, "units").empty()) << d;
  }
  for (const char* d : {"/correlation/xi_theta_direction", "/correlation/a0_direction", "/correlation/xi_length",
                        "/correlation/xi_length_error", "/correlation/xi_length_truncated",
                        "/correlation/xi_length_ratio", "/correlation/xi_length_ratio_error"})
    EXPECT_EQ(string_attribute(out, d, "rows"), "one row per input run, in /runs order") << d;
  EXPECT_EQ(dir.entries(), 2) << "only the run and the output";
}

// --map-method fft on isolated pairs (d = 1.3) in sheared frames: the same ξ as the exact pair
// sums within the binning (a lag moves by less than two cell diagonals, 0.14 here), the
// method and grid recorded; the default output carries no method attributes; --whole-box
// takes ℓ_max to half the box; auto picks the exact sums for 18 grains and says so.
TEST(GfCorrelate, FftMethodAgreesWithPairs) {
  ScratchDir dir("correlate_fft");
  const std::string run = dir / "run.h5", pairs = dir / "pairs.h5", fft = dir / "fft.h5", whole = dir / "whole.h5",
                    automatic = dir / "auto.h5";
  const Sums s = write_pairs_run(run, 0.6, 0.5, 1.3, 10, 5);
  const std::string common = " --from-strain 0.5 --blocks 5 --quiet";
  auto r = run_tool("gf-correlate", run + " -o " + pairs + " --max-lag 10" + common);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_tool("gf-correlate", run + " -o " + fft + " --max-lag 10 --map-method fft --fft-cell 0.05" + common);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NEAR(read_doubles(fft, "/correlation/xi")[0], s.w2 / s.w2_over_d, 0.14);
  EXPECT_NEAR(read_doubles(fft, "/correlation/xi")[0], read_doubles(pairs, "/correlation/xi")[0], 0.14);
  EXPECT_EQ(string_attribute(fft, "/correlation", "map_method"), "fft");
  EXPECT_EQ(string_attribute(fft, "/correlation", "fft_grid"), "1500x1500");
  EXPECT_EQ(string_attribute(fft, "/parameters", "map-method"), "fft");
  // Identical input, identical numbers, bit for bit (FFTW_ESTIMATE plans).
  const std::string again = dir / "again.h5";
  r = run_tool("gf-correlate", run + " -o " + again + " --max-lag 10 --map-method fft --fft-cell 0.05" + common);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* d : {"/correlation/C", "/correlation/map", "/correlation/xi_theta", "/correlation/xi_abs"}) {
    const std::vector<double> a = read_doubles(fft, d), b = read_doubles(again, d);
    ASSERT_EQ(a.size(), b.size()) << d;
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0) << d;
  }
  {
    io::File f = io::open_file(pairs, false);
    EXPECT_EQ(H5Aexists_by_name(f.get(), "/correlation", "map_method", H5P_DEFAULT), 0)
        << "the default output keeps its attributes";
  }
  r = run_tool("gf-correlate",
               run + " -o " + whole + " --whole-box --map-method fft --fft-cell 0.1 --map-bin 0.5" + common);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_doubles(whole, "/correlation/r").size(), std::size_t(37.5 / (1.3 / 20)));  // bins σ/20 to 75/2
  EXPECT_NEAR(read_doubles(whole, "/correlation/xi_truncated").back(), read_doubles(whole, "/correlation/xi")[0],
              1e-12);
  r = run_tool("gf-correlate", run + " -o " + automatic + " --map-method auto --from-strain 0.5 --blocks 5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(string_attribute(automatic, "/correlation", "map_method"), "pairs");
  EXPECT_NE(r.err.find("pair sums by pairs (auto: estimated"), std::string::npos) << r.err;
  EXPECT_EQ(dir.entries(), 6);
}

TEST(GfCorrelate, SweepGivesNuBcAndClusters) {
  // ξ of isolated pairs is their distance: runs at ν = 0.6, 0.7, 0.8 with d = 1.0, 1.2, 1.5
  // and ξ_el = 1 cross ξ/ξ_el = 1.25 at ν = 0.7 + 0.05/0.3 · 0.1.
  ScratchDir dir("correlate_sweep");
  const std::string a = dir / "a.h5", b = dir / "b.h5", c = dir / "c.h5", ref = dir / "ref.h5";
  write_pairs_run(a, 0.6, 0.5, 1.0, 6, 0, true, 1);
  write_pairs_run(b, 0.7, 0.5, 1.2, 6, 0, true, 2);
  write_pairs_run(c, 0.8, 0.5, 1.5, 6, 0, true, 3);
  write_pairs_run(ref, 0.3, 0.5, 1.0, 6, 0, true, 4);
  const std::string common = " --from-strain 0 --max-lag 10 --quiet --clusters-window 2 --clusters-frame 3";
  auto r = run_tool("gf-correlate", a + " " + b + " " + c + " -o " + (dir / "given.h5") + " --xi-el 1" + common);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string out = dir / "given.h5";
  EXPECT_NEAR(read_doubles(out, "/sweep/nu_bc")[0], 0.7 + 0.05 / 0.3 * 0.1, 1e-12);
  EXPECT_EQ(read_ints(out, "/sweep/status")[0], 0);
  EXPECT_EQ(read_ints(out, "/sweep/regime"), (std::vector<std::int32_t>{0, 0, 1}));
  const auto ratio = read_doubles(out, "/correlation/xi_ratio");
  EXPECT_NEAR(ratio[1], 1.2, 1e-12);
  EXPECT_EQ(read_doubles(out, "/runs/packing_fraction"), (std::vector<double>{0.6, 0.7, 0.8}));
  // Clusters: every pair is its own cluster of two; runs are stacked with offsets.
  EXPECT_EQ(read_ints(out, "/clusters/grain_offset"), (std::vector<std::int32_t>{0, 18, 36, 54}));
  EXPECT_EQ(read_ints(out, "/clusters/count"), (std::vector<std::int32_t>{9, 9, 9}));
  EXPECT_EQ(read_ints(out, "/clusters/first_frame"), (std::vector<std::int32_t>{2, 2, 2}));
  const auto label = read_ints(out, "/clusters/label");
  for (std::size_t i = 0; i < label.size(); i += 2) EXPECT_EQ(label[i], label[i + 1]) << i;

  // The same with ξ_el from a dilute reference run (pairs at d = 1: ξ_el = 1 exactly).
  r = run_tool("gf-correlate", a + " " + b + " " + c + " -o " + (dir / "ref_out.h5") + " --reference " + ref + common);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NEAR(read_scalar(dir / "ref_out.h5", "/correlation/xi_el"), 1.0, 1e-12);
  EXPECT_NEAR(read_doubles(dir / "ref_out.h5", "/sweep/nu_bc")[0], 0.7 + 0.05 / 0.3 * 0.1, 1e-12);
  EXPECT_EQ(string_attribute(dir / "ref_out.h5", "/parameters", "reference"), ref);
  // ξ_|C| is the pair distance too: the same ν_bc from the reference's ξ_|C| = 1.
  EXPECT_NEAR(read_scalar(dir / "ref_out.h5", "/correlation/xi_abs_el"), 1.0, 1e-12);
  EXPECT_NEAR(read_doubles(dir / "ref_out.h5", "/correlation/xi_abs_ratio")[2], 1.5, 1e-12);
  EXPECT_NEAR(read_doubles(dir / "ref_out.h5", "/sweep/nu_bc_abs")[0], 0.7 + 0.05 / 0.3 * 0.1, 1e-12);
  EXPECT_EQ(read_ints(dir / "ref_out.h5", "/sweep/status_abs")[0], 0);
  EXPECT_EQ(read_ints(dir / "ref_out.h5", "/sweep/regime_abs"), (std::vector<std::int32_t>{0, 0, 1}));
  // ξ with C per unit length: one distance per run, so the same ratios from ξ_length_el = 1.
  EXPECT_NEAR(read_scalar(dir / "ref_out.h5", "/correlation/xi_length_el"), 1.0, 1e-12);
  EXPECT_NEAR(read_doubles(dir / "ref_out.h5", "/reference/xi_length")[0], 1.0, 1e-12);
  const auto length_ratio = read_doubles(dir / "ref_out.h5", "/correlation/xi_length_ratio");
  ASSERT_EQ(length_ratio.size(), 3u);
  EXPECT_NEAR(length_ratio[0], 1.0, 1e-12);
  EXPECT_NEAR(length_ratio[1], 1.2, 1e-12);
  EXPECT_NEAR(length_ratio[2], 1.5, 1e-12);
  // With --xi-el (ξ_el of the area reading only) there is no ξ_length_el.
  EXPECT_TRUE(std::isnan(read_scalar(out, "/correlation/xi_length_el")));
}

// --detect-transient starts where the run's T and p stop rising (frame 20 of 40, strain 2),
// past --from-strain; without it, at --from-strain.
TEST(GfCorrelate, DetectedTransientIsSkipped) {
  ScratchDir dir("correlate_transient");
  const std::string run = dir / "run.h5";
  write_pairs_run(run, 0.6, 0.5, 1.3, 40, 0, true, 1, 20);
  const std::string common = " --max-lag 10 --blocks 4 --quiet --from-strain 0.5";
  ASSERT_EQ(run_tool("gf-correlate", run + " -o " + (dir / "fixed.h5") + common).exit_code, 0);
  EXPECT_NEAR(read_doubles(dir / "fixed.h5", "/runs/first_strain")[0], 0.5, 1e-9);
  auto r = run_tool("gf-correlate", run + " -o " + (dir / "detected.h5") + common + " --detect-transient");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NEAR(read_doubles(dir / "detected.h5", "/runs/first_strain")[0], 2.0, 0.1 + 1e-9);
  const int frames = read_ints(dir / "detected.h5", "/runs/frames")[0];
  EXPECT_GE(frames, 19);
  EXPECT_LE(frames, 21);
  // A transient shorter than --from-strain leaves --from-strain.
  ASSERT_EQ(run_tool("gf-correlate", run + " -o " + (dir / "late.h5") +
                                         " --max-lag 10 --blocks 4 --quiet "
                                         "--from-strain 3 --detect-transient")
                .exit_code,
            0);
  EXPECT_NEAR(read_doubles(dir / "late.h5", "/runs/first_strain")[0], 3.0, 1e-9);
  // A run without T and p cannot be checked for its transient.
  const std::string bare = dir / "bare.h5";
  write_pairs_run(bare, 0.6, 0.5, 1.3, 10, 0);
  r = run_tool("gf-correlate", bare + " -o " + (dir / "bare_out.h5") + common + " --detect-transient");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("temperature"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "bare_out.h5"));
  // T and p must have the strain's length, or MSER would read past their end.
  const std::string cut = dir / "cut.h5";
  write_pairs_run(cut, 0.6, 0.5, 1.3, 40, 0, true, 1, 20, 30);
  r = run_tool("gf-correlate", cut + " -o " + (dir / "cut_out.h5") + common + " --detect-transient");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("differ in length"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "cut_out.h5"));
  // Without --detect-transient T and p are not read: the run is usable.
  EXPECT_EQ(run_tool("gf-correlate", cut + " -o " + (dir / "cut_fixed.h5") + common).exit_code, 0);
}

TEST(GfCorrelate, RealShearRun) {
  ScratchDir dir("correlate_real");
  const std::string run = dir / "run.h5", out = dir / "out.h5";
  ASSERT_EQ(run_tool("gf-shear", "-i " + packing() + " -o " + run +
                                     " --rate 1 --steps 400 --frame-every 20 --restitution 0.5 --quiet")
                .exit_code,
            0);
  auto r = run_tool("gf-correlate", run + " -o " + out + " --from-strain 0.1 --blocks 4");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("ξ ="), std::string::npos) << r.err;
  EXPECT_EQ(read_ints(out, "/runs/frames")[0], 16);  // strains 0.10, 0.12, …, 0.40
  const double xi = read_doubles(out, "/correlation/xi")[0];
  const double xi_abs = read_doubles(out, "/correlation/xi_abs")[0];
  EXPECT_GT(xi_abs, 0.5);
  EXPECT_LT(xi_abs, 20);
  EXPECT_GT(read_doubles(out, "/correlation/xi_abs_error")[0], 0);
  EXPECT_GT(xi, 0.5);
  EXPECT_LT(xi, 20);
  EXPECT_TRUE(std::isfinite(read_doubles(out, "/correlation/a0")[0]));
  const auto peak = read_ints(out, "/forces/peak");
  EXPECT_TRUE(peak[0] == 0 || peak[0] == 1);
  // The same run by FFT to half the box, against the exact sums to half the box: ξ within its
  // error (cells σ/20 move each lag by less than σ/10). Not ξ_|C|: on this small run (150
  // grains, 4 blocks, correlations reaching the box) its noise floor makes it jump by several
  // of its jackknife errors when the lags move by a fraction of a cell (1.76–2.16 for cells
  // σ/40–σ/20 against 1.92 ± 0.08 exactly), which says more about ξ_|C| on so few blocks than
  // about the FFT; the 10⁴-grain unit test compares it.
  const std::string whole = dir / "whole.h5", whole_fft = dir / "whole_fft.h5";
  ASSERT_EQ(
      run_tool("gf-correlate", run + " -o " + whole + " --from-strain 0.1 --blocks 4 --whole-box --quiet").exit_code,
      0);
  r = run_tool("gf-correlate",
               run + " -o " + whole_fft + " --from-strain 0.1 --blocks 4 --whole-box --map-method fft --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NEAR(read_doubles(whole_fft, "/correlation/xi")[0], read_doubles(whole, "/correlation/xi")[0],
              read_doubles(whole, "/correlation/xi_error")[0]);
}

// ---- bad input: exit 2, one line naming the problem, no output file left ----

namespace {

const std::string& valid_run() {
  static ScratchDir dir("correlate_valid_run");
  static std::string path = [] {
    std::string p = dir / "run.h5";
    write_pairs_run(p, 0.6, 0.5, 1.3, 10, 0);
    return p;
  }();
  return path;
}

const std::string& bare_run() {
  static ScratchDir dir("correlate_bare_run");
  static std::string path = [] {
    std::string p = dir / "bare.h5";
    write_pairs_run(p, 0.6, 0.5, 1.3, 4, 0, false);
    return p;
  }();
  return path;
}
}  // namespace

class GfCorrelateBadInput : public ::testing::TestWithParam<BadInput> {};

TEST_P(GfCorrelateBadInput, FailsWithExitTwoOneLineNoOutput) {
  // {run}: a valid run, {bare}: a run without contacts, {pack}: a packing.
  expect_refused("gf-correlate", GetParam(), {{"{run}", valid_run()}, {"{bare}", bare_run()}, {"{pack}", packing()}},
                 " --quiet");
}

INSTANTIATE_TEST_SUITE_P(
    Cases, GfCorrelateBadInput,
    ::testing::Values(BadInput{"no_contacts_stored", "{bare} -o {out}", "no contacts stored"},
                      BadInput{"a_packing", "{pack} -o {out}", "is a packing"},
                      BadInput{"from_strain_past_the_end", "{run} -o {out} --from-strain 5", "past the end of the run"},
                      BadInput{"second_input_bad", "{run} {pack} -o {out}", "is a packing"},
                      BadInput{"missing_file", "{out}.missing -o {out}", "no such file"},
                      BadInput{"no_input", "-o {out}", "missing RUN.h5"},
                      BadInput{"missing_output", "{run}", "--output"},
                      BadInput{"blocks_zero", "{run} -o {out} --blocks 0", "--blocks"},
                      BadInput{"max_lag_beyond_half_box", "{run} -o {out} --max-lag 40", "--max-lag"},
                      BadInput{"bin_width_negative", "{run} -o {out} --bin-width -1", "--bin-width"},
                      BadInput{"angle_bins_two", "{run} -o {out} --angle-bins 2", "--angle-bins"},
                      BadInput{"xi_el_zero", "{run} -o {out} --xi-el 0", "--xi-el"},
                      BadInput{"xi_el_and_reference", "{run} -o {out} --xi-el 1 --reference {run}", "not both"},
                      BadInput{"reference_missing", "{run} -o {out} --reference {out}.ref", "no such file"},
                      BadInput{"reference_empty", "{run} -o {out} --reference ,", "--reference"},
                      BadInput{"reference_given_twice", "{run} -o {out} --reference {run} --reference {run}",
                               "option --reference: given 2 times"},
                      BadInput{"reference_empty_item", "{run} -o {out} --reference {run},,{run}",
                               "option --reference: item 2 of"},
                      BadInput{"kde_bandwidth_too_wide", "{run} -o {out} --kde-bandwidth 5", "--kde-bandwidth"},
                      BadInput{"clusters_window_too_long", "{run} -o {out} --clusters-window 11", "--clusters-window"},
                      BadInput{"abs_bin_width_not_a_multiple", "{run} -o {out} --abs-bin-width 0.33",
                               "--abs-bin-width"},
                      BadInput{"abs_threshold_unknown", "{run} -o {out} --abs-threshold medium", "--abs-threshold"},
                      BadInput{"max_tail_share_above_one", "{run} -o {out} --max-tail-share 1.5", "--max-tail-share"},
                      BadInput{"from_strain_nan", "{run} -o {out} --from-strain nan", "--from-strain"},
                      BadInput{"output_dir_missing", "{run} -o {out}/nodir/c.h5", "does not exist"},
                      BadInput{"map_method_unknown", "{run} -o {out} --map-method fast", "--map-method"},
                      BadInput{"fft_cell_negative", "{run} -o {out} --map-method fft --fft-cell -1", "--fft-cell"},
                      BadInput{"whole_box_and_max_lag", "{run} -o {out} --whole-box --max-lag 5", "not both"}),
    bad_input_name);

// Options that set the size of a table: a count beyond the documented bound is refused
// naming the option and the count, before anything is allocated.
INSTANTIATE_TEST_SUITE_P(
    TableSizes, GfCorrelateBadInput,
    ::testing::Values(
        BadInput{"bin_width_tiny", "{run} -o {out} --bin-width 1e-9", "--bin-width"},
        BadInput{"bin_width_small", "{run} -o {out} --bin-width 1e-7", "--bin-width"},
        BadInput{"bin_width_above_bound", "{run} -o {out} --bin-width 1e-4", "radial bins"},
        BadInput{"abs_bin_width_by_angle_bins",
                 "{run} -o {out} --angle-bins 3600 --bin-width 0.01 --abs-bin-width 0.01", "--abs-bin-width"},
        BadInput{"force_bin_width_tiny", "{run} -o {out} --force-bin-width 1e-9", "--force-bin-width"},
        BadInput{"force_bin_width_above_bound", "{run} -o {out} --force-bin-width 1e-5", "--force-bin-width"},
        BadInput{"kde_bandwidth_tiny", "{run} -o {out} --kde-bandwidth 1e-9", "--kde-bandwidth"},
        BadInput{"fft_cell_tiny", "{run} -o {out} --map-method fft --fft-cell 1e-3", "--fft-cell"},
        BadInput{"clusters_frame_out_of_range", "{run} -o {out} --clusters-window 1 --clusters-frame 500",
                 "--clusters-frame 500"}),
    bad_input_name);

TEST(GfCorrelateBadInput, NotHdf5AndOutputIsInput) {
  ScratchDir dir("correlate_bad_files");
  const std::string text = dir / "text.h5";
  std::ofstream(text) << "not hdf5\n";
  auto r = run_tool("gf-correlate", text + " -o " + (dir / "out.h5"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("not an HDF5 file"), std::string::npos) << r.err;
  const std::string run = dir / "run.h5";
  write_pairs_run(run, 0.6, 0.5, 1.3, 4, 0);
  r = run_tool("gf-correlate", run + " -o " + run);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("same file as the input"), std::string::npos) << r.err;
  EXPECT_EQ(dir.entries(), 2);
}

TEST(GfCorrelateUsage, HelpListsEveryOptionWithDefaults) {
  ScratchDir dir("correlate_help");
  ASSERT_EQ(std::system((tool_path("gf-correlate") + " --help > " + (dir / "help.txt")).c_str()), 0);
  std::ifstream in(dir / "help.txt");
  const std::string help((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const char* option :
       {"--output",          "--from-strain",    "--bin-width",        "--max-lag",   "--angle-bins",
        "--map-bin",         "--blocks",         "--reference",        "--xi-el",     "--threshold",
        "--force-bin-width", "--force-max",      "--kde-bandwidth",    "--bootstrap", "--seed",
        "--clusters-window", "--clusters-frame", "--detect-transient", "--quiet",     "--version",
        "--map-method",      "--fft-cell",       "--whole-box"})
    EXPECT_NE(help.find(option), std::string::npos) << option;
  EXPECT_NE(help.find("[default: 0.5]"), std::string::npos);
  EXPECT_NE(help.find("[default: 1.25]"), std::string::npos);
  EXPECT_EQ(run_tool("gf-correlate", "--version").exit_code, 0);
}
