#include "correlation/report.hpp"

#include <cmath>
#include <functional>

#include "io/analysis_writer.hpp"
#include "io/table_writer.hpp"

namespace granflow::correlation {

namespace {

constexpr const char* kPerRun = "one row per input run, in /runs order";

// Rows of equal length, flattened row-major; row(result) is a std::vector<double> member
// of RunResult or a function returning one.
template <class Row>
std::vector<double> rows(const std::vector<RunResult>& results, Row row) {
  std::vector<double> out;
  for (const auto& r : results) {
    const std::vector<double>& values = std::invoke(row, r);
    out.insert(out.end(), values.begin(), values.end());
  }
  return out;
}

template <class F>
std::vector<double> column(std::size_t n, F value) {
  std::vector<double> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = value(i);
  return out;
}

template <class F>
std::vector<std::int32_t> int_column(std::size_t n, F value) {
  std::vector<std::int32_t> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = std::int32_t(value(i));
  return out;
}

io::Parameters rows_note() {
  io::Parameters p;
  p.set("rows", kPerRun);
  return p;
}

// What every step of write_report writes with: the writer, the report, its run count and the
// `rows` note of the per-run datasets.
struct Target {
  io::AnalysisWriter& w;
  const Report& report;
  std::size_t n;
  io::Parameters per_run;
};

// The attributes of /correlation: the grid, the window, the rules of ξ_|C| and C, the map's method.
io::Parameters correlation_attributes(const Report& report) {
  const LagGrid& grid = report.grid;
  io::Parameters attrs;
  attrs.set("mean_diameter", report.mean_diameter);
  attrs.set("bin_width", grid.bin_width);
  attrs.set("max_lag", grid.max_lag());
  attrs.set("angle_bins", grid.angle_bins);
  attrs.set("map_bin", grid.map_bin);
  attrs.set("from_strain", report.settings.from_strain);
  attrs.set("detect_transient", report.settings.detect_transient ? 1 : 0);
  attrs.set("abs_bin_width", report.settings.abs_bin_width);
  attrs.set("abs_noise", report.settings.magnitude.noise);
  attrs.set("abs_threshold", report.settings.magnitude.hard ? "hard" : "soft");
  attrs.set("abs_tail_from", report.settings.magnitude.tail_from);
  attrs.set("abs_max_tail_share", report.settings.magnitude.max_tail_share);
  attrs.set("xi_abs_definition",
            "coarse bins c = [l_c-, l_c+) of abs_bin_width (the last may be partial); I_c = int_c C dl = "
            "sum_c (w/l) / (2 pi W), J_c = int_c l C dl = sum_c w / (2 pi W) (for a sector: C(l, theta) averaged over "
            "the sector, 2 dtheta W instead of 2 pi W); a_c = max(|I_c| - abs_noise * dI_c, 0) (abs_threshold "
            "soft; hard: a_c = |I_c| if |I_c| > abs_noise * dI_c, else 0) with dI_c the block-jackknife error of I_c "
            "(0 with one block); l_c = J_c / I_c clamped to [l_c-, l_c+]; xi_abs = "
            "sum l_c a_c / sum a_c; xi_abs_tail = share of sum l_c a_c from bins centred beyond abs_tail_from * "
            "max_lag; errors: jackknife over the blocks with the noise floors abs_noise * dI_c fixed");
  attrs.set("definition",
            "C(l) = (1/W) sum_{i>j} F^i.F^j (1/2)[delta(l - r_ij) + delta(l + r_ij)], W = sum_i F^i.F^i, over "
            "grains with a contact, r_ij the Lees-Edwards minimum image, |r_ij| < max_lag; frames averaged as "
            "ratios of sums (thesis eq. 5.1, symmetrised in l)");
  // The method is recorded when --map-method was other than the default (exact pairs), so
  // that tables made without it keep their attributes.
  if (report.settings.map_method != MapMethod::pairs) {
    const bool fft = report.method == MapMethod::fft;
    attrs.set("map_method", fft ? "fft" : "pairs");
    attrs.set("map_method_reason", report.method_reason);
    if (fft) {
      attrs.set("fft_cell", report.settings.fft_cell);
      std::string shapes;
      for (const FftShape& shape : report.fft_shapes)
        shapes += (shapes.empty() ? "" : ", ") + std::to_string(shape.m1) + "x" + std::to_string(shape.m2);
      attrs.set("fft_grid", shapes);
      attrs.set("fft_definition",
                "pair sums by FFT: F^i added to the cell of an fft_grid of m1 x m2 cells in lattice coordinates "
                "(u, v), r = u (Lx, 0) + v (s, Ly), s the Lees-Edwards offset reduced into [-Lx/2, Lx/2]; "
                "sum_ij F^i.F^j per lattice lag (k1, k2) = IFFT(|FFT F_x|^2 + |FFT F_y|^2), mapped to the real lag "
                "(k1/m1)(Lx, 0) + (k2/m2)(s, Ly), minimum image; equal to the exact pair sums of the grains moved "
                "to their cell centres; fft_grid lists the runs, then the reference runs");
    }
  }
  return attrs;
}

// /runs: the input runs' identity and what was averaged.
void write_runs_table(const Target& t) {
  std::vector<RunsRow> rows;
  for (std::size_t i = 0; i < t.n; ++i) {
    const Run& run = t.report.runs[i];
    const RunResult& result = t.report.results[i];
    rows.push_back({run, std::int32_t(run.frames.size()), std::int32_t(result.blocks), run.first_strain,
                    run.last_strain, double(result.contacts)});
  }
  io::TableWriter(t.w, "/runs", "").write(rows, run_columns());
}

// /correlation's per-run datasets (correlation_columns()).
void write_correlation_table(const Target& t) {
  const Report& report = t.report;
  std::vector<CorrelationRow> rows;
  for (std::size_t i = 0; i < t.n; ++i)
    rows.push_back({report.results[i], report.xi_ratio[i], report.xi_ratio_error[i], report.xi_length_ratio[i],
                    report.xi_length_ratio_error[i], report.xi_abs_ratio[i], report.xi_abs_ratio_error[i]});
  io::TableWriter(t.w, "/correlation", kPerRun).write(rows, correlation_columns());
}

// /correlation: the isotropic C(l), ξ truncated at each bin, and the elastic lengths of eq. 5.2
// (ξ_el, ξ_length_el).
void write_isotropic(const Target& t) {
  io::AnalysisWriter& w = t.w;
  const Report& report = t.report;
  const std::size_t n = t.n;
  const LagGrid& grid = t.report.grid;
  const std::size_t nb = std::size_t(t.report.grid.radial_bins);
  const auto& res = t.report.results;
  const io::Parameters& per_run = t.per_run;
  w.write("/correlation/r", {nb}, radial_centres(grid),
          "centre of the radial lag bin [r - bin_width/2, r + bin_width/2)", "length");
  w.write("/correlation/C", {n, nb}, rows(res, &RunResult::c),
          "isotropic C(l): sum of F^i.F^j over pairs in the bin / (W * annulus area), the angle average of eq. 5.1",
          "1/length^2", per_run);
  w.write("/correlation/C_error", {n, nb}, rows(res, &RunResult::c_error), "jackknife standard error of C",
          "1/length^2", per_run);
  w.write("/correlation/xi_truncated", {n, nb}, rows(res, &RunResult::xi_truncated),
          "xi of eq. 5.2 with both integrals truncated at the bin's upper edge (convergence with max_lag)", "length",
          per_run);
  w.write("/correlation/xi_el", {}, std::vector<double>{report.xi_el},
          report.references.empty() ? "elastic (dilute) reference length xi_el, given by --xi-el (NaN: none given)"
                                    : "elastic (dilute) reference length xi_el: xi of all reference frames pooled",
          "length");
  w.write("/correlation/xi_el_error", {}, std::vector<double>{report.xi_el_error},
          "standard error of xi_el (jackknife over all reference blocks; 0 when given)", "length");
  // ξ with C read as a density per unit length (force_correlation.hpp, Density::length).
  w.write("/correlation/xi_length_truncated", {n, nb}, rows(res, &RunResult::xi_length_truncated),
          "xi_length with both integrals truncated at the bin's upper edge (convergence with max_lag)", "length",
          per_run);
  w.write("/correlation/xi_length_el", {}, std::vector<double>{report.xi_length_el},
          "elastic (dilute) reference length for xi_length: xi_length of all reference frames pooled (NaN without "
          "--reference; --xi-el gives xi_el only)",
          "length");
  w.write("/correlation/xi_length_el_error", {}, std::vector<double>{report.xi_length_el_error},
          "jackknife standard error of xi_length_el (over all reference blocks)", "length");
}

// /correlation: ξ_|C|(θ), the decay length of |C| per sector (decay_length.hpp), and ξ_|C|,el.
void write_magnitude(const Target& t) {
  io::AnalysisWriter& w = t.w;
  const Report& report = t.report;
  const std::size_t n = t.n;
  const std::size_t nk = std::size_t(t.report.grid.angle_bins);
  const auto& res = t.report.results;
  const io::Parameters& per_run = t.per_run;
  w.write("/correlation/xi_abs_theta", {n, nk},
          rows(res, [](const RunResult& r) -> const std::vector<double>& { return r.magnitude.xi_theta; }),
          "xi_abs of the radial profile of C(l, theta) averaged over the sector (angle of the lag modulo pi): a "
          "decay length per direction, not per radian",
          "length", per_run);
  w.write("/correlation/xi_abs_theta_error", {n, nk},
          rows(res, [](const RunResult& r) -> const std::vector<double>& { return r.magnitude.xi_theta_error; }),
          "jackknife standard error of xi_abs_theta", "length", per_run);
  w.write("/correlation/xi_abs_el", {}, std::vector<double>{report.xi_abs_el},
          "elastic (dilute) reference length for xi_abs: xi_abs of all reference frames pooled (NaN without "
          "--reference)",
          "length");
  w.write("/correlation/xi_abs_el_error", {}, std::vector<double>{report.xi_abs_el_error},
          "jackknife standard error of xi_abs_el (over all reference blocks)", "length");
}

// /correlation: ξ(θ) and ξ_dir(θ) per sector (their eq. 5.3 fits are columns).
void write_anisotropy(const Target& t) {
  io::AnalysisWriter& w = t.w;
  const std::size_t n = t.n;
  const LagGrid& grid = t.report.grid;
  const std::size_t nk = std::size_t(t.report.grid.angle_bins);
  const auto& res = t.report.results;
  const io::Parameters& per_run = t.per_run;
  w.write("/correlation/theta", {nk}, sector_centres(grid),
          "centre of the angular sector of the lag (angle to the x axis, modulo pi)", "radian");
  w.write("/correlation/xi_theta", {n, nk}, rows(res, &RunResult::xi_theta),
          "xi(theta) = int dl l C(l, theta) / (2 pi int dl C(l)), averaged over the sector; int_0^2pi xi(theta) "
          "dtheta = xi (eq. 5.3's normalisation)",
          "length/radian", per_run);
  w.write("/correlation/xi_theta_error", {n, nk}, rows(res, &RunResult::xi_theta_error),
          "jackknife standard error of xi_theta", "length/radian", per_run);
  // ξ_dir(θ), eq. 5.2 per direction (force_correlation.hpp).
  w.write("/correlation/xi_theta_direction", {n, nk},
          rows(res, [](const RunResult& r) -> const std::vector<double>& { return r.direction.xi_theta; }),
          "xi_dir(theta) = int dl l C(l, theta) / int dl C(l, theta), eq. 5.2 per direction, numerator and "
          "denominator each averaged over the sector: sum w / sum (w/l) over the pairs with l < max_lag whose angle "
          "modulo pi falls in the sector; a length, not per radian (xi_theta = xi_theta_direction * int dl C(l, "
          "theta) / (2 pi int dl C(l))); NaN where int dl C(l, theta) = 0 or the ratio is outside (0, max_lag] "
          "(C of both signs: the integrals of opposite signs, or int dl C(l, theta) nearly cancelled)",
          "length", per_run);
  w.write("/correlation/xi_theta_direction_error", {n, nk},
          rows(res, [](const RunResult& r) -> const std::vector<double>& { return r.direction.xi_theta_error; }),
          "jackknife standard error of xi_theta_direction (NaN where a leave-one-block-out value is NaN)", "length",
          per_run);
}

// /correlation: the map of C over lag vectors.
void write_map(const Target& t) {
  io::AnalysisWriter& w = t.w;
  const std::size_t n = t.n;
  const LagGrid& grid = t.report.grid;
  const std::size_t nm = std::size_t(t.report.grid.map_side());
  const auto& res = t.report.results;
  const io::Parameters& per_run = t.per_run;
  std::vector<double> maps;
  for (const auto& r : res) maps.insert(maps.end(), r.map.begin(), r.map.end());
  w.write("/correlation/map", {n, nm, nm}, maps,
          "C(l) on square lag bins [run][y][x]: half of F^i.F^j at +r_ij and -r_ij per pair / (W * bin area); NaN "
          "in bins not wholly within |l| < max_lag",
          "1/length^2", per_run);
  w.write("/correlation/map_x", {nm}, map_centres(grid), "x component of the lag at the map bin centres", "length");
  w.write("/correlation/map_y", {nm}, map_centres(grid), "y component of the lag at the map bin centres", "length");
}

// /forces: P(f), P(f_bc), the mean forces and the peak decision.
void write_forces(const Target& t) {
  io::AnalysisWriter& w = t.w;
  const std::size_t n = t.n;
  const auto& res = t.report.results;
  const io::Parameters& per_run = t.per_run;
  const Settings& s = t.report.settings;
  io::Parameters force_attrs;
  force_attrs.set("bin_width", s.force_bin_width);
  force_attrs.set("max_f", s.force_max);
  force_attrs.set("kde_bandwidth", s.kde_bandwidth);
  force_attrs.set("bootstrap", s.bootstrap);
  force_attrs.set("seed", std::int64_t(s.seed));
  force_attrs.set("peak_rule",
                  "Gaussian kernel density estimate P^ of f reflected at f = 0, bandwidth h = kde_bandwidth: "
                  "peak = 1 if P^(3h) > P^(0) (P rises from 0: a peak at f > 0), 0 otherwise (largest at f = 0); "
                  "confidence = fraction of block-bootstrap replicates reaching the same decision");
  w.write_attributes("/forces", force_attrs);
  std::vector<double> centres = res.front().normal.centre;
  auto distribution = [&](const std::string& name, Distribution RunResult::*member, const char* meaning) {
    std::vector<double> p, e;
    for (const auto& r : res) {
      p.insert(p.end(), (r.*member).density.begin(), (r.*member).density.end());
      e.insert(e.end(), (r.*member).error.begin(), (r.*member).error.end());
    }
    w.write("/forces/" + name, {n, centres.size()}, p, meaning, "1", per_run);
    w.write("/forces/" + name + "_error", {n, centres.size()}, e,
            "jackknife standard error (each block left out "
            "with its own mean force)",
            "1", per_run);
  };
  w.write("/forces/f", {centres.size()}, centres, "bin centre of f = F_n/<F_n>", "1");
  w.write("/forces/f_bc", {centres.size()}, centres, "bin centre of f_bc = F_bc/<F_bc>", "1");
  distribution("P", &RunResult::normal,
               "P(f) of normal contact forces, counts / (all contacts * bin width) (Figs 5.7, 5.8)");
  distribution("P_bc", &RunResult::binary,
               "P(f_bc) of the binary-collision forces F_bc of eq. 5.4 of the same contacts (Fig. 5.7)");
  io::TableWriter(w, "/forces", kPerRun).write(res, force_columns());
}

// /reference: the reference runs (with --reference).
void write_reference(const Target& t) {
  const Report& report = t.report;
  std::vector<ReferenceRow> rows;
  for (std::size_t i = 0; i < report.references.size(); ++i)
    rows.push_back({report.references[i], report.reference_xi[i], report.reference_xi_error[i],
                    report.reference_xi_length[i], report.reference_xi_length_error[i], report.reference_xi_abs[i],
                    report.reference_xi_abs_error[i]});
  io::TableWriter(t.w, "/reference", "").write(rows, reference_columns());
}

// /sweep: ν_bc per (e, μ) series and the regimes (when ξ_el is known).
void write_sweep(const Target& t) {
  io::AnalysisWriter& w = t.w;
  const Report& report = t.report;
  const std::size_t n = t.n;
  const auto& res = t.report.results;
  const io::Parameters& per_run = t.per_run;
  const Settings& s = t.report.settings;
  const auto& c = report.crossings;
  const std::size_t g = c.size();
  io::Parameters sweep_attrs;
  sweep_attrs.set("threshold", s.threshold);
  sweep_attrs.set("rule",
                  "nu_bc: first upward crossing of xi/xi_el = threshold along nu within one (e, mu) "
                  "series, linear interpolation between the bracketing runs (thesis Figs 5.9, 5.10)");
  w.write_attributes("/sweep", sweep_attrs);
  auto series = [&](const char* name, auto value, const char* meaning, const char* units) {
    w.write(std::string("/sweep/") + name, {g}, column(g, value), meaning, units);
  };
  series(
      "restitution", [&](std::size_t k) { return c[k].restitution; }, "e of the series", "1");
  series(
      "friction", [&](std::size_t k) { return c[k].friction; }, "mu of the series", "1");
  series(
      "nu_bc", [&](std::size_t k) { return c[k].nu_bc; },
      "packing fraction where xi/xi_el crosses the threshold (NaN unless status = 0)", "1");
  series(
      "nu_bc_error", [&](std::size_t k) { return c[k].nu_bc_error; },
      "standard error of nu_bc from the errors of xi and xi_el (interpolation error not included)", "1");
  series(
      "nu_below", [&](std::size_t k) { return c[k].nu_below; }, "nu of the run below the crossing", "1");
  series(
      "nu_above", [&](std::size_t k) { return c[k].nu_above; }, "nu of the run above the crossing", "1");
  w.write("/sweep/runs", {g}, int_column(g, [&](std::size_t k) { return c[k].runs; }),
          "runs in the series (runs at equal nu are merged)", "1");
  w.write("/sweep/sign_changes", {g}, int_column(g, [&](std::size_t k) { return c[k].sign_changes; }),
          "sign changes of xi/xi_el - threshold along nu (more than 1: noisy or non-monotonic)", "1");
  w.write("/sweep/status", {g}, int_column(g, [&](std::size_t k) { return int(c[k].status); }),
          "0 crossing interpolated; 1 every run above the threshold (nu_bc below the lowest nu); 2 every run "
          "below (nu_bc above the highest nu); 3 fewer than two distinct nu; 4 only downward crossings",
          "1");
  if (!report.crossings_abs.empty()) {
    const auto& a = report.crossings_abs;
    series(
        "nu_bc_abs", [&](std::size_t k) { return a[k].nu_bc; },
        "nu where xi_abs/xi_abs_el crosses the threshold, measurable runs only (NaN unless status_abs = 0)", "1");
    series(
        "nu_bc_abs_error", [&](std::size_t k) { return a[k].nu_bc_error; },
        "standard error of nu_bc_abs from the jackknife errors of xi_abs and xi_abs_el", "1");
    series(
        "nu_below_abs", [&](std::size_t k) { return a[k].nu_below; }, "nu of the run below the crossing", "1");
    series(
        "nu_above_abs", [&](std::size_t k) { return a[k].nu_above; }, "nu of the run above the crossing", "1");
    w.write("/sweep/runs_abs", {g}, int_column(g, [&](std::size_t k) { return a[k].runs; }),
            "measurable runs in the series", "1");
    w.write("/sweep/sign_changes_abs", {g}, int_column(g, [&](std::size_t k) { return a[k].sign_changes; }),
            "sign changes of xi_abs/xi_abs_el - threshold along nu", "1");
    w.write("/sweep/status_abs", {g}, int_column(g, [&](std::size_t k) { return int(a[k].status); }),
            "as status, for xi_abs over the measurable runs", "1");
    w.write("/sweep/regime_abs", {n},
            int_column(n,
                       [&](std::size_t i) {
                         const double q = report.xi_abs_ratio[i];
                         if (!res[i].magnitude.measurable) return -2;
                         return std::isfinite(q) ? (q >= s.threshold ? 1 : 0) : -1;
                       }),
            "as regime, by xi_abs/xi_abs_el; -2 correlations reach the box (not measurable)", "1", per_run);
  }
  w.write("/sweep/regime", {n},
          int_column(n,
                     [&](std::size_t i) {
                       const double q = report.xi_ratio[i];
                       return std::isfinite(q) ? (q >= s.threshold ? 1 : 0) : -1;
                     }),
          "phase diagram (Fig. 5.10): 1 dense inertial (xi/xi_el >= threshold), 0 dilute (binary collisions), "
          "-1 unknown",
          "1", per_run);
}

// /clusters: the contact clusters of a window (with --clusters-window).
void write_clusters(const Target& t) {
  io::AnalysisWriter& w = t.w;
  const Report& report = t.report;
  const std::size_t n = t.n;
  const io::Parameters& per_run = t.per_run;
  const Settings& s = t.report.settings;
  std::vector<std::int32_t> label, offset{0};
  std::vector<double> position, box;
  for (const Clusters& c : report.clusters) {
    label.insert(label.end(), c.label.begin(), c.label.end());
    for (const Vec2& r : c.position) position.insert(position.end(), {r.x(), r.y()});
    offset.push_back(std::int32_t(label.size()));
    box.insert(box.end(), {c.box.lx, c.box.ly, c.box.offset});
  }
  const auto& c = report.clusters;
  io::Parameters cluster_attrs;
  cluster_attrs.set("window", s.clusters_window);
  cluster_attrs.set("rule",
                    "grains in contact in any stored frame of the window, grouped into connected "
                    "components of the union of the frames' contact graphs (thesis Fig. 5.1)");
  w.write_attributes("/clusters", cluster_attrs);
  w.write("/clusters/label", {label.size()}, label,
          "cluster of each grain: 0 no contact in the window, 1.. clusters by decreasing size; run k's grains "
          "are rows grain_offset[k] .. grain_offset[k+1]-1",
          "1");
  w.write("/clusters/position", {label.size(), 2}, position, "grain centres at the window's last frame", "length");
  w.write("/clusters/grain_offset", {offset.size()}, offset, "first row of each run in label and position", "1");
  w.write("/clusters/box", {n, 3}, box, "Lx, Ly and the Lees-Edwards image offset at the window's last frame", "length",
          per_run);
  w.write("/clusters/first_frame", {n}, int_column(n, [&](std::size_t i) { return c[i].first_frame; }),
          "first stored frame of the window", "1", per_run);
  w.write("/clusters/last_frame", {n}, int_column(n, [&](std::size_t i) { return c[i].last_frame; }),
          "last stored frame of the window", "1", per_run);
  std::vector<std::int64_t> first_step, last_step;
  for (const Clusters& k : c) {
    first_step.push_back(k.first_step);
    last_step.push_back(k.last_step);
  }
  w.write("/clusters/first_step", {n}, first_step, "time step of the window's first frame", "1", per_run);
  w.write("/clusters/last_step", {n}, last_step, "time step of the window's last frame", "1", per_run);
  w.write("/clusters/count", {n}, int_column(n, [&](std::size_t i) { return c[i].count; }), "clusters", "1", per_run);
}

}  // namespace

namespace {

const char* const kInput = "path of the trajectory as given on the command line";

template <class Row>
std::vector<io::RowColumn<Row>> identity_columns() {
  return {io::text<Row>("input", kInput, [](const Row& r) { return r.run.path; }),
          io::real<Row>(io::identity_column("packing_fraction"), [](const Row& r) { return r.run.packing_fraction; }),
          io::real<Row>(io::identity_column("restitution"), [](const Row& r) { return r.run.restitution; }),
          io::real<Row>(io::identity_column("friction"), [](const Row& r) { return r.run.friction; })};
}

// /correlation's columns of eq. 5.2's lengths, ξ and ξ_length, and their ratios to ξ_el.
std::vector<io::RowColumn<CorrelationRow>> isotropic_columns() {
  using Row = CorrelationRow;
  return {
      io::real<Row>(
          {"xi", "length",
           "correlation length xi, eq. 5.2 taken literally on the signed C: sum w / sum (w/l) over pairs "
           "with l < max_lag (exact integrals of the sampled C); ill-conditioned in dense flows, where int C "
           "dl crosses zero (see xi_abs)",
           "xi_error", "jackknife standard error of xi"},
          [](const Row& r) { return r.result.xi; }, [](const Row& r) { return r.result.xi_error; }),
      io::real("xi_ratio", "1", "xi / xi_el", &Row::xi_ratio,
               "standard error of xi / xi_el (errors of xi and xi_el combined in quadrature)", &Row::xi_ratio_error),
      // ξ with C read as a density per unit length (force_correlation.hpp, Density::length).
      io::real<Row>(
          {"xi_length", "length",
           "correlation length of eq. 5.2 with C read as a density per unit length, C_L(l) = 2 pi l C(l) "
           "(the radial pair sum per unit l): int l C_L dl / int C_L dl = sum (w l) / sum w over pairs with "
           "l < max_lag (exact integrals of the sampled C); xi is the same with C per unit area",
           "xi_length_error", "jackknife standard error of xi_length"},
          [](const Row& r) { return r.result.xi_length; }, [](const Row& r) { return r.result.xi_length_error; }),
      io::real("xi_length_ratio", "1", "xi_length / xi_length_el", &Row::xi_length_ratio,
               "standard error of xi_length / xi_length_el (errors combined in quadrature)",
               &Row::xi_length_ratio_error)};
}

// /correlation's columns of ξ_|C|, the decay length of |C| (decay_length.hpp): its tail share,
// flag, the eq. 5.3 fit to ξ_|C|(θ) and the ratio to ξ_|C|,el.
std::vector<io::RowColumn<CorrelationRow>> magnitude_columns() {
  using Row = CorrelationRow;
  return {
      io::real<Row>(
          {"xi_abs", "length",
           "decay length of |C(l)| (the xi of Figs 5.2-5.10): sum_c l_c a_c / sum_c a_c over coarse bins c "
           "of abs_bin_width, a_c = max(|I_c| - abs_noise * dI_c, 0), I_c = int_c C dl exactly from the pair "
           "sums, dI_c its jackknife error, l_c = int_c l C dl / I_c clamped to the bin (see the group's "
           "xi_abs_definition)",
           "xi_abs_error", "block-jackknife standard error of xi_abs (noise floors fixed at their full-sample values)"},
          [](const Row& r) { return r.result.magnitude.xi; }, [](const Row& r) { return r.result.magnitude.xi_error; }),
      io::real<Row>(
          {"xi_abs_tail", "1",
           "share of sum_c l_c a_c (int l|C|) from coarse bins centred beyond abs_tail_from * max_lag",
           "xi_abs_tail_error", "jackknife standard error of xi_abs_tail"},
          [](const Row& r) { return r.result.magnitude.tail_share; },
          [](const Row& r) { return r.result.magnitude.tail_share_error; }),
      io::integer<Row>({"measurable", "1",
                        "1: xi_abs finite and xi_abs_tail <= abs_max_tail_share; 0: correlations reach the box "
                        "(xi_abs measures the cell, the thesis' 'too large to be measured') or no signal; left out of "
                        "nu_bc_abs"},
                       [](const Row& r) { return std::int64_t(r.result.magnitude.measurable); }),
      io::real<Row>(
          {"a0_abs", "1",
           "a0 of eq. 5.3's shape fitted to xi_abs_theta = m (1 - a0 sin 2(theta - theta0)), m its mean "
           "over the sectors",
           "a0_abs_error", "standard error of a0_abs"},
          [](const Row& r) { return r.result.fit_abs.a0; }, [](const Row& r) { return r.result.fit_abs.a0_error; }),
      io::real<Row>(
          {"theta0_abs", "radian", "theta0 of that fit, in [-pi/2, pi/2)", "theta0_abs_error",
           "standard error of theta0_abs"},
          [](const Row& r) { return r.result.fit_abs.theta0; },
          [](const Row& r) { return r.result.fit_abs.theta0_error; }),
      io::real<Row>({"fit_abs_chi2_dof", "1", "chi^2 per degree of freedom of that fit"},
                    [](const Row& r) { return r.result.fit_abs.chi2_per_dof; }),
      io::real("xi_abs_ratio", "1", "xi_abs / xi_abs_el", &Row::xi_abs_ratio,
               "standard error of xi_abs / xi_abs_el (errors combined in quadrature)", &Row::xi_abs_ratio_error)};
}

// /correlation's columns of the eq. 5.3 fit to ξ(θ).
std::vector<io::RowColumn<CorrelationRow>> anisotropy_columns() {
  using Row = CorrelationRow;
  return {
      io::real<Row>(
          {"a0", "1", "a0 of eq. 5.3, xi(theta) = xi/(2 pi) (1 - a0 sin 2(theta - theta0)), fitted", "a0_error",
           "standard error of a0 (covariance scaled by max(1, sqrt(chi2/dof)))"},
          [](const Row& r) { return r.result.fit.a0; }, [](const Row& r) { return r.result.fit.a0_error; }),
      io::real<Row>(
          {"theta0", "radian", "theta0 of eq. 5.3, in [-pi/2, pi/2)", "theta0_error", "standard error of theta0"},
          [](const Row& r) { return r.result.fit.theta0; }, [](const Row& r) { return r.result.fit.theta0_error; }),
      io::real<Row>({"fit_chi2_dof", "1", "chi^2 per degree of freedom of the eq. 5.3 fit"},
                    [](const Row& r) { return r.result.fit.chi2_per_dof; }),
      io::integer<Row>({"fit_weighted", "1",
                        "1: fit weighted by the jackknife errors of xi_theta; 0: unweighted, errors from the scatter"},
                       [](const Row& r) { return std::int64_t(r.result.fit.weighted); })};
}

// /correlation's columns of eq. 5.3's shape fitted to ξ_dir(θ), eq. 5.2 per direction.
std::vector<io::RowColumn<CorrelationRow>> direction_columns() {
  using Row = CorrelationRow;
  return {io::real<Row>(
              {"a0_direction", "1",
               "a0 of eq. 5.3's shape fitted to the finite xi_theta_direction = m (1 - a0 sin 2(theta - "
               "theta0)), m their mean (eq. 5.3 with xi = 2 pi m); NaN with fewer than 3 finite sectors",
               "a0_direction_error",
               "standard error of a0_direction (covariance scaled by max(1, sqrt(chi2/dof)), or by "
               "sqrt(chi2/dof) when unweighted)"},
              [](const Row& r) { return r.result.direction.fit.a0; },
              [](const Row& r) { return r.result.direction.fit.a0_error; }),
          io::real<Row>(
              {"theta0_direction", "radian", "theta0 of that fit, in [-pi/2, pi/2)", "theta0_direction_error",
               "standard error of theta0_direction"},
              [](const Row& r) { return r.result.direction.fit.theta0; },
              [](const Row& r) { return r.result.direction.fit.theta0_error; }),
          io::real<Row>({"fit_direction_chi2_dof", "1", "chi^2 per degree of freedom of that fit"},
                        [](const Row& r) { return r.result.direction.fit.chi2_per_dof; }),
          io::integer<Row>({"fit_direction_weighted", "1",
                            "1: that fit weighted by the jackknife errors of the finite xi_theta_direction; 0: "
                            "unweighted (one of those errors not finite and positive, or no fit), errors from the "
                            "scatter"},
                           [](const Row& r) { return std::int64_t(r.result.direction.fit.weighted); })};
}

}  // namespace

const std::vector<io::RowColumn<RunsRow>>& run_columns() {
  using Row = RunsRow;
  static const std::vector<io::RowColumn<Row>> columns = [] {
    std::vector<io::RowColumn<Row>> c = identity_columns<Row>();
    const std::vector<io::RowColumn<Row>> more = {
        io::real<Row>({"tangential_restitution", "1", "tangential restitution e_t (the run's /parameters)"},
                      [](const Row& r) { return r.run.tangential_restitution; }),
        io::real<Row>(io::identity_column("rate"), [](const Row& r) { return r.run.rate; }),
        io::integer<Row>(io::identity_column("grains"), [](const Row& r) { return std::int32_t(r.run.grains); }),
        io::integer("frames", "1",
                    "stored frames averaged (strain >= from_strain, or past the run's transient with detect_transient)",
                    &Row::frames),
        io::integer("blocks", "1", "blocks of consecutive frames for the jackknife and bootstrap errors", &Row::blocks),
        io::real("first_strain", "1", "shear strain of the first frame averaged", &Row::first_strain),
        io::real("last_strain", "1", "shear strain of the last frame averaged", &Row::last_strain),
        io::real("contacts", "1", "contacts (F_n > 0) in the frames averaged", &Row::contacts)};
    c.insert(c.end(), more.begin(), more.end());
    return c;
  }();
  return columns;
}

const std::vector<io::RowColumn<ReferenceRow>>& reference_columns() {
  using Row = ReferenceRow;
  static const std::vector<io::RowColumn<Row>> columns = [] {
    std::vector<io::RowColumn<Row>> c = identity_columns<Row>();
    const std::vector<io::RowColumn<Row>> more = {
        io::real("xi", "length", "xi (eq. 5.2) of the reference run", &Row::xi, "jackknife standard error of xi",
                 &Row::xi_error),
        io::real("xi_length", "length", "xi_length (eq. 5.2 with C per unit length) of the reference run",
                 &Row::xi_length, "jackknife standard error of xi_length", &Row::xi_length_error),
        io::real("xi_abs", "length", "xi_abs (decay length of |C|) of the reference run", &Row::xi_abs,
                 "jackknife standard error of xi_abs", &Row::xi_abs_error)};
    c.insert(c.end(), more.begin(), more.end());
    return c;
  }();
  return columns;
}

const std::vector<io::RowColumn<CorrelationRow>>& correlation_columns() {
  static const std::vector<io::RowColumn<CorrelationRow>> columns = [] {
    std::vector<io::RowColumn<CorrelationRow>> c = isotropic_columns();
    for (const auto& part : {magnitude_columns(), anisotropy_columns(), direction_columns()})
      c.insert(c.end(), part.begin(), part.end());
    return c;
  }();
  return columns;
}

const std::vector<io::RowColumn<RunResult>>& force_columns() {
  using Row = RunResult;
  static const std::vector<io::RowColumn<Row>> columns = {
      io::real<Row>(
          {"mean_force", "force", "<F_n> over all contacts", "mean_force_error", "jackknife standard error of <F_n>"},
          [](const Row& r) { return r.normal.mean; }, [](const Row& r) { return r.normal.mean_error; }),
      io::real<Row>(
          {"mean_binary_force", "force", "<F_bc> over all contacts", "mean_binary_force_error",
           "jackknife standard error of <F_bc>"},
          [](const Row& r) { return r.binary.mean; }, [](const Row& r) { return r.binary.mean_error; }),
      io::integer<Row>({"peak", "1",
                        "1: P(f) rises from f = 0 (a peak at f > 0); 0: it is largest at f = 0 (see the group's "
                        "peak_rule); -1: no contact force in the window"},
                       [](const Row& r) { return std::int64_t(r.peak.peak); }),
      io::real<Row>(
          {"peak_confidence", "1", "fraction of bootstrap replicates with the same peak decision (NaN with one block)"},
          [](const Row& r) { return r.peak.confidence; }),
      io::real<Row>(
          {"mode", "1", "f at the maximum of the kernel density estimate", "mode_error",
           "standard deviation of the mode over the bootstrap replicates of the peak decision (NaN with "
           "one block)"},
          [](const Row& r) { return r.peak.mode; }, [](const Row& r) { return r.peak.mode_error; }),
      io::real<Row>({"p0_over_pmax", "1", "kernel density estimate at f = 0 over its maximum (1: maximum at 0)"},
                    [](const Row& r) { return r.peak.ratio; })};
  return columns;
}

void write_report(const std::string& path, const Report& report, const io::Parameters& provenance) {
  io::AnalysisWriter w(path);
  w.write_parameters(provenance);
  const Target t{w, report, report.runs.size(), rows_note()};
  write_runs_table(t);
  w.write_attributes("/correlation", correlation_attributes(report));
  write_correlation_table(t);
  write_isotropic(t);
  write_magnitude(t);
  write_anisotropy(t);
  write_map(t);
  write_forces(t);
  if (!report.references.empty()) write_reference(t);
  if (!report.crossings.empty()) write_sweep(t);
  if (!report.clusters.empty()) write_clusters(t);
  w.close();
}

}  // namespace granflow::correlation
