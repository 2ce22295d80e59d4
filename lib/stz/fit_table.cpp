#include "stz/fit_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <numbers>
#include <stdexcept>

#include "core/error.hpp"
#include "core/format.hpp"
#include "core/sha256.hpp"
#include "core/signals.hpp"
#include "correlation/table_lookup.hpp"
#include "io/analysis_writer.hpp"
#include "io/hdf5_handle.hpp"
#include "io/run_identity.hpp"
#include "io/table_writer.hpp"
#include "statistics/delta.hpp"

namespace granflow::stz {

namespace {

using statistics::delta_error;
using statistics::mean;

std::vector<double> tail(const std::vector<double>& x, std::size_t first) {
  return std::vector<double>(x.begin() + std::ptrdiff_t(first), x.end());
}

// A one-dimensional dataset of strings, variable-length (h5py) or fixed-length (granflow).
std::vector<std::string> read_strings(hid_t dataset) {
  io::Datatype type(io::check(H5Dget_type(dataset), dataset, "get type"));
  if (H5Tget_class(type.get()) != H5T_STRING) throw io::Hdf5Error(io::where(dataset) + ": not strings");
  const std::vector<hsize_t> dims = io::shape(dataset);
  if (dims.size() != 1) throw io::Hdf5Error(io::where(dataset) + ": expected one dimension");
  const std::size_t count = dims[0];
  std::vector<std::string> values;
  if (io::check(H5Tis_variable_str(type.get()), dataset, "inspect string type") > 0) {
    io::Datatype mem(io::check(H5Tcopy(H5T_C_S1), dataset, "copy string type"));
    H5Tset_size(mem.get(), H5T_VARIABLE);
    H5Tset_cset(mem.get(), H5Tget_cset(type.get()));
    std::vector<char*> pointers(count, nullptr);
    io::check(H5Dread(dataset, mem.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, pointers.data()), dataset, "read");
    for (char* p : pointers) {
      values.emplace_back(p ? p : "");
      H5free_memory(p);
    }
  } else {
    const std::size_t width = H5Tget_size(type.get());
    std::string packed(width * count, '\0');
    if (count > 0)
      io::check(H5Dread(dataset, type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, packed.data()), dataset, "read");
    for (std::size_t i = 0; i < count; ++i) {
      std::string v = packed.substr(i * width, width);
      v.resize(std::min(v.find('\0'), v.size()));
      values.push_back(std::move(v));
    }
  }
  return values;
}

double rms(const std::vector<double>& residuals) {
  if (residuals.empty()) return kNaN;
  double sum = 0;
  for (double r : residuals) sum += r * r;
  return std::sqrt(sum / double(residuals.size()));
}

bool positive_finite(double x) { return x > 0 && std::isfinite(x); }

// The shortest decimal text that reads back as x (for the dense rule's threshold).
std::string exact_text(double x) {
  for (int digits = 6; digits < 17; ++digits) {
    const std::string text = format_number(x, digits);
    if (std::strtod(text.c_str(), nullptr) == x) return text;
  }
  return format_number(x, 17);
}

}  // namespace

FitRunRow read_shear_row(const std::string& path, const shear_run::WindowSettings& window) {
  const shear_run::Opened o = shear_run::open(path, "gf-stz fit");
  auto bad = [&](const std::string& what) { return UsageError("'" + path + "': " + what); };
  if (!(o.rate != 0) || !std::isfinite(o.rate))
    throw bad("not sheared (shear rate " + format_number(o.rate) + "): gf-stz fit needs steady shear runs");
  const shear_run::Window w = shear_run::window(o, path, window);
  const io::RunIdentity id = io::read_run_identity(o.reader, o.parameters, path, {.hash = true, .dt = false});

  FitRunRow row;
  row.input = path;
  row.input_sha256 = id.sha256;
  row.kind = "shear";
  row.friction = id.friction;
  row.restitution = id.restitution;
  row.packing_fraction = id.packing_fraction;

  const io::GrainProperties grains = o.reader.grains();
  double mass = 0, area = 0;
  for (std::size_t i = 0; i < grains.radius.size(); ++i) {
    mass += grains.mass[i];
    area += std::numbers::pi * grains.radius[i] * grains.radius[i];
  }
  const double mean_radius = mean(grains.radius), density = mass / area;

  const std::size_t f = w.first_row;
  const std::vector<double> T = tail(shear_run::observable(o, path, "temperature"), f);
  const std::vector<double> P = tail(shear_run::observable(o, path, "pressure"), f);
  std::vector<double> S = tail(shear_run::observable(o, path, "shear_stress"), f);
  // γ̇ < 0 is the mirror image x → −x of a run at |γ̇|: its s = −Σxy is negative.
  if (o.rate < 0)
    for (double& s : S) s = -s;
  const double rate = std::fabs(o.rate);
  const double t = mean(T), pm = mean(P), sm = mean(S);
  if (!(t > 0) || !(pm > 0))
    throw bad("non-positive mean temperature or pressure over the window (T = " + format_number(t) +
              ", p = " + format_number(pm) + ")");
  row.s_over_p = sm / pm;
  row.s_over_p_error = delta_error({{S, 1 / pm}, {P, -sm / (pm * pm)}});
  row.rate_R_over_sqrt_T = rate * mean_radius / std::sqrt(t);
  row.rate_R_over_sqrt_T_error = delta_error({{T, -row.rate_R_over_sqrt_T / (2 * t)}});
  row.inertial_number = rate * 2 * mean_radius / std::sqrt(pm / density);
  row.inertial_number_error = delta_error({{P, -row.inertial_number / (2 * pm)}});
  return row;
}

std::vector<FitRunRow> read_incline_rows(const std::string& path) {
  auto bad = [&](const std::string& what) { return UsageError("'" + path + "': " + what); };
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw bad("no such file");
  io::silence_hdf5_errors();
#if H5_VERSION_GE(1, 12, 0)
  const htri_t is_hdf5 = H5Fis_accessible(path.c_str(), H5P_DEFAULT);
#else
  const htri_t is_hdf5 = H5Fis_hdf5(path.c_str());
#endif
  if (is_hdf5 < 0) throw bad("cannot read: " + io::hdf5_reason());
  if (is_hdf5 == 0) throw bad("not an HDF5 file");
  try {
    const io::File file = io::open_file(path, false);
    const hid_t f = file.get();
    std::string program;
    if (io::exists(f, "/parameters")) {
      const io::Group g = io::open_group(f, "/parameters");
      if (io::has_attribute(g.get(), "program")) {
        const io::Attribute a = io::open_attribute(g.get(), "program");
        if (io::attribute_class(a.get()) == H5T_STRING) program = io::read_string_attribute(a.get());
      }
    }
    if (program != "incline_bulk.py")
      throw bad("not an incline-bulk table (/parameters program is not incline_bulk.py); --incline needs one");
    auto strings = [&](const std::string& name) {
      if (!io::exists(f, name)) throw bad("no " + name + ": not an incline-bulk table");
      return read_strings(io::open_dataset(f, name).get());
    };
    auto doubles = [&](const std::string& name) {
      if (!io::exists(f, name)) throw bad("no " + name + ": not an incline-bulk table");
      return io::read_all<double>(io::open_dataset(f, name).get());
    };
    const std::vector<std::string> input = strings("/runs/input"), sha = strings("/runs/input_sha256");
    const std::vector<std::int64_t> flowing = [&] {
      if (!io::exists(f, "/runs/flowing")) throw bad("no /runs/flowing: not an incline-bulk table");
      return io::read_all<std::int64_t>(io::open_dataset(f, "/runs/flowing").get());
    }();
    const std::vector<double> friction = doubles("/runs/friction"), restitution = doubles("/runs/restitution"),
                              nu = doubles("/bulk/packing_fraction"), x = doubles("/bulk/inertial"),
                              x_error = doubles("/bulk/inertial_error"), mu = doubles("/bulk/s_over_p"),
                              mu_error = doubles("/bulk/s_over_p_error"), q = doubles("/bulk/mT_over_pR2"),
                              q_error = doubles("/bulk/mT_over_pR2_error");
    const std::size_t n = input.size();
    for (std::size_t size : {sha.size(), flowing.size(), friction.size(), restitution.size(), nu.size(), x.size(),
                             x_error.size(), mu.size(), mu_error.size(), q.size(), q_error.size()})
      if (size != n) throw bad("its /runs and /bulk columns differ in length: not an incline-bulk table");
    std::vector<FitRunRow> rows;
    for (std::size_t k = 0; k < n; ++k) {
      if (flowing[k] != 1) continue;
      FitRunRow r;
      r.input = input[k];
      r.input_sha256 = sha[k];
      r.kind = "incline";
      r.friction = friction[k];
      r.restitution = restitution[k];
      r.packing_fraction = nu[k];
      r.rate_R_over_sqrt_T = x[k];
      r.rate_R_over_sqrt_T_error = x_error[k];
      r.s_over_p = mu[k];
      r.s_over_p_error = mu_error[k];
      // I = 2x√(ρ_p T/p) with ρ_p = m̄/(π⟨R⟩²): 2x√(q/π).
      if (q[k] > 0 && x[k] >= 0) {
        r.inertial_number = 2 * x[k] * std::sqrt(q[k] / std::numbers::pi);
        r.inertial_number_error = r.inertial_number * std::hypot(x_error[k] / x[k], q_error[k] / (2 * q[k]));
      }
      rows.push_back(r);
    }
    return rows;
  } catch (const io::Hdf5Error& e) {
    throw UsageError("'" + path + "': " + e.what());
  }
}

namespace {

// The shear rows of the runs, each read once (a run given twice, by its SHA-256, is refused).
std::vector<FitRunRow> read_shear_rows(const std::vector<std::string>& runs, const FitSettings& settings) {
  std::vector<FitRunRow> rows;
  std::map<std::string, std::string> seen;  // sha256 → path
  for (const std::string& path : runs) {
    FitRunRow row = read_shear_row(path, settings.window);
    check_interrupt();
    const auto [it, fresh] = seen.emplace(row.input_sha256, path);
    if (!fresh) throw UsageError("'" + path + "': the same run as '" + it->second + "' (same sha256): given twice");
    rows.push_back(std::move(row));
  }
  return rows;
}

// Marks the dense shear rows: by ξ/ξ_el of the correlation table (by_xi), else by ν.
void mark_dense(FitTable& table, const std::vector<std::string>& runs, const FitSettings& settings, bool by_xi) {
  if (!by_xi) {
    for (FitRunRow& r : table.runs) r.dense = r.packing_fraction >= settings.min_packing_fraction;
    return;
  }
  const std::vector<correlation::XiValue> xi = correlation::read_xi_ratios(
      settings.correlation, runs,
      settings.signed_xi ? correlation::XiReading::signed_area : correlation::XiReading::abs, "gf-stz fit");
  // A ratio gf-correlate calls not measurable is the one the cell allows (the correlations
  // reach it): ξ is at least that long, so the ratio is a lower bound and still decides.
  for (std::size_t k = 0; k < runs.size(); ++k) {
    table.runs[k].xi_ratio = xi[k].ratio;
    table.runs[k].xi_measurable = xi[k].measurable;
    table.runs[k].dense = std::isfinite(xi[k].ratio) && xi[k].ratio >= settings.dense_ratio;
  }
}

// Marks the fitted rows (dense, at the fitted restitution, x, s/p and I > 0 and finite);
// returns the dense rows at that restitution left out, and why.
std::vector<std::string> mark_fitted(FitTable& table, const FitSettings& settings) {
  std::vector<std::string> left_out;
  for (FitRunRow& r : table.runs) {
    const bool candidate = r.dense && r.restitution == settings.fit_restitution;
    r.fitted = candidate && positive_finite(r.rate_R_over_sqrt_T) && positive_finite(r.s_over_p) &&
               positive_finite(r.inertial_number);
    if (candidate && !r.fitted)
      left_out.push_back("'" + r.input + "' (x = " + format_number(r.rate_R_over_sqrt_T) +
                         ", s/p = " + format_number(r.s_over_p) + ", I = " + format_number(r.inertial_number) +
                         "; each must be > 0 and finite)");
  }
  for (const std::string& run : left_out) table.notes.push_back("left out of the fit: " + run);
  return left_out;
}

// The frictions with a fitted row, increasing; a note for each friction of shear rows without one.
std::vector<double> fitted_frictions(FitTable& table, const FitSettings& settings) {
  std::vector<double> frictions;
  for (const FitRunRow& r : table.runs)
    if (r.fitted && std::find(frictions.begin(), frictions.end(), r.friction) == frictions.end())
      frictions.push_back(r.friction);
  std::sort(frictions.begin(), frictions.end());
  std::vector<double> unfitted;  // frictions of shear rows without a single fitted point
  for (const FitRunRow& r : table.runs)
    if (r.kind == "shear" && std::find(frictions.begin(), frictions.end(), r.friction) == frictions.end() &&
        std::find(unfitted.begin(), unfitted.end(), r.friction) == unfitted.end())
      unfitted.push_back(r.friction);
  for (const double mu : unfitted)
    table.notes.push_back("friction " + format_number(mu) + ": no fitted point (restitution " +
                          format_number(settings.fit_restitution) + " and dense): no fit");
  return frictions;
}

// The points of one friction's fit: x, s/p, I and their errors (cleared when a point has none).
struct FitPoints {
  std::vector<double> x, y, x_err, y_err, I;
};

FitPoints fit_points(FitTable& table, const std::vector<std::size_t>& points, double mu, const FitSettings& settings) {
  FitPoints p;
  bool weighted = true;
  for (std::size_t k : points) {
    const FitRunRow& r = table.runs[k];
    p.x.push_back(r.rate_R_over_sqrt_T);
    p.y.push_back(r.s_over_p);
    p.I.push_back(r.inertial_number);
    p.x_err.push_back(r.rate_R_over_sqrt_T_error);
    p.y_err.push_back(r.s_over_p_error);
    weighted = weighted && positive_finite(r.rate_R_over_sqrt_T_error) && positive_finite(r.s_over_p_error);
  }
  if (!weighted && settings.objective == StzObjective::orthogonal_distance)
    throw UsageError("friction " + format_number(mu) +
                     ": --objective orthogonal needs the errors of x and s/p of every fitted point (a run's window "
                     "too short for an error?)");
  if (!weighted) {
    p.x_err.clear();
    p.y_err.clear();
    table.notes.push_back("friction " + format_number(mu) +
                          ": a fitted point has no error: fits unweighted (errors from the scatter)");
  }
  return p;
}

// The STZ law and μ(I) fitted to one friction's points.
FitRow fit_laws(FitTable& table, const FitPoints& p, std::size_t points, double mu, const FitSettings& settings) {
  FitRow fit;
  fit.friction = mu;
  fit.points = std::int64_t(points);
  try {
    fit.stz = fit_stz(p.x, p.y, p.y_err, p.x_err, settings.objective);
    fit.tan_theta_star_jackknife_error = stz_repose_jackknife_error(p.x, p.y, p.y_err, p.x_err, settings.objective);
  } catch (const std::exception& e) {
    throw RuntimeFailure("friction " + format_number(mu) + ": the STZ fit failed: " + e.what());
  }
  fit.dof = fit.stz.dof;
  try {
    fit.mu_of_I = fit_mu_of_I(p.I, p.y, p.y_err);
    fit.has_mu_of_I = true;
  } catch (const std::exception& e) {
    table.notes.push_back("friction " + format_number(mu) + ": the mu(I) fit failed (" + e.what() +
                          "): its columns are NaN");
  }
  const LawComparison laws =
      compare_laws(fit.stz.value, fit.has_mu_of_I ? fit.mu_of_I.value : MuICoefficients{}, p.x, p.I, p.y);
  fit.stz_rms = laws.stz_rms;
  fit.mu_of_I_rms = fit.has_mu_of_I ? laws.mu_of_I_rms : kNaN;
  return fit;
}

// Each row of the fit's friction: its predictions and residuals; the fit: the rms residuals
// of the rows it did not fit (shear and incline).
void predict_rows(FitTable& table, FitRow& fit) {
  std::vector<double> predicted, incline, mi_predicted, mi_incline;
  for (FitRunRow& r : table.runs) {
    if (r.friction != fit.friction) continue;
    r.prediction = stz_stress_ratio(fit.stz.value, r.rate_R_over_sqrt_T);
    r.residual = r.s_over_p - r.prediction;
    if (fit.has_mu_of_I) {
      r.prediction_mu_of_I = mu_of_I(fit.mu_of_I.value, r.inertial_number);
      r.residual_mu_of_I = r.s_over_p - r.prediction_mu_of_I;
    }
    if (r.fitted) continue;
    auto& stz_list = r.kind == "shear" ? predicted : incline;
    auto& mi_list = r.kind == "shear" ? mi_predicted : mi_incline;
    if (std::isfinite(r.residual)) stz_list.push_back(r.residual);
    if (std::isfinite(r.residual_mu_of_I)) mi_list.push_back(r.residual_mu_of_I);
  }
  fit.predicted_rms = rms(predicted);
  fit.predicted_count = std::int64_t(predicted.size());
  fit.incline_rms = rms(incline);
  fit.incline_count = std::int64_t(incline.size());
  fit.mu_of_I_predicted_rms = rms(mi_predicted);
  fit.mu_of_I_incline_rms = rms(mi_incline);
}

}  // namespace

FitTable analyse_fit(const std::vector<std::string>& runs, const FitSettings& settings) {
  if (runs.empty()) throw UsageError("no input run");
  const bool by_xi = !settings.correlation.empty();
  if (!by_xi && !std::isfinite(settings.min_packing_fraction))
    throw UsageError(
        "no dense rule: give --correlation TABLE.h5 (xi/xi_el >= --dense-ratio) or "
        "--min-packing-fraction NU");
  if (by_xi && !(settings.dense_ratio > 0))
    throw UsageError("option --dense-ratio: must be > 0, got " + format_number(settings.dense_ratio));

  FitTable table;
  table.settings = settings;
  table.runs = read_shear_rows(runs, settings);
  mark_dense(table, runs, settings, by_xi);
  const std::vector<std::string> left_out = mark_fitted(table, settings);
  for (const std::string& path : settings.incline)
    for (FitRunRow& r : read_incline_rows(path)) {
      // The incline bulk has no correlation-table entry: dense only by the packing-fraction rule.
      r.dense = !by_xi && r.packing_fraction >= settings.min_packing_fraction;
      table.runs.push_back(std::move(r));
    }

  for (const double mu : fitted_frictions(table, settings)) {
    std::vector<std::size_t> points;
    for (std::size_t k = 0; k < table.runs.size(); ++k)
      if (table.runs[k].fitted && table.runs[k].friction == mu) points.push_back(k);
    if (points.size() < 3) {
      table.notes.push_back("friction " + format_number(mu) + ": " + std::to_string(points.size()) +
                            " fitted points, fewer than the 3 parameters: no fit");
      continue;
    }
    FitRow fit = fit_laws(table, fit_points(table, points, mu, settings), points.size(), mu, settings);
    predict_rows(table, fit);
    table.fits.push_back(fit);
  }
  if (table.fits.empty())
    throw UsageError("fewer points than parameters: no friction coefficient has 3 fitted runs (restitution " +
                     format_number(settings.fit_restitution) + ", dense by " +
                     (by_xi ? "xi/xi_el >= " + format_number(settings.dense_ratio)
                            : "packing fraction >= " + format_number(settings.min_packing_fraction)) +
                     ")" +
                     (left_out.empty()
                          ? ""
                          : "; left out of the fit: " + left_out.front() +
                                (left_out.size() > 1 ? " and " + std::to_string(left_out.size() - 1) + " more" : "")));
  return table;
}

const std::vector<io::RowColumn<FitRunRow>>& run_columns() {
  using Row = FitRunRow;
  using io::flag, io::real, io::text;
  static const std::vector<io::RowColumn<Row>> columns = {
      text("input", "path of the run (shear) or of the incline run as its table gives it (incline)", &Row::input),
      text("input_sha256", "SHA-256 of that file", &Row::input_sha256),
      text("kind", "shear: a RUN.h5; incline: a flowing row of an --incline table", &Row::kind),
      real(io::identity_column("friction"), &Row::friction),
      real(io::identity_column("restitution"), &Row::restitution),
      real("packing_fraction", "1", "ν: the run's /parameters (shear), the bulk mean (incline)",
           &Row::packing_fraction),
      real("rate_R_over_sqrt_T", "1",
           "x = |γ̇|⟨R⟩/√T̄, T the temperature observable (eq. 4.5) over the window (shear); /bulk/inertial (incline)",
           &Row::rate_R_over_sqrt_T,
           "its error: delta method over the blocked standard error (shear); /bulk/inertial_error (incline)",
           &Row::rate_R_over_sqrt_T_error),
      real("s_over_p", "1",
           "μ = s̄/p̄, s = −Σxy and p of the total stress over the window (shear); /bulk/s_over_p (incline)",
           &Row::s_over_p,
           "its error: delta method over the blocked standard errors (shear); /bulk/s_over_p_error (incline)",
           &Row::s_over_p_error),
      real("inertial_number", "1",
           "I = |γ̇|d/√(p̄/ρ_p), d = 2⟨R⟩, ρ_p = Σm/Σ(πR²) (shear); 2x√(q/π), q = /bulk/mT_over_pR2 (incline)",
           &Row::inertial_number,
           "its error: delta method (shear); relative errors of x and √q in quadrature (incline)",
           &Row::inertial_number_error),
      real("xi_ratio", "1",
           "ξ/ξ_el of the correlation table, a lower bound where xi_measurable is 0 (NaN: no table, an incline row, "
           "or no value)",
           &Row::xi_ratio),
      flag("xi_measurable",
           "the correlation table's measurable flag (0: the correlations reach the cell, xi_ratio is a lower bound; "
           "0 without a table)",
           &Row::xi_measurable),
      flag("dense", "1 if dense by the rule of /fit's dense_rule", &Row::dense),
      flag("fitted",
           "1 if a point of its friction's fit: a shear row, restitution = fit_restitution, dense, x, s/p and I > 0",
           &Row::fitted),
      real("prediction", "1", "STZ s/p at the row's x with the fit of its friction (NaN: no fit for that friction)",
           &Row::prediction),
      real("residual", "1", "s_over_p − prediction", &Row::residual),
      real("prediction_mu_of_I", "1", "μ(I) at the row's I with the fit of its friction (NaN: no fit)",
           &Row::prediction_mu_of_I),
      real("residual_mu_of_I", "1", "s_over_p − prediction_mu_of_I", &Row::residual_mu_of_I)};
  return columns;
}

const std::vector<io::RowColumn<FitRow>>& fit_columns() {
  using Row = FitRow;
  using io::integer;
  constexpr double kDegrees = 180 / std::numbers::pi;
  // A real column (with its error column when error_meaning is given) read by functions of the row.
  using Read = std::function<double(const Row&)>;
  auto real = [](std::string name, std::string units, std::string meaning, Read value, std::string error_meaning = {},
                 Read error = {}) {
    std::string error_name = error ? name + "_error" : std::string();
    return io::real<Row>(
        {std::move(name), std::move(units), std::move(meaning), std::move(error_name), std::move(error_meaning)},
        std::move(value), std::move(error));
  };
  // μ(I)'s values are NaN where the fit has none.
  auto mu_of_I = [](double MuICoefficients::*member, bool error) {
    return [member, error](const Row& f) {
      return f.has_mu_of_I ? (error ? f.mu_of_I.error : f.mu_of_I.value).*member : kNaN;
    };
  };
  auto coefficient = [](double StzCoefficients::*member, bool error) {
    return [member, error](const Row& f) { return (error ? f.stz.error : f.stz.value).*member; };
  };
  static const std::vector<io::RowColumn<Row>> columns = {
      real("friction", "1", "Coulomb friction μ of the fitted runs", [](const Row& f) { return f.friction; }),
      integer("points", "1", "fitted runs (rows of /runs with fitted = 1 and this friction)", &Row::points),
      real("A", "1", "A of eq. 6.36", coefficient(&StzCoefficients::A, false), "standard error of A",
           coefficient(&StzCoefficients::A, true)),
      real("kappa", "1", "κ of eq. 6.36", coefficient(&StzCoefficients::kappa, false), "standard error of κ",
           coefficient(&StzCoefficients::kappa, true)),
      real("zeta", "1", "ζ of eq. 6.36", coefficient(&StzCoefficients::zeta, false), "standard error of ζ",
           coefficient(&StzCoefficients::zeta, true)),
      real(
          "tan_theta_star", "1", "tanθ*, root of ζ t tanh(κt) = 1 (eq. 6.35)",
          [](const Row& f) { return f.stz.tan_theta_star; },
          "its error (delta method over the covariance of κ, ζ; NaN where the coefficients are degenerate and the "
          "covariance keeps no digit of it)",
          [](const Row& f) { return f.stz.tan_theta_star_error; }),
      real("tan_theta_star_jackknife_error", "1",
           "its delete-one jackknife error over the fitted points (refits; NaN for fewer than 5 points)",
           [](const Row& f) { return f.tan_theta_star_jackknife_error; }),
      real(
          "theta_star", "degrees", "repose angle θ*", [](const Row& f) { return f.stz.theta_star * kDegrees; },
          "its error (from tan_theta_star_error)", [](const Row& f) { return f.stz.theta_star_error * kDegrees; }),
      real("theta_star_jackknife_error", "degrees", "its error from tan_theta_star_jackknife_error",
           [](const Row& f) {
             const double t = f.stz.tan_theta_star;
             return f.tan_theta_star_jackknife_error / (1 + t * t) * kDegrees;
           }),
      real("chi2", "1", "χ² of the STZ fit's weighted residuals (unweighted: sum of squares)",
           [](const Row& f) { return f.stz.chi2; }),
      integer("dof", "1", "points − 3", &Row::dof),
      real("mu_s", "1", "μ_s of μ(I)", mu_of_I(&MuICoefficients::mu_s, false), "its standard error",
           mu_of_I(&MuICoefficients::mu_s, true)),
      real("mu_2", "1", "μ₂ of μ(I)", mu_of_I(&MuICoefficients::mu_2, false), "its standard error",
           mu_of_I(&MuICoefficients::mu_2, true)),
      real("I0", "1", "I₀ of μ(I)", mu_of_I(&MuICoefficients::I0, false), "its standard error",
           mu_of_I(&MuICoefficients::I0, true)),
      real("stz_rms", "1", "rms residual in s/p of the STZ law, fitted points", [](const Row& f) { return f.stz_rms; }),
      real("mu_of_I_rms", "1", "rms residual in s/p of μ(I), fitted points",
           [](const Row& f) { return f.mu_of_I_rms; }),
      real("predicted_rms", "1", "rms STZ residual of the shear rows of this friction that are not fitted (NaN: none)",
           [](const Row& f) { return f.predicted_rms; }),
      integer("predicted_count", "1", "rows in predicted_rms", &Row::predicted_count),
      real("incline_rms", "1", "rms STZ residual of the incline rows of this friction (NaN: none)",
           [](const Row& f) { return f.incline_rms; }),
      integer("incline_count", "1", "rows in incline_rms", &Row::incline_count),
      real("mu_of_I_predicted_rms", "1", "rms μ(I) residual over the rows of predicted_rms",
           [](const Row& f) { return f.mu_of_I_predicted_rms; }),
      real("mu_of_I_incline_rms", "1", "rms μ(I) residual over the incline rows",
           [](const Row& f) { return f.mu_of_I_incline_rms; })};
  return columns;
}

void write_fit_table(const std::string& path, const FitTable& table, const io::Parameters& provenance) {
  io::AnalysisWriter w(path);
  w.write_parameters(provenance);
  io::TableWriter(w, "/runs",
                  "one row per RUN.h5 in command-line order (kind shear), then the flowing rows of each --incline "
                  "table (kind incline)")
      .write(table.runs, run_columns());
  io::Parameters run_group;
  run_group.set("from_strain", table.settings.window.from_strain);
  run_group.set("detect_transient", std::int64_t(table.settings.window.detect_transient));
  run_group.set("temperature_definition",
                "the gf-shear temperature observable (eq. 4.5, about the mean flow, rotation included), as the "
                "incline-bulk table's T");
  w.write_attributes("/runs", run_group);

  io::TableWriter(w, "/fit", "one row per friction coefficient with a fit, by increasing friction")
      .write(table.fits, fit_columns());
  io::Parameters fit_group;
  fit_group.set("objective",
                table.settings.objective == StzObjective::orthogonal_distance ? "orthogonal" : "least-squares");
  fit_group.set("fit_restitution", table.settings.fit_restitution);
  fit_group.set("dense_rule", !table.settings.correlation.empty()
                                  ? "xi_ratio >= " + exact_text(table.settings.dense_ratio)
                                  : "packing_fraction >= " + exact_text(table.settings.min_packing_fraction));
  fit_group.set("xi", table.settings.signed_xi ? "signed" : "abs");
  fit_group.set("theta_star_units", "degrees");
  w.write_attributes("/fit", fit_group);
  w.close();
}

}  // namespace granflow::stz
