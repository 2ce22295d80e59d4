// gf-stz fit as a user runs it, on real gf-pack → gf-shear chains (100 grains, strain 2):
// the steady means of /runs against an independent average over the same window, the
// selection of the fitted rows (restitution, dense by ν or by ξ/ξ_el of a gf-correlate
// table), /fit against lib/stz's fits of the same points, every prediction and residual
// against the law at the row's abscissa, incline rows read from an incline-bulk table, and
// bad input (exit 2, one line, nothing left).
#include <gtest/gtest.h>

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <utility>

#include "io/analysis_writer.hpp"
#include "io/hdf5_handle.hpp"
#include "io/trajectory.hpp"
#include "programs/run_tool.hpp"
#include "stz/constitutive.hpp"

using namespace granflow;
using namespace granflow::testing;

namespace {

std::vector<double> read_doubles(const std::string& file, const std::string& dataset) {
  io::File f = io::open_file(file, false);
  return io::read_all<double>(io::open_dataset(f.get(), dataset).get());
}

std::vector<std::uint8_t> read_flags(const std::string& file, const std::string& dataset) {
  io::File f = io::open_file(file, false);
  io::Dataset d = io::open_dataset(f.get(), dataset);
  io::Datatype t(H5Dget_type(d.get()));
  EXPECT_EQ(H5Tget_class(t.get()), H5T_INTEGER);
  EXPECT_EQ(H5Tget_size(t.get()), 1u) << dataset << " is not uint8";
  return io::read_all<std::uint8_t>(d.get());
}

std::vector<std::int64_t> read_int64(const std::string& file, const std::string& dataset) {
  io::File f = io::open_file(file, false);
  return io::read_all<std::int64_t>(io::open_dataset(f.get(), dataset).get());
}

std::vector<std::string> read_texts(const std::string& file, const std::string& dataset) {
  io::File f = io::open_file(file, false);
  io::Dataset d = io::open_dataset(f.get(), dataset);
  io::Datatype t(H5Dget_type(d.get()));
  const std::size_t width = H5Tget_size(t.get()), n = io::shape(d.get())[0];
  std::string packed(width * n, '\0');
  H5Dread(d.get(), t.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, packed.data());
  std::vector<std::string> out;
  for (std::size_t i = 0; i < n; ++i) {
    std::string v = packed.substr(i * width, width);
    v.resize(std::min(v.find('\0'), v.size()));
    out.push_back(v);
  }
  return out;
}

std::string string_attribute(const std::string& file, const std::string& group, const std::string& name) {
  io::File f = io::open_file(file, false);
  io::Group g = io::open_group(f.get(), group);
  return io::read_string_attribute(io::open_attribute(g.get(), name).get());
}

// Packings of 100 grains shared by the runs below.
const std::string& packing(const std::string& nu, int seed = 3) {
  return packed_once("stz_fit_pack_" + nu + "_" + std::to_string(seed),
                     "--grains 100 --packing-fraction " + nu + " --seed " + std::to_string(seed));
}

// `gf-shear -i packing(nu, seed) ARGS` to strain 2 (1000 steps, a frame every 50), made once per name.
const std::string& run(const std::string& name, const std::string& nu, const std::string& args, int seed = 3) {
  static std::map<std::string, std::pair<std::unique_ptr<ScratchDir>, std::string>> made;
  auto it = made.find(name);
  if (it == made.end()) {
    auto dir = std::make_unique<ScratchDir>("stz_fit_run_" + name);
    const std::string path = *dir / (name + ".h5");
    EXPECT_EQ(run_tool("gf-shear", "-i " + packing(nu, seed) + " -o " + path +
                                       " --strain 2 --strain-step 2e-3 --frame-every 50 --quiet " + args)
                  .exit_code,
              0);
    it = made.emplace(name, std::make_pair(std::move(dir), path)).first;
  }
  return it->second.second;
}

// Frictionless, e = 0, at four packing fractions; e = 0.5; μ = 0.4 (e = 0); γ̇ = −1.
std::vector<std::string> e0_runs() {
  return {run("e0_76", "0.76", "--restitution 0"), run("e0_78", "0.78", "--restitution 0"),
          run("e0_80", "0.80", "--restitution 0"), run("e0_82", "0.82", "--restitution 0")};
}
const std::string& e5_run() { return run("e5_80", "0.80", "--restitution 0.5"); }
// The solver is capped (most steps end unconverged): the test needs a frictional run's rows,
// not a converged frictional flow, and a converged one costs 15 times more.
const std::string& friction_run() {
  return run("m4_80", "0.80", "--restitution 0 --friction 0.4 --max-iterations 200 --max-unconverged 1");
}
const std::string& reversed_run() { return run("neg_80", "0.80", "--restitution 0 --rate -1"); }

std::string joined(const std::vector<std::string>& files) {
  std::string s;
  for (const std::string& f : files) s += f + " ";
  return s;
}

bool same(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

double relative(double a, double b) { return std::fabs(a - b) / std::max(std::fabs(b), 1e-300); }

// What a test expects of one run: the window of rows at |strain| ≥ 0.5 and the ratios of
// their plain means.
struct Expected {
  double s_over_p, x, I, friction, restitution, nu;
};

Expected independent(const std::string& path) {
  io::TrajectoryReader r(path);
  const std::vector<double> strain = r.observable_scalar("strain"), T = r.observable_scalar("temperature"),
                            p = r.observable_scalar("pressure"), s = r.observable_scalar("shear_stress");
  double sum_T = 0, sum_p = 0, sum_s = 0;
  std::size_t n = 0;
  for (std::size_t k = 0; k < strain.size(); ++k)
    if (std::fabs(strain[k]) >= 0.5 - 1e-9) {
      sum_T += T[k];
      sum_p += p[k];
      sum_s += s[k];
      ++n;
    }
  const double rate = r.lees_edwards_rate(), Tm = sum_T / double(n), pm = sum_p / double(n), sm = sum_s / double(n);
  const io::GrainProperties g = r.grains();
  double R = 0, mass = 0, area = 0;
  for (std::size_t i = 0; i < g.radius.size(); ++i) {
    R += g.radius[i];
    mass += g.mass[i];
    area += std::numbers::pi * g.radius[i] * g.radius[i];
  }
  R /= double(g.radius.size());
  const io::Parameters prm = r.parameters();
  return {(rate > 0 ? sm : -sm) / pm,
          std::fabs(rate) * R / std::sqrt(Tm),
          std::fabs(rate) * 2 * R / std::sqrt(pm / (mass / area)),
          prm.get_double("friction"),
          prm.get_double("restitution"),
          prm.get_double("packing_fraction")};
}

stz::StzCoefficients stz_of(const std::string& out, std::size_t row) {
  return {read_doubles(out, "/fit/A")[row], read_doubles(out, "/fit/kappa")[row], read_doubles(out, "/fit/zeta")[row]};
}

stz::MuICoefficients mu_of_I_of(const std::string& out, std::size_t row) {
  return {read_doubles(out, "/fit/mu_s")[row], read_doubles(out, "/fit/mu_2")[row], read_doubles(out, "/fit/I0")[row]};
}

// Every prediction and residual of /runs against the fitted law of its friction (NaN when
// that friction has no /fit row).
void expect_predictions(const std::string& out) {
  const auto friction = read_doubles(out, "/runs/friction"), x = read_doubles(out, "/runs/rate_R_over_sqrt_T"),
             I = read_doubles(out, "/runs/inertial_number"), mu = read_doubles(out, "/runs/s_over_p"),
             prediction = read_doubles(out, "/runs/prediction"), residual = read_doubles(out, "/runs/residual"),
             prediction_I = read_doubles(out, "/runs/prediction_mu_of_I"),
             residual_I = read_doubles(out, "/runs/residual_mu_of_I"), fits = read_doubles(out, "/fit/friction");
  for (std::size_t k = 0; k < x.size(); ++k) {
    const auto it = std::find(fits.begin(), fits.end(), friction[k]);
    if (it == fits.end()) {
      EXPECT_TRUE(std::isnan(prediction[k]) && std::isnan(residual[k]) && std::isnan(prediction_I[k])) << k;
      continue;
    }
    const std::size_t f = std::size_t(it - fits.begin());
    const double want = stz::stz_stress_ratio(stz_of(out, f), x[k]);
    const double want_I = stz::mu_of_I(mu_of_I_of(out, f), I[k]);
    ASSERT_TRUE(std::isfinite(want)) << k;
    EXPECT_EQ(prediction[k], want) << k;
    EXPECT_EQ(residual[k], mu[k] - want) << k;
    // μ(I) is NaN where its fit failed (said on stderr): the same value, or both NaN.
    EXPECT_TRUE(same(prediction_I[k], want_I)) << k << ": " << prediction_I[k] << " against " << want_I;
    EXPECT_TRUE(same(residual_I[k], mu[k] - want_I)) << k;
  }
}

// An incline-bulk table as pipelines/analysis/incline_bulk.py writes it (the columns gf-stz fit
// reads, the input column as variable-length strings as h5py writes them).
struct InclineRow {
  std::string input;
  double friction, restitution, nu, x, x_error, mu, mu_error, q, q_error;
  std::int64_t flowing;
};

void write_incline_table(const std::string& path, const std::vector<InclineRow>& rows) {
  const std::size_t n = rows.size();
  {
    io::AnalysisWriter w(path);
    io::Parameters p;
    p.set("program", "incline_bulk.py");
    w.write_parameters(p);
    std::vector<std::string> sha;
    std::vector<std::int64_t> flowing;
    for (std::size_t k = 0; k < n; ++k) {
      sha.push_back(std::string(64, char('a' + k)));
      flowing.push_back(rows[k].flowing);
    }
    w.write("/runs/input_sha256", sha, "");
    w.write("/runs/flowing", {n}, flowing, "", "1");
    auto column = [&](const char* name, double InclineRow::*member) {
      std::vector<double> v;
      for (const InclineRow& r : rows) v.push_back(r.*member);
      w.write(name, {n}, v, "", "1");  // every column here is a number
    };
    column("/runs/friction", &InclineRow::friction);
    column("/runs/restitution", &InclineRow::restitution);
    column("/bulk/packing_fraction", &InclineRow::nu);
    column("/bulk/inertial", &InclineRow::x);
    column("/bulk/inertial_error", &InclineRow::x_error);
    column("/bulk/s_over_p", &InclineRow::mu);
    column("/bulk/s_over_p_error", &InclineRow::mu_error);
    column("/bulk/mT_over_pR2", &InclineRow::q);
    column("/bulk/mT_over_pR2_error", &InclineRow::q_error);
    w.close();
  }
  io::File f = io::open_file(path, true);
  io::Datatype type(H5Tcopy(H5T_C_S1));
  H5Tset_size(type.get(), H5T_VARIABLE);
  H5Tset_cset(type.get(), H5T_CSET_UTF8);
  const hsize_t dims[1] = {n};
  const hid_t space = H5Screate_simple(1, dims, nullptr);
  const hid_t d = H5Dcreate2(f.get(), "/runs/input", type.get(), space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  std::vector<const char*> names;
  for (const InclineRow& r : rows) names.push_back(r.input.c_str());
  EXPECT_GE(H5Dwrite(d, type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, names.data()), 0);
  H5Dclose(d);
  H5Sclose(space);
}

}  // namespace

TEST(GfStzFit, RunsAreTheRatiosOfTheWindowMeans) {
  std::vector<std::string> runs = e0_runs();
  runs.push_back(e5_run());
  runs.push_back(friction_run());
  runs.push_back(reversed_run());
  ScratchDir dir("stz_fit_means");
  const std::string out = dir / "fit.h5";
  auto r = run_tool("gf-stz", "fit " + joined(runs) + "-o " + out + " --min-packing-fraction 0.77 --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto mu = read_doubles(out, "/runs/s_over_p"), x = read_doubles(out, "/runs/rate_R_over_sqrt_T"),
             I = read_doubles(out, "/runs/inertial_number"), friction = read_doubles(out, "/runs/friction"),
             restitution = read_doubles(out, "/runs/restitution"), nu = read_doubles(out, "/runs/packing_fraction");
  ASSERT_EQ(mu.size(), runs.size());
  const auto inputs = read_texts(out, "/runs/input"), kinds = read_texts(out, "/runs/kind");
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const Expected e = independent(runs[k]);
    EXPECT_EQ(inputs[k], runs[k]);
    EXPECT_EQ(kinds[k], "shear");
    EXPECT_LT(relative(mu[k], e.s_over_p), 1e-12) << runs[k];
    EXPECT_LT(relative(x[k], e.x), 1e-12) << runs[k];
    EXPECT_LT(relative(I[k], e.I), 1e-12) << runs[k];
    EXPECT_GT(mu[k], 0) << runs[k] << ": s/p of a sheared flow is positive whatever the sign of the rate";
    EXPECT_EQ(friction[k], e.friction);
    EXPECT_EQ(restitution[k], e.restitution);
    EXPECT_EQ(nu[k], e.nu);
  }
  for (const char* name : {"/runs/s_over_p_error", "/runs/rate_R_over_sqrt_T_error", "/runs/inertial_number_error"})
    for (double err : read_doubles(out, name)) EXPECT_TRUE(err > 0 && std::isfinite(err)) << name;
  // Every run's file by its hash; /parameters names the program, the command and each input.
  const auto hashes = read_texts(out, "/runs/input_sha256");
  for (std::size_t k = 0; k < runs.size(); ++k)
    EXPECT_EQ(hashes[k],
              string_attribute(out, "/parameters", k == 0 ? "input_sha256" : "input_" + std::to_string(k) + "_sha256"));
  EXPECT_EQ(string_attribute(out, "/parameters", "program"), "gf-stz");
  EXPECT_EQ(string_attribute(out, "/parameters", "command"), "fit");
}

TEST(GfStzFit, FitsTheDenseRunsOfTheGivenRestitutionPerFriction) {
  std::vector<std::string> runs = e0_runs();
  runs.push_back(e5_run());
  runs.push_back(friction_run());
  runs.push_back(reversed_run());
  ScratchDir dir("stz_fit_selection");
  const std::string out = dir / "fit.h5";
  auto r = run_tool("gf-stz", "fit " + joined(runs) + "-o " + out + " --min-packing-fraction 0.77");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // μ = 0.4 has a single e = 0 run: no fit, said on stderr.
  EXPECT_NE(r.err.find("friction 0.4: 1 fitted points, fewer than the 3 parameters: no fit"), std::string::npos)
      << r.err;
  const auto dense = read_flags(out, "/runs/dense"), fitted = read_flags(out, "/runs/fitted");
  // ν ≥ 0.77: all but the ν = 0.76 run; fitted: those at e = 0 (the e = 0.5 run is not).
  EXPECT_EQ(dense, (std::vector<std::uint8_t>{0, 1, 1, 1, 1, 1, 1}));
  EXPECT_EQ(fitted, (std::vector<std::uint8_t>{0, 1, 1, 1, 0, 1, 1}));
  EXPECT_EQ(read_doubles(out, "/fit/friction"), std::vector<double>{0});
  EXPECT_EQ(read_int64(out, "/fit/points"), std::vector<std::int64_t>{4});
  EXPECT_EQ(string_attribute(out, "/fit", "dense_rule"), "packing_fraction >= 0.77");
  EXPECT_EQ(string_attribute(out, "/fit", "objective"), "least-squares");

  // /fit is lib/stz's fit of the fitted rows, weighted by their s/p errors.
  const auto x = read_doubles(out, "/runs/rate_R_over_sqrt_T"), mu = read_doubles(out, "/runs/s_over_p"),
             mu_err = read_doubles(out, "/runs/s_over_p_error"), I = read_doubles(out, "/runs/inertial_number"),
             friction = read_doubles(out, "/runs/friction");
  std::vector<double> fx, fmu, ferr, fI;
  for (std::size_t k = 0; k < x.size(); ++k)
    if (fitted[k] && friction[k] == 0) {
      fx.push_back(x[k]);
      fmu.push_back(mu[k]);
      ferr.push_back(mu_err[k]);
      fI.push_back(I[k]);
    }
  const stz::StzFit want = stz::fit_stz(fx, fmu, ferr);
  const stz::StzCoefficients got = stz_of(out, 0);
  EXPECT_EQ(got.A, want.value.A);
  EXPECT_EQ(got.kappa, want.value.kappa);
  EXPECT_EQ(got.zeta, want.value.zeta);
  EXPECT_EQ(read_doubles(out, "/fit/kappa_error")[0], want.error.kappa);
  EXPECT_EQ(read_doubles(out, "/fit/tan_theta_star")[0], want.tan_theta_star);
  EXPECT_EQ(read_doubles(out, "/fit/theta_star")[0],
            want.theta_star * (180 / std::numbers::pi));  // the table's kDegrees
  EXPECT_EQ(read_doubles(out, "/fit/chi2")[0], want.chi2);
  EXPECT_EQ(read_int64(out, "/fit/dof")[0], 1);
  // Four points: too few for the jackknife (NaN), as the library says.
  EXPECT_TRUE(std::isnan(stz::stz_repose_jackknife_error(fx, fmu, ferr)));
  EXPECT_TRUE(std::isnan(read_doubles(out, "/fit/tan_theta_star_jackknife_error")[0]));
  const stz::MuIFit want_I = stz::fit_mu_of_I(fI, fmu, ferr);
  const stz::MuICoefficients got_I = mu_of_I_of(out, 0);
  EXPECT_EQ(got_I.mu_s, want_I.value.mu_s);
  EXPECT_EQ(got_I.mu_2, want_I.value.mu_2);
  EXPECT_EQ(got_I.I0, want_I.value.I0);
  const stz::LawComparison laws = stz::compare_laws(got, got_I, fx, fI, fmu);
  EXPECT_EQ(read_doubles(out, "/fit/stz_rms")[0], laws.stz_rms);
  EXPECT_EQ(read_doubles(out, "/fit/mu_of_I_rms")[0], laws.mu_of_I_rms);

  expect_predictions(out);
  // The predicted rms: the μ = 0 shear rows not fitted (ν = 0.76 and e = 0.5).
  const auto residual = read_doubles(out, "/runs/residual");
  EXPECT_EQ(read_int64(out, "/fit/predicted_count")[0], 2);
  EXPECT_DOUBLE_EQ(read_doubles(out, "/fit/predicted_rms")[0],
                   std::sqrt((residual[0] * residual[0] + residual[4] * residual[4]) / 2));
  EXPECT_EQ(read_int64(out, "/fit/incline_count")[0], 0);
  EXPECT_TRUE(std::isnan(read_doubles(out, "/fit/incline_rms")[0]));

  // --fit-restitution 0.5: a single point at μ = 0, none at μ = 0.4: no fit at all.
  r = run_tool("gf-stz", "fit " + joined(runs) + "-o " + out + ".2 --min-packing-fraction 0.77 --fit-restitution 0.5");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("fewer points than parameters"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out + ".2"));
}

TEST(GfStzFit, DenseByTheCorrelationTable) {
  // Seven frictionless e = 0 runs and a correlation table over them, ξ_el from the ν = 0.80 run.
  std::vector<std::string> runs = e0_runs();
  for (int seed : {4, 5, 6}) runs.push_back(run("e0_80_seed" + std::to_string(seed), "0.80", "--restitution 0", seed));
  ScratchDir dir("stz_fit_xi");
  const std::string table = dir / "correlation.h5", out = dir / "fit.h5";
  ASSERT_EQ(run_tool("gf-correlate", joined(runs) + "-o " + table + " --reference " + runs[2] + " --quiet").exit_code,
            0);
  // The table's rows in the order of its inputs: reversed here, so matching is by hash.
  std::vector<std::string> given(runs.rbegin(), runs.rend());
  const std::vector<double> xi_table = read_doubles(table, "/correlation/xi_ratio");
  std::vector<double> positive;
  for (double v : xi_table)
    if (v > 0) positive.push_back(v);
  ASSERT_GE(positive.size(), 3u);
  std::sort(positive.rbegin(), positive.rend());
  // The third largest ratio: the rule keeps at least three rows, and leaves out the others.
  const double R = positive[2];
  char ratio[64];
  std::snprintf(ratio, sizeof ratio, "%.17g", R);
  auto r = run_tool("gf-stz", "fit " + joined(given) + "-o " + out + " --correlation " + table +
                                  " --xi signed --dense-ratio " + ratio + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto xi = read_doubles(out, "/runs/xi_ratio");
  const auto dense = read_flags(out, "/runs/dense"), fitted = read_flags(out, "/runs/fitted");
  std::size_t count = 0;
  for (std::size_t k = 0; k < given.size(); ++k) {
    const double want = xi_table[runs.size() - 1 - k];
    EXPECT_EQ(xi[k], want) << k;
    EXPECT_EQ(dense[k], want >= R ? 1 : 0) << k;
    EXPECT_EQ(fitted[k], dense[k]) << k;
    count += dense[k];
  }
  EXPECT_GE(count, 3u);
  EXPECT_LT(count, given.size());
  EXPECT_EQ(read_int64(out, "/fit/points")[0], std::int64_t(count));
  EXPECT_EQ(string_attribute(out, "/fit", "dense_rule"), std::string("xi_ratio >= ") + ratio);
  expect_predictions(out);
}

// gf-correlate marks a run whose correlations reach the cell "not measurable" and keeps the
// ratio the cell allows: ξ is at least that long, so the ratio is a lower bound and a run with
// a bound at or above R is dense (the densest runs of a small cell are all such runs).
TEST(GfStzFit, ARatioBoundedByTheCellIsALowerBound) {
  std::vector<std::string> runs = e0_runs();
  for (int seed : {4, 5, 6}) runs.push_back(run("e0_80_seed" + std::to_string(seed), "0.80", "--restitution 0", seed));
  ScratchDir dir("stz_fit_xi_bound");
  const std::string table = dir / "correlation.h5", out = dir / "fit.h5";
  ASSERT_EQ(run_tool("gf-correlate", joined(runs) + "-o " + table + " --reference " + runs[2] + " --quiet").exit_code,
            0);
  const std::vector<double> ratio = read_doubles(table, "/correlation/xi_abs_ratio");
  std::vector<double> finite;
  for (double v : ratio)
    if (std::isfinite(v)) finite.push_back(v);
  ASSERT_GE(finite.size(), 4u);
  std::sort(finite.begin(), finite.end());
  // R = the third largest finite ratio (three dense runs, enough for a fit, when the bound
  // counts); the rows of the largest and the smallest marked as reaching the cell.
  const double R = finite[finite.size() - 3];
  std::vector<std::int32_t> measurable(ratio.size(), 1);
  for (std::size_t k = 0; k < ratio.size(); ++k)
    if (ratio[k] == finite.back() || ratio[k] == finite.front()) measurable[k] = 0;
  {
    io::File f = io::open_file(table, true);
    io::Dataset d = io::open_dataset(f.get(), "/correlation/measurable");
    ASSERT_GE(H5Dwrite(d.get(), H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, measurable.data()), 0);
  }
  char text[64];
  std::snprintf(text, sizeof text, "%.17g", R);
  const auto r = run_tool("gf-stz", "fit " + joined(runs) + "-o " + out + " --correlation " + table +
                                        " --dense-ratio " + text + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto xi = read_doubles(out, "/runs/xi_ratio");
  const auto dense = read_flags(out, "/runs/dense");
  const auto xi_measurable = read_flags(out, "/runs/xi_measurable");
  for (std::size_t k = 0; k < runs.size(); ++k) {
    EXPECT_EQ(xi[k], ratio[k]) << k;
    EXPECT_EQ(xi_measurable[k], measurable[k]) << k;
    EXPECT_EQ(dense[k], std::isfinite(ratio[k]) && ratio[k] >= R ? 1 : 0) << k;
  }
}

TEST(GfStzFit, InclineRowsArePredictedNeverFitted) {
  std::vector<std::string> runs = e0_runs();
  runs.push_back(friction_run());
  ScratchDir dir("stz_fit_incline");
  const std::string bulk = dir / "bulk.h5", out = dir / "fit.h5";
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // Two flowing rows at μ = 0, one at μ = 0.4 (no fit there), one not flowing.
  const std::vector<InclineRow> rows = {
      {"incline_a.h5", 0, 0, 0.79, 0.30, 0.01, 0.33, 0.005, 2.5, 0.1, 1},
      {"incline_b.h5", 0, 0, 0.78, 0.40, 0.02, 0.37, 0.006, 1.5, 0.05, 1},
      {"incline_c.h5", 0.4, 0, 0.80, 0.20, 0.01, 0.45, 0.01, 3.0, 0.1, 1},
      {"incline_d.h5", 0, 0, 0.82, nan, nan, nan, nan, nan, nan, 0},
  };
  write_incline_table(bulk, rows);
  auto r = run_tool(
      "gf-stz", "fit " + joined(runs) + "-o " + out + " --min-packing-fraction 0.77 --incline " + bulk + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto kinds = read_texts(out, "/runs/kind"), inputs = read_texts(out, "/runs/input");
  ASSERT_EQ(kinds.size(), runs.size() + 3);
  const auto x = read_doubles(out, "/runs/rate_R_over_sqrt_T"), I = read_doubles(out, "/runs/inertial_number"),
             I_err = read_doubles(out, "/runs/inertial_number_error"), mu = read_doubles(out, "/runs/s_over_p"),
             residual = read_doubles(out, "/runs/residual");
  const auto fitted = read_flags(out, "/runs/fitted");
  for (std::size_t j = 0; j < 3; ++j) {
    const std::size_t k = runs.size() + j;
    const InclineRow& in = rows[j];
    EXPECT_EQ(kinds[k], "incline");
    EXPECT_EQ(inputs[k], in.input);
    EXPECT_EQ(fitted[k], 0);
    EXPECT_EQ(x[k], in.x);
    EXPECT_EQ(mu[k], in.mu);
    // I = 2x√(ρ_p T/p) with ρ_p = m/(π⟨R⟩²), T/p = q⟨R⟩²/m.
    const double want_I = 2 * in.x * std::sqrt(in.q / std::numbers::pi);
    EXPECT_LT(relative(I[k], want_I), 1e-14);
    EXPECT_LT(relative(I_err[k], want_I * std::hypot(in.x_error / in.x, in.q_error / (2 * in.q))), 1e-14);
  }
  expect_predictions(out);
  EXPECT_EQ(read_int64(out, "/fit/incline_count")[0], 2);
  const std::size_t a = runs.size(), b = runs.size() + 1;
  EXPECT_DOUBLE_EQ(read_doubles(out, "/fit/incline_rms")[0],
                   std::sqrt((residual[a] * residual[a] + residual[b] * residual[b]) / 2));
  EXPECT_EQ(string_attribute(out, "/parameters", "incline"), bulk);
}

TEST(GfStzFit, OrthogonalDistanceUsesBothErrors) {
  std::vector<std::string> runs = e0_runs();
  runs.push_back(reversed_run());
  ScratchDir dir("stz_fit_odr");
  const std::string out = dir / "fit.h5";
  auto r = run_tool(
      "gf-stz", "fit " + joined(runs) + "-o " + out + " --min-packing-fraction 0.77 --objective orthogonal --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(string_attribute(out, "/fit", "objective"), "orthogonal");
  const auto x = read_doubles(out, "/runs/rate_R_over_sqrt_T"),
             x_err = read_doubles(out, "/runs/rate_R_over_sqrt_T_error"), mu = read_doubles(out, "/runs/s_over_p"),
             mu_err = read_doubles(out, "/runs/s_over_p_error");
  const auto fitted = read_flags(out, "/runs/fitted");
  std::vector<double> fx, fxe, fmu, fmue;
  for (std::size_t k = 0; k < x.size(); ++k)
    if (fitted[k]) {
      fx.push_back(x[k]);
      fxe.push_back(x_err[k]);
      fmu.push_back(mu[k]);
      fmue.push_back(mu_err[k]);
    }
  ASSERT_EQ(fx.size(), 4u);
  const stz::StzFit want = stz::fit_stz(fx, fmu, fmue, fxe, stz::StzObjective::orthogonal_distance);
  const stz::StzCoefficients got = stz_of(out, 0);
  EXPECT_EQ(got.A, want.value.A);
  EXPECT_EQ(got.kappa, want.value.kappa);
  EXPECT_EQ(got.zeta, want.value.zeta);
  EXPECT_EQ(read_doubles(out, "/fit/zeta_error")[0], want.error.zeta);
  expect_predictions(out);
}

class GfStzFitBadInput : public ::testing::TestWithParam<BadInput> {};

TEST_P(GfStzFitBadInput, FailsWithExitTwoOneLineNoOutput) {
  static ScratchDir dir("stz_fit_bad_inputs");
  const std::vector<std::string> runs = e0_runs();
  static const std::string copy = [&] {
    const std::string path = dir / "copy.h5";
    std::filesystem::copy_file(runs[1], path);
    return path;
  }();
  static const std::string truncated = [&] {
    const std::string path = dir / "truncated.h5";
    std::ifstream in(runs[0], std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(path, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    return path;
  }();
  static const std::string text = [&] {
    const std::string path = dir / "text.h5";
    std::ofstream(path) << "not a table\n";
    return path;
  }();
  static const std::string unsheared = [&] {
    const std::string path = dir / "unsheared.h5";
    EXPECT_EQ(
        run_tool("gf-shear", "-i " + packing("0.80") + " -o " + path + " --rate 0 --steps 100 --temperature 1 --quiet")
            .exit_code,
        0);
    return path;
  }();
  // A correlation table over other runs, and one without --reference.
  static const std::string other = [&] {
    const std::string path = dir / "other.h5";
    EXPECT_EQ(run_tool("gf-correlate", e5_run() + " -o " + path + " --reference " + e5_run() + " --quiet").exit_code,
              0);
    return path;
  }();
  static const std::string noref = [&] {
    const std::string path = dir / "noref.h5";
    EXPECT_EQ(run_tool("gf-correlate", joined(runs) + "-o " + path + " --quiet").exit_code, 0);
    return path;
  }();
  // An incline-bulk table whose /bulk columns are one row short of /runs.
  static const std::string short_bulk = [&] {
    const std::string path = dir / "short_bulk.h5";
    write_incline_table(path, {{"a.h5", 0, 0, 0.8, 0.3, 0.01, 0.3, 0.01, 2, 0.1, 1},
                               {"b.h5", 0, 0, 0.8, 0.4, 0.01, 0.35, 0.01, 2, 0.1, 1}});
    io::File f = io::open_file(path, true);
    H5Ldelete(f.get(), "/bulk/s_over_p", H5P_DEFAULT);
    const double one = 0.3;
    io::write_dataset<double>(f.get(), "/bulk/s_over_p", {1}, &one);
    return path;
  }();
  const std::string all = runs[0] + " " + runs[1] + " " + runs[2] + " " + runs[3];
  expect_refused("gf-stz", GetParam(),
                 {{"{all}", all},
                  {"{run}", runs[1]},
                  {"{copy}", copy},
                  {"{truncated}", truncated},
                  {"{text}", text},
                  {"{unsheared}", unsheared},
                  {"{other}", other},
                  {"{noref}", noref},
                  {"{short}", short_bulk},
                  {"{pack}", packing("0.80")}},
                 " --quiet");
}

INSTANTIATE_TEST_SUITE_P(
    Cases, GfStzFitBadInput,
    ::testing::Values(
        BadInput{"no_dense_rule", "fit {all} -o {out}", "no dense rule"},
        BadInput{"both_dense_rules", "fit {all} -o {out} --min-packing-fraction 0.7 --correlation {other}",
                 "--min-packing-fraction"},
        BadInput{"dense_ratio_zero", "fit {all} -o {out} --correlation {other} --dense-ratio 0", "--dense-ratio"},
        BadInput{"dense_ratio_without_table", "fit {all} -o {out} --min-packing-fraction 0.7 --dense-ratio 2",
                 "--dense-ratio"},
        BadInput{"unknown_objective", "fit {all} -o {out} --min-packing-fraction 0.7 --objective log", "--objective"},
        BadInput{"unknown_xi", "fit {all} -o {out} --correlation {other} --xi both", "--xi"},
        BadInput{"output_among_inputs", "fit {all} -o {run} --min-packing-fraction 0.7",
                 "is the same file as the input"},
        BadInput{"run_given_twice", "fit {all} {copy} -o {out} --min-packing-fraction 0.7", "given twice"},
        BadInput{"not_sheared", "fit {all} {unsheared} -o {out} --min-packing-fraction 0.7", "not sheared"},
        BadInput{"a_packing", "fit {all} {pack} -o {out} --min-packing-fraction 0.7", "is a packing"},
        BadInput{"missing_file", "fit {all} {out}.missing -o {out} --min-packing-fraction 0.7", "no such file"},
        BadInput{"truncated_file", "fit {all} {truncated} -o {out} --min-packing-fraction 0.7", "truncated.h5"},
        BadInput{"not_hdf5", "fit {all} {text} -o {out} --min-packing-fraction 0.7", "text.h5"},
        BadInput{"run_not_in_correlation_table", "fit {all} -o {out} --correlation {other}",
                 "not among the runs of the correlation table"},
        BadInput{"correlation_without_reference", "fit {all} -o {out} --correlation {noref}",
                 "made without --reference (gf-stz fit needs xi_el"},
        BadInput{"correlation_not_a_table", "fit {all} -o {out} --correlation {run}", "not a gf-correlate table"},
        BadInput{"incline_not_a_table", "fit {all} -o {out} --min-packing-fraction 0.7 --incline {run}",
                 "not an incline-bulk table"},
        BadInput{"incline_columns_differ", "fit {all} -o {out} --min-packing-fraction 0.7 --incline {short}",
                 "differ in length: not an incline-bulk table"},
        BadInput{"incline_missing", "fit {all} -o {out} --min-packing-fraction 0.7 --incline {out}.missing",
                 "no such file"},
        BadInput{"incline_given_twice",
                 "fit {all} -o {out} --min-packing-fraction 0.7 --incline {text} --incline {text}",
                 "option --incline: given 2 times"},
        BadInput{"incline_not_hdf5", "fit {all} -o {out} --min-packing-fraction 0.7 --incline {text}",
                 "not an HDF5 file"},
        BadInput{"fewer_points_than_parameters", "fit {all} -o {out} --min-packing-fraction 0.9",
                 "fewer points than parameters"},
        BadInput{"from_strain_past_the_end", "fit {all} -o {out} --min-packing-fraction 0.7 --from-strain 3",
                 "past the end of the run"}),
    bad_input_name);
