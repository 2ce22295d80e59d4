#include "network/table.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "core/error.hpp"
#include "core/progress.hpp"
#include "core/signals.hpp"
#include "correlation/table_lookup.hpp"
#include "io/analysis_writer.hpp"
#include "io/hdf5_handle.hpp"
#include "io/run_identity.hpp"
#include "io/table_writer.hpp"
#include "network/geometric_contacts.hpp"
#include "network/network.hpp"
#include "statistics/delta.hpp"

namespace granflow::network {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr const char* kPerRun = "one row per RUN.h5, in command-line order";

using statistics::delta_error;
using statistics::mean;
using statistics::mean_error;

// Every field of FrameSums: the per-frame series the window means are taken of.
constexpr std::array kFields = {&FrameSums::grains,        &FrameSums::contacts,         &FrameSums::long_lived,
                                &FrameSums::active_grains, &FrameSums::deflection_pairs, &FrameSums::sum_cos,
                                &FrameSums::sum_cos_cos2,  &FrameSums::sum_sin2,         &FrameSums::sum_cos2,
                                &FrameSums::sum_f,         &FrameSums::sum_f_sin2,       &FrameSums::sum_f_cos2,
                                &FrameSums::sum_b,         &FrameSums::sum_b_sin2,       &FrameSums::sum_b_cos2,
                                &FrameSums::sum_bf,        &FrameSums::sum_bf_sin2,      &FrameSums::sum_bf_cos2};

// The frame quantities with an error, in the order evaluate() returns them: /runs names,
// then /prediction names.
const std::vector<std::string> kRunQuantities = {"coordination",
                                                 "coordination_active",
                                                 "mean_cos_deflection",
                                                 "mean_cos_cos2_deflection",
                                                 "Phi",
                                                 "Psi",
                                                 "phi_11",
                                                 "phi_22",
                                                 "phi_12",
                                                 "chi_11",
                                                 "chi_22",
                                                 "chi_12",
                                                 "a_c",
                                                 "a_c_prime",
                                                 "a_f",
                                                 "a_f_prime",
                                                 "shear_ratio_collisional_frames"};
const std::vector<std::string> kPredictionQuantities = {
    "rhs_pressure",        "rhs_shear",        "rhs_xx",        "rhs_pressure_floor", "rhs_shear_floor", "rhs_xx_floor",
    "rhs_pressure_active", "rhs_shear_active", "rhs_xx_active", "rhs_pressure_unit",  "rhs_shear_unit",  "rhs_xx_unit"};

std::vector<double> evaluate(const FrameSums& means, double xi) {
  const Ingredients g = ingredients(means);
  std::vector<double> out = {g.z,
                             g.z_active,
                             g.mean_cos,
                             g.mean_cos_cos2,
                             g.Phi,
                             g.Psi,
                             g.phi11,
                             g.phi22,
                             g.phi12,
                             g.chi11,
                             g.chi22,
                             g.chi12,
                             g.a_c,
                             g.a_c_prime,
                             g.a_f,
                             g.a_f_prime,
                             g.shear_ratio_collisional_frames};
  auto add = [&](const Prediction& p) {
    out.push_back(p.pressure);
    out.push_back(p.shear);
    out.push_back(p.xx);
  };
  add(predict(g.z, g.Phi, g.Psi, g.a_c, g.a_c_prime, g.a_f, g.a_f_prime, xi, SumLimit::continuation));
  add(predict(g.z, g.Phi, g.Psi, g.a_c, g.a_c_prime, g.a_f, g.a_f_prime, xi, SumLimit::floor));
  add(predict(g.z_active, g.Phi, g.Psi, g.a_c, g.a_c_prime, g.a_f, g.a_f_prime, xi, SumLimit::continuation));
  add(predict(g.z, g.mean_cos, g.mean_cos_cos2, g.a_c, g.a_c_prime, g.a_f, g.a_f_prime, xi, SumLimit::continuation));
  return out;
}

// Per-bin ratio a_k/b_k (NaN in an empty bin).
std::vector<double> per_bin(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<double> out(a.size());
  for (std::size_t k = 0; k < a.size(); ++k) out[k] = b[k] > 0 ? a[k] / b[k] : kNaN;
  return out;
}

// The 4θ components of a histogram set: sin and cos of C(θ), then of F_bc(θ).
std::array<double, 4> fourth_order(const Histograms& h) {
  const Harmonic c = harmonic(h.angle_count, 4);
  const Harmonic f = harmonic(per_bin(h.angle_force, h.angle_count), 4);
  return {c.sin_coefficient, c.cos_coefficient, f.sin_coefficient, f.cos_coefficient};
}

Histograms minus(const Histograms& all, const Histograms& part) {
  Histograms h = all;
  auto sub = [](std::vector<double>& a, const std::vector<double>& b) {
    for (std::size_t k = 0; k < a.size(); ++k) a[k] -= b[k];
  };
  sub(h.angle_count, part.angle_count);
  sub(h.angle_force, part.angle_force);
  sub(h.angle_branch, part.angle_branch);
  sub(h.deflection_count, part.deflection_count);
  return h;
}

// The stresses of the window's rows: p = (Σxx + Σyy)/2, s = −Σxy, Σxx.
struct Stresses {
  std::vector<double> p, s, xx;
};

Stresses stresses(const shear_run::Opened& o, const std::string& path, const char* name, std::size_t first) {
  const std::vector<Mat2> t = shear_run::tensor(o, path, name);
  Stresses out;
  for (std::size_t r = first; r < t.size(); ++r) {
    out.p.push_back(0.5 * (t[r](0, 0) + t[r](1, 1)));
    out.s.push_back(-t[r](0, 1));
    out.xx.push_back(t[r](0, 0));
  }
  return out;
}

// The per-frame sums of the window's frames (and their means), each frame's contacts also
// added to its block's histograms; frame_done after each frame.
struct FrameSeries {
  std::vector<std::vector<double>> series;  // [field of kFields][frame]
  FrameSums means;
};

FrameSeries frame_sums(const shear_run::Opened& o, const std::string& path, const std::vector<std::size_t>& frames,
                       const TableSettings& settings, std::size_t n, double dt, std::vector<Histograms>& block,
                       const std::function<void()>& frame_done) {
  auto bad = [&](const std::string& what) { return UsageError("'" + path + "': " + what); };
  const std::size_t blocks = block.size();
  std::vector<FrameSums> sums;
  FrameAnalyser analyser;
  const bool geometric = !std::isnan(settings.contact_gap);
  std::vector<double> radius;
  double gap = 0;
  if (geometric) {
    radius = o.reader.grains().radius;
    gap = settings.contact_gap * 2 * mean(radius);
  }
  for (std::size_t k = 0; k < frames.size(); ++k) {
    check_interrupt();
    const io::Frame frame = o.reader.frame(frames[k]);
    if (!frame.has_contacts) throw bad("frame " + std::to_string(frames[k]) + " has no contacts stored");
    try {
      const ContactRecords contacts = geometric ? geometric_contacts(frame, radius, gap, dt, o.rate) : ContactRecords{};
      sums.push_back(analyser.analyse(geometric ? contacts : frame.contacts, n, &block[k * blocks / frames.size()]));
    } catch (const std::invalid_argument& e) {
      throw bad("/contacts of frame " + std::to_string(frames[k]) + ": " + e.what());
    }
    if (frame_done) frame_done();
  }
  std::vector<std::vector<double>> series(kFields.size(), std::vector<double>(sums.size()));
  FrameSums means;
  for (std::size_t f = 0; f < kFields.size(); ++f) {
    for (std::size_t k = 0; k < sums.size(); ++k) series[f][k] = sums[k].*kFields[f];
    means.*kFields[f] = mean(series[f]);
  }
  if (!(means.contacts > 0)) throw bad("no contact in the window's " + std::to_string(frames.size()) + " frame(s)");
  return {std::move(series), means};
}

// The window values of the frame quantities and the predictions, with their delta-method
// errors (derivatives by central differences), and the network model's factors.
void window_values(RunRow& row, const FrameSeries& frames, const XiValue& xi) {
  const auto& series = frames.series;
  const FrameSums& means = frames.means;
  const std::size_t count = series.front().size();
  auto& r = row.runs;
  const double xi_ratio = xi.ratio;
  const std::vector<double> value = evaluate(means, xi_ratio);
  std::vector<std::vector<double>> linear(value.size(), std::vector<double>(count, 0.0));
  for (std::size_t f = 0; f < kFields.size(); ++f) {
    double scale = std::fabs(means.*kFields[f]);
    if (scale == 0)
      for (double x : series[f]) scale = std::max(scale, std::fabs(x));
    if (scale == 0) continue;  // a series of zeros moves nothing
    const double h = 1e-6 * scale;
    FrameSums up = means, down = means;
    up.*kFields[f] += h;
    down.*kFields[f] -= h;
    const std::vector<double> a = evaluate(up, xi_ratio), b = evaluate(down, xi_ratio);
    for (std::size_t q = 0; q < value.size(); ++q) {
      const double g = (a[q] - b[q]) / (2 * h);
      for (std::size_t k = 0; k < count; ++k) linear[q][k] += g * series[f][k];
    }
  }
  std::vector<double> error(value.size());
  for (std::size_t q = 0; q < value.size(); ++q) error[q] = mean_error(linear[q]);
  // The predictions' dependence on ξ/ξ_el, whose error is independent of the frames'.
  if (std::isfinite(xi_ratio) && xi.error > 0) {
    const double h = 1e-6 * std::max(std::fabs(xi_ratio), 1.0);
    const std::vector<double> a = evaluate(means, xi_ratio + h), b = evaluate(means, xi_ratio - h);
    for (std::size_t q = kRunQuantities.size(); q < value.size(); ++q)
      error[q] = std::hypot(error[q], (a[q] - b[q]) / (2 * h) * xi.error);
  }
  for (std::size_t q = 0; q < kRunQuantities.size(); ++q) {
    r[kRunQuantities[q]] = value[q];
    r[kRunQuantities[q] + "_error"] = error[q];
  }
  auto& pr = row.prediction;
  for (std::size_t q = 0; q < kPredictionQuantities.size(); ++q) {
    pr[kPredictionQuantities[q]] = value[kRunQuantities.size() + q];
    pr[kPredictionQuantities[q] + "_error"] = error[kRunQuantities.size() + q];
  }
  const Ingredients g = ingredients(means);
  r["fabric_norm"] = g.fabric_norm;
  r["a_f_first_order"] = g.a_f_first_order;
  r["a_f_prime_first_order"] = g.a_f_prime_first_order;
  r["mean_binary_force"] = g.mean_binary_force;
  pr["xi_ratio"] = xi.ratio;
  pr["xi_ratio_error"] = xi.error;
  row.xi_measurable = xi.measurable ? 1 : 0;
  const double network_factor = std::min(g.Phi * (g.z - 1), 1.0), path_factor = g.Psi * (g.z - 1);
  const double sum_limit = std::isfinite(xi_ratio) ? std::max(xi_ratio - 1, 0.0) : kNaN;
  pr["network_factor"] = network_factor;
  pr["path_factor"] = path_factor;
  pr["sum_limit"] = sum_limit;
  row.continuation_real = std::isfinite(xi_ratio) ? predict(g.z, g.Phi, g.Psi, g.a_c, g.a_c_prime, g.a_f, g.a_f_prime,
                                                            xi_ratio, SumLimit::continuation)
                                                        .continuation_real
                                                  : 0;
}

// The histograms pooled over the window, the 4θ components with block-jackknife errors, and
// σ(θ)'s anisotropy.
void histogram_values(RunRow& row, const std::vector<Histograms>& block, const TableSettings& settings) {
  const std::size_t blocks = block.size();
  auto& r = row.runs;
  Histograms pooled(settings.angle_bins, settings.deflection_bins);
  for (const Histograms& b : block) pooled.add(b);
  const std::array<double, 4> fourth = fourth_order(pooled);
  std::array<double, 4> fourth_error;
  fourth_error.fill(kNaN);
  if (blocks >= 2) {
    std::vector<std::array<double, 4>> leave_out;
    for (const Histograms& b : block) leave_out.push_back(fourth_order(minus(pooled, b)));
    for (std::size_t c = 0; c < 4; ++c) {
      double m = 0, ss = 0;
      for (const auto& x : leave_out) m += x[c];
      m /= double(blocks);
      for (const auto& x : leave_out) ss += (x[c] - m) * (x[c] - m);
      fourth_error[c] = std::sqrt(double(blocks - 1) / double(blocks) * ss);
    }
  }
  const char* fourth_names[] = {"a4_c", "a4_c_prime", "a4_f", "a4_f_prime"};
  for (std::size_t c = 0; c < 4; ++c) {
    r[fourth_names[c]] = fourth[c];
    r[std::string(fourth_names[c]) + "_error"] = fourth_error[c];
  }
  const std::size_t K = settings.angle_bins, D = settings.deflection_bins;
  const double dtheta = std::numbers::pi / double(K), dx = std::numbers::pi / double(D);
  double contacts = 0, branch = 0, pairs = 0;
  for (std::size_t k = 0; k < K; ++k) {
    contacts += pooled.angle_count[k];
    branch += pooled.angle_branch[k];
  }
  for (double c : pooled.deflection_count) pairs += c;
  const std::vector<double> force = per_bin(pooled.angle_force, pooled.angle_count);
  const std::vector<double> length = per_bin(pooled.angle_branch, pooled.angle_count);
  // The angle average over the bins that hold a contact: an empty bin (NaN) stays NaN alone.
  double force_average = 0, filled = 0;
  for (double f : force)
    if (std::isfinite(f)) force_average += f, filled += 1;
  force_average /= filled;
  const double mean_branch = branch / contacts;
  double deviation = 0;
  for (std::size_t k = 0; k < K; ++k) {
    row.C.push_back(pooled.angle_count[k] / (contacts * 2 * dtheta));
    row.binary_force.push_back(force[k] / force_average);
    row.sigma.push_back(length[k] / mean_branch);
    deviation = std::max(deviation, std::fabs(row.sigma.back() - 1));
  }
  r["sigma_max_deviation"] = deviation;
  const Harmonic sigma_2 = harmonic(row.sigma, 2);
  r["sigma_anisotropy"] = std::hypot(sigma_2.sin_coefficient, sigma_2.cos_coefficient);
  for (std::size_t k = 0; k < D; ++k)
    row.P_C.push_back(pairs > 0 ? pooled.deflection_count[k] / (2 * pairs * dx) : kNaN);
}

// The stresses and both sides' left-hand sides from the window's observable rows.
void stress_values(RunRow& row, const shear_run::Opened& o, const std::string& path, std::size_t first_row) {
  auto& r = row.runs;
  auto& pr = row.prediction;
  const Stresses st = stresses(o, path, "stress_static", first_row);
  const Stresses bc = stresses(o, path, "stress_collisional", first_row);
  auto average = [&](const char* name, const std::vector<double>& x) {
    r[name] = mean(x);
    r[std::string(name) + "_error"] = mean_error(x);
  };
  average("p_static", st.p);
  average("p_collisional", bc.p);
  average("s_static", st.s);
  average("s_collisional", bc.s);
  average("sxx_static", st.xx);
  average("sxx_collisional", bc.xx);
  const double pbc = mean(bc.p);
  // (a − b)/c of window means, and its delta-method error.
  auto relative = [&](const std::vector<double>& a, const std::vector<double>& b, double& ratio, double& err) {
    const double ma = mean(a), mb = mean(b);
    ratio = (ma - mb) / pbc;
    err = delta_error({{a, 1 / pbc}, {b, -1 / pbc}, {bc.p, -ratio / pbc}});
  };
  relative(st.p, bc.p, pr["lhs_pressure"], pr["lhs_pressure_error"]);
  relative(st.s, bc.s, pr["lhs_shear"], pr["lhs_shear_error"]);
  relative(st.xx, bc.xx, pr["lhs_xx"], pr["lhs_xx_error"]);
  const double sbc = mean(bc.s);
  r["shear_ratio_collisional"] = sbc / pbc;
  r["shear_ratio_collisional_error"] = delta_error({{bc.s, 1 / pbc}, {bc.p, -sbc / (pbc * pbc)}});
}

RunRow run_row(const std::string& path, const TableSettings& settings, const XiValue& xi,
               const std::function<void()>& frame_done) {
  const shear_run::Opened o = shear_run::open(path, "gf-network");
  auto bad = [&](const std::string& what) { return UsageError("'" + path + "': " + what); };
  if (!o.reader.has_contacts())
    throw bad("no contacts stored (no /contacts group): gf-network needs its frames' contacts");
  const shear_run::Window w = shear_run::window(o, path, settings.window);
  const std::vector<std::size_t> frames = shear_run::window_frames(o, w);
  if (frames.empty())
    throw bad("no stored frame in the window (steps " + std::to_string(w.previous_step + 1) + " to " +
              std::to_string(o.step.back()) +
              "); store more frames (gf-shear --frame-every) or start the window earlier (--from-strain)");
  const io::RunIdentity id = io::read_run_identity(o.reader, o.parameters, path, {.hash = false, .dt = true});
  RunRow row;
  row.input = path;
  const std::size_t n = id.grains;
  row.grains = std::int32_t(n);
  row.frames = std::int32_t(frames.size());
  auto& r = row.runs;
  r["packing_fraction"] = id.packing_fraction;
  r["restitution"] = id.restitution;
  r["friction"] = id.friction;
  r["tangential_restitution"] = id.tangential_restitution;
  r["rate"] = id.rate;
  r["dt"] = id.dt;
  r["first_strain"] = std::fabs(o.strain[w.first_row]);
  r["last_strain"] = std::fabs(o.strain.back());

  const std::size_t blocks = std::min(settings.blocks, frames.size());
  std::vector<Histograms> block(blocks, Histograms(settings.angle_bins, settings.deflection_bins));
  const FrameSeries series = frame_sums(o, path, frames, settings, n, id.dt, block, frame_done);
  r["contacts"] = series.means.contacts;
  r["long_lived"] = series.means.long_lived;
  window_values(row, series, xi);
  histogram_values(row, block, settings);
  stress_values(row, o, path, w.first_row);
  return row;
}

}  // namespace

std::vector<XiValue> read_correlation(const std::string& table, const std::vector<std::string>& runs,
                                      correlation::XiReading reading) {
  return correlation::read_xi_ratios(table, runs, reading, "gf-network");
}

Table analyse(const std::vector<std::string>& runs, const TableSettings& settings) {
  if (runs.empty()) throw UsageError("no input trajectory");
  Table table;
  table.settings = settings;
  table.has_correlation = !settings.correlation.empty();
  std::vector<XiValue> xi(runs.size(), XiValue{kNaN, kNaN, false});
  if (table.has_correlation) xi = read_correlation(settings.correlation, runs, settings.xi);
  // Every run's window is checked before any frame is read.
  double total = 0, done = 0;
  for (const auto& path : runs) {
    const shear_run::Opened o = shear_run::open(path, "gf-network");
    total += double(shear_run::window_frames(o, shear_run::window(o, path, settings.window)).size());
  }
  Progress bar("gf-network", total, settings.quiet);
  std::string status;
  auto frame_done = [&] { bar.update(++done, status); };
  for (std::size_t i = 0; i < runs.size(); ++i) {
    status = "run " + std::to_string(i + 1) + "/" + std::to_string(runs.size());
    table.runs.push_back(run_row(runs[i], settings, xi[i], frame_done));
  }
  bar.finish();
  return table;
}

// ---- Output

const std::vector<io::Column>& run_columns() {
  static const std::vector<io::Column> columns = [] {
    const char* const stress = "mass/time^2";
    auto id = io::identity_column;
    std::vector<io::Column> c = {
        {"input", {}, "path of the trajectory as given on the command line", {}, {}, io::ColumnType::text},
        id("grains"),
        {"frames", "1", "stored frames in the window (those written by its steps)", {}, {}, io::ColumnType::int32},
        id("packing_fraction"),
        id("restitution"),
        id("friction"),
        id("tangential_restitution"),
        id("rate"),
        id("dt"),
        {"first_strain", "1", "shear strain of the first observable row of the window"},
        {"last_strain", "1", "shear strain of the last observable row of the window"},
        {"contacts", "1",
         "contacts per frame, window mean: force-bearing (P_n > 0), or with contact_gap in /parameters geometric "
         "(gap <= contact_gap mean diameters at the frame's positions)"},
        {"long_lived", "1",
         "long-lived contacts (age >= 2: in contact in this step and the previous one; geometric: within the gap "
         "at the frame and one step earlier) per frame"},
        {"coordination", "1", "z = 2 long_lived / N over all grains (ratio of window means)"},
        {"coordination_active", "1",
         "z over the grains with at least one long-lived contact: 2 long_lived / those grains"},
        {"mean_cos_deflection", "1",
         "<cos x> over pairs of distinct long-lived contacts of one grain, cos x = -u_Im.u_IJ (straight chain: 1)"},
        {"mean_cos_cos2_deflection", "1", "<cos x cos 2x> over the same pairs"},
        {"Phi", "1", "Phi = 2 <cos x> (the thesis' normalisation, eq. 6.23)"},
        {"Psi", "1", "Psi = 2 <cos x cos 2x> (eq. 6.23)"},
        {"phi_11", "1", "fabric <n_x n_x> over all contacts"},
        {"phi_22", "1", "fabric <n_y n_y> over all contacts"},
        {"phi_12", "1", "fabric <n_x n_y> over all contacts"},
        {"chi_11", "1", "force fabric <F_bc n_x n_x>/<F_bc> over all contacts (F_bc the stored binary_force)"},
        {"chi_22", "1", "force fabric <F_bc n_y n_y>/<F_bc>"},
        {"chi_12", "1", "force fabric <F_bc n_x n_y>/<F_bc>"},
        {"a_c", "1", "a_c = 4 phi_12: sin 2theta amplitude of C(theta) (eq. 6.20; negative in granflow's shear)"},
        {"a_c_prime", "1", "a'_c = 2 (phi_11 - phi_22): cos 2theta amplitude of C(theta)"},
        {"a_f", "1", "a_f of F_bc(theta) (eq. 6.21), exact inversion of chi given a_c, a'_c"},
        {"a_f_prime", "1", "a'_f of F_bc(theta), exact inversion"},
        {"shear_ratio_collisional_frames", "1",
         "s^bc/p^bc from the frames: -<|b| F_bc sin 2theta>/<|b| F_bc> (exact for the frames whatever "
         "sigma(theta))"}};
    // The frame quantities of /runs carry their delta-method error beside them.
    for (io::Column& col : c)
      if (std::find(kRunQuantities.begin(), kRunQuantities.end(), col.name) != kRunQuantities.end()) {
        col.error = col.name + "_error";
        col.error_meaning = "standard error of " + col.name + " (delta method over the frames, covariances included)";
      }
    const std::vector<io::Column> more = {
        {"fabric_norm", "1", "D = 1 + (a_c a_f + a'_c a'_f)/2 = <F_bc> contact-weighted / <F_bc> angle-averaged"},
        {"a_f_first_order", "1", "first-order reading a_f = 4 chi_12 - a_c"},
        {"a_f_prime_first_order", "1", "first-order reading a'_f = 2 (chi_11 - chi_22) - a'_c"},
        {"a4_c", "1", "sin 4theta coefficient of C(theta)/<C> from the pooled histogram (bin-average corrected)",
         "a4_c_error", "block-jackknife standard error of a4_c (--blocks contiguous blocks of frames)"},
        {"a4_c_prime", "1", "cos 4theta coefficient of C(theta)/<C>", "a4_c_prime_error",
         "block-jackknife standard error of a4_c_prime"},
        {"a4_f", "1", "sin 4theta coefficient of F_bc(theta)/<F_bc> (per-bin mean binary force)", "a4_f_error",
         "block-jackknife standard error of a4_f"},
        {"a4_f_prime", "1", "cos 4theta coefficient of F_bc(theta)/<F_bc>", "a4_f_prime_error",
         "block-jackknife standard error of a4_f_prime"},
        {"mean_binary_force", "force", "<F_bc> over all contacts of the window (contact-weighted)"},
        {"sigma_anisotropy", "1",
         "amplitude sqrt(s^2 + c^2) of the 2theta harmonic of sigma(theta)/<sigma> (/histograms/sigma, the "
         "per-bin mean |b|, bin-average corrected): sigma(theta)'s own anisotropy, C(theta)'s excluded; NaN if a "
         "bin is empty"},
        {"sigma_max_deviation", "1", "max over the angle bins of |sigma(theta_k)/<sigma> - 1| (/histograms/sigma)"},
        {"p_static", stress, "static pressure p^s = (Sxx + Syy)/2 of stress_static, window mean of the rows",
         "p_static_error", "blocked standard error of p_static"},
        {"p_collisional", stress, "collisional pressure p^bc of stress_collisional", "p_collisional_error",
         "blocked standard error of p_collisional"},
        {"s_static", stress, "static shear stress s^s = -Sxy of stress_static (positive for rate > 0)",
         "s_static_error", "blocked standard error of s_static"},
        {"s_collisional", stress, "collisional shear stress s^bc = -Sxy of stress_collisional", "s_collisional_error",
         "blocked standard error of s_collisional"},
        {"sxx_static", stress, "Sxx of stress_static", "sxx_static_error", "blocked standard error of sxx_static"},
        {"sxx_collisional", stress, "Sxx of stress_collisional", "sxx_collisional_error",
         "blocked standard error of sxx_collisional"},
        {"shear_ratio_collisional", "1", "s^bc/p^bc from the rows (= -2 chi_12 when sigma(theta) is constant)",
         "shear_ratio_collisional_error", "delta-method error of shear_ratio_collisional"}};
    c.insert(c.end(), more.begin(), more.end());
    return c;
  }();
  return columns;
}

std::vector<io::Column> prediction_columns(correlation::XiReading xi) {
  std::vector<io::Column> c;
  for (const char* side : {"pressure", "shear", "xx"}) {
    const std::string s = side;
    const char* what = s == "pressure" ? "(p^s - p^bc)/p^bc"
                       : s == "shear"  ? "(s^s - s^bc)/p^bc"
                                       : "(Sxx^s - Sxx^bc)/p^bc";
    const char* eq = s == "pressure" ? "6.27" : s == "shear" ? "6.28" : "6.29";
    c.push_back({"lhs_" + s, "1",
                 std::string("measured ") + what + " from the window's rows (left side of eq. " + eq + ")",
                 "lhs_" + s + "_error", "delta-method error of lhs_" + s});
    const std::pair<const char*, const char*> readings[] = {
        {"", "z = coordination, Phi, Psi (thesis' normalisation), sums continued to the non-integer limit"},
        {"_floor", "the main reading with the sums up to floor(xi/xi_el - 1)"},
        {"_active", "z = coordination_active, otherwise the main reading"},
        {"_unit", "Phi = mean_cos_deflection, Psi = mean_cos_cos2_deflection, otherwise the main reading"}};
    for (const auto& [suffix, reading] : readings) {
      const std::string name = "rhs_" + s + suffix;
      c.push_back({name, "1", std::string("predicted ") + what + " (right side of eq. " + eq + "): " + reading,
                   name + "_error",
                   "error of " + name + ": delta method over the frames plus d/d(xi/xi_el) times xi_ratio_error"});
    }
  }
  c.push_back({"xi_ratio", "1",
               std::string("xi/xi_el of the correlation table (its ") + correlation::xi_ratio_dataset(xi) + ")",
               "xi_ratio_error", "standard error of xi_ratio (the table's)"});
  c.push_back({"xi_measurable",
               "1",
               "1: the table marks the run's xi measurable (--xi abs: its measurable; signed, signed-length: the "
               "ratio finite)",
               {},
               {},
               io::ColumnType::int32});
  c.push_back({"sum_limit", "1", "L = max(xi/xi_el - 1, 0), the upper limit of the sums over links"});
  c.push_back({"network_factor", "1", "M = min(Phi (z - 1), 1)"});
  c.push_back({"path_factor", "1", "Q = Psi (z - 1)"});
  c.push_back({"continuation_real",
               "1",
               "1: the continued sums are real; 0: a negative base with a non-integer limit (floor values used)",
               {},
               {},
               io::ColumnType::int32});
  return c;
}

namespace {

// A per-run group (/runs, /prediction) of declared columns: the reals from the row's map
// (NaN where absent), the integers and texts from its members.
void write_group(io::AnalysisWriter& w, const std::string& group, const std::vector<io::Column>& columns,
                 const std::vector<RunRow>& runs, const std::map<std::string, double> RunRow::*values) {
  io::TableWriter table(w, group, kPerRun);
  auto real = [&](const std::string& name) {
    std::vector<double> out;
    for (const RunRow& r : runs) {
      const auto it = (r.*values).find(name);
      out.push_back(it == (r.*values).end() ? kNaN : it->second);
    }
    return out;
  };
  auto integer = [&](std::int32_t RunRow::*member) {
    std::vector<std::int64_t> out;
    for (const RunRow& r : runs) out.push_back(r.*member);
    return out;
  };
  const std::map<std::string, std::int32_t RunRow::*> integers = {{"grains", &RunRow::grains},
                                                                  {"frames", &RunRow::frames},
                                                                  {"xi_measurable", &RunRow::xi_measurable},
                                                                  {"continuation_real", &RunRow::continuation_real}};
  for (const io::Column& c : columns) {
    if (c.type == io::ColumnType::text) {
      std::vector<std::string> inputs;
      for (const RunRow& r : runs) inputs.push_back(r.input);
      table.write(c, inputs);
    } else if (c.type == io::ColumnType::int32) {
      table.write(c, integer(integers.at(c.name)));
    } else {
      table.write(c, real(c.name), c.error.empty() ? std::vector<double>{} : real(c.error));
    }
  }
}

// /histograms: C(θ), F_bc(θ), σ(θ) per angle bin and P_C(x) per deflection bin, per run.
void write_histograms(io::AnalysisWriter& w, const Table& table) {
  const std::size_t n = table.runs.size();
  const auto& runs = table.runs;
  io::Parameters per_run;
  per_run.set("rows", kPerRun);
  const std::size_t K = table.settings.angle_bins, D = table.settings.deflection_bins;
  std::vector<double> theta(K), deflection(D);
  for (std::size_t k = 0; k < K; ++k) theta[k] = (double(k) + 0.5) * std::numbers::pi / double(K);
  for (std::size_t k = 0; k < D; ++k) deflection[k] = (double(k) + 0.5) * std::numbers::pi / double(D);
  w.write("/histograms/theta", {K}, theta, "centre of the angle bin of the contact normal (theta folded into [0, pi))",
          "radian");
  w.write("/histograms/deflection", {D}, deflection, "centre of the |x| bin (deflection angle, [0, pi])", "radian");
  auto matrix = [&](std::vector<double> RunRow::*member) {
    std::vector<double> out;
    for (const RunRow& r : runs) out.insert(out.end(), (r.*member).begin(), (r.*member).end());
    return out;
  };
  w.write("/histograms/C", {n, K}, matrix(&RunRow::C),
          "C(theta): contacts in the bin / (contacts * 2 dtheta), a density over 2 pi (1/(2 pi) if isotropic)",
          "1/radian", per_run);
  w.write("/histograms/binary_force", {n, K}, matrix(&RunRow::binary_force),
          "F_bc(theta)/<F_bc>: per-bin mean binary force over its average over the bins (angle-averaged)", "1",
          per_run);
  w.write("/histograms/sigma", {n, K}, matrix(&RunRow::sigma),
          "sigma(theta)/<sigma>: per-bin mean |branch| over the mean |branch| of all contacts", "1", per_run);
  w.write("/histograms/P_C", {n, D}, matrix(&RunRow::P_C),
          "P_C(x): pairs in the |x| bin / (2 pairs dx), a density over x in [-pi, pi] (integral 1)", "1/radian",
          per_run);
}

}  // namespace

void write_table(const std::string& path, const Table& table, const io::Parameters& provenance) {
  io::AnalysisWriter w(path);
  // The settings also under the names the readers of the table use (underscores).
  io::Parameters parameters = provenance;
  parameters.set("from_strain", table.settings.window.from_strain);
  parameters.set("detect_transient", std::int64_t(table.settings.window.detect_transient));
  parameters.set("angle_bins", std::int64_t(table.settings.angle_bins));
  parameters.set("deflection_bins", std::int64_t(table.settings.deflection_bins));
  parameters.set("blocks", std::int64_t(table.settings.blocks));
  if (table.has_correlation) parameters.set("xi", correlation::xi_reading_name(table.settings.xi));
  w.write_parameters(parameters);
  const auto& runs = table.runs;
  write_group(w, "/runs", run_columns(), runs, &RunRow::runs);
  write_histograms(w, table);
  write_group(w, "/prediction", prediction_columns(table.settings.xi), runs, &RunRow::prediction);
  io::Parameters group;
  group.set("xi_source", !table.has_correlation ? "none" : correlation::xi_ratio_dataset(table.settings.xi));
  w.write_attributes("/prediction", group);
  w.close();
}

}  // namespace granflow::network
