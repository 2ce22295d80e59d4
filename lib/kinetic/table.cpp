#include "kinetic/table.hpp"
#include "core/format.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <stdexcept>

#include "core/error.hpp"
#include "core/progress.hpp"
#include "core/signals.hpp"
#include "io/analysis_writer.hpp"
#include "kinetic/kinetic.hpp"
#include "shear/steady_window.hpp"

namespace granflow::kinetic {

const char* const kTemperatureDefinition =
    "the thesis' T (eq. 4.5 without rotation): <|V|^2>, V = v - rate*y*x the peculiar velocity about the mean "
    "flow, over both components, not mass-weighted; = the temperature observable minus its rotational part "
    "(1/2)<R^2 (w - <w>)^2> measured on the stored frames (zero for frictionless runs)";

namespace {

std::vector<double> subset(const std::vector<double>& x, std::size_t first) {
  return std::vector<double>(x.begin() + std::ptrdiff_t(first), x.end());
}

}  // namespace

// ---- ChiTable

ChiTable::ChiTable(std::vector<ChiNode> nodes) {
  if (nodes.empty()) throw std::invalid_argument("ChiTable: no node");
  for (const ChiNode& n : nodes)
    if (!(n.chi > 0) || !std::isfinite(n.chi) || !std::isfinite(n.nu))
      throw std::invalid_argument("ChiTable: chi must be finite and > 0");
  std::stable_sort(nodes.begin(), nodes.end(), [](const ChiNode& a, const ChiNode& b) { return a.nu < b.nu; });
  // Runs at the same ν (e.g. two time steps) are one node: the inverse-variance mean of ln χ.
  for (std::size_t i = 0; i < nodes.size();) {
    std::size_t j = i;
    while (j < nodes.size() && nodes[j].nu - nodes[i].nu <= 1e-9) ++j;
    if (j - i == 1) {
      nodes_.push_back(nodes[i]);
    } else {
      double weights = 0, sum = 0, plain = 0;
      bool all_weighted = true;
      for (std::size_t k = i; k < j; ++k) {
        const double rel = nodes[k].error / nodes[k].chi;
        if (!(rel > 0) || !std::isfinite(rel)) all_weighted = false;
        plain += std::log(nodes[k].chi);
      }
      if (all_weighted) {
        for (std::size_t k = i; k < j; ++k) {
          const double rel = nodes[k].error / nodes[k].chi, w = 1 / (rel * rel);
          weights += w;
          sum += w * std::log(nodes[k].chi);
        }
        const double chi = std::exp(sum / weights);
        nodes_.push_back({nodes[i].nu, chi, chi / std::sqrt(weights)});
      } else {
        const double chi = std::exp(plain / double(j - i));
        nodes_.push_back({nodes[i].nu, chi, kNaN});
      }
    }
    i = j;
  }
}

bool ChiTable::covers(double nu) const { return nu >= min_nu() - 1e-9 && nu <= max_nu() + 1e-9; }

ChiValue ChiTable::at(double nu, bool extrapolate) const {
  if (!covers(nu) && !extrapolate)
    throw std::out_of_range("packing fraction " + format_number(nu) + " outside the equilibrium table's range [" +
                            format_number(min_nu()) + ", " + format_number(max_nu()) + "]");
  if (nodes_.size() == 1) {
    const ChiNode& n = nodes_.front();
    const double chi = n.chi * henderson_chi(nu) / henderson_chi(n.nu);
    return {chi, chi * n.error / n.chi};
  }
  // The segment holding ν, or the end segment whose line is extended.
  std::size_t b = 1;
  while (b + 1 < nodes_.size() && nodes_[b].nu < nu) ++b;
  const ChiNode &lo = nodes_[b - 1], &hi = nodes_[b];
  const double w = (nu - lo.nu) / (hi.nu - lo.nu);
  const double chi = std::exp((1 - w) * std::log(lo.chi) + w * std::log(hi.chi));
  const double rel_lo = lo.error / lo.chi, rel_hi = hi.error / hi.chi;
  double rel;
  if (w < 0) rel = rel_lo;
  else if (w > 1) rel = rel_hi;
  else rel = std::hypot((1 - w) * rel_lo, w * rel_hi);
  if (w == 0) rel = rel_lo;  // exactly a node: its own error, even if the neighbour's is NaN
  if (w == 1) rel = rel_hi;
  return {chi, chi * rel};
}

// ---- Reading a run

namespace {

using shear_run::observable;
using shear_run::Opened;
using shear_run::tensor;
using shear_run::window_frames;

Opened open(const std::string& path) { return shear_run::open(path, "gf-kinetic"); }

shear_run::Window window(const Opened& o, const std::string& path, const Settings& s) {
  return shear_run::window(o, path, {s.from_strain, s.from_time, s.detect_transient});
}

}  // namespace

std::size_t window_frame_count(const std::string& path, const Settings& settings) {
  const Opened o = open(path);
  return window_frames(o, window(o, path, settings)).size();
}

RunData read_run(const std::string& path, const Settings& settings, bool need_frames,
                 const std::function<void()>& frame_done) {
  const Opened o = open(path);
  auto bad = [&](const std::string& what) { return UsageError("'" + path + "': " + what); };
  if (need_frames && !o.reader.has_contacts())
    throw bad("no contacts stored (no /contacts group): not a gf-shear trajectory");
  const shear_run::Window w = window(o, path, settings);

  RunData run;
  static_cast<io::RunIdentity&>(run) = io::read_run_identity(o.reader, o.parameters, path, {.hash = false, .dt = true});
  const io::GrainProperties grains = o.reader.grains();
  run.mean_mass = mean(grains.mass);
  run.mean_diameter = 2 * mean(grains.radius);
  run.area = run.box.area();
  run.number_density = double(run.grains) / run.area;

  const std::size_t f = w.first_row;
  run.first_strain = std::fabs(o.strain[f]);
  run.last_strain = std::fabs(o.strain.back());
  run.first_time = o.time[f];
  run.last_time = o.time.back();
  for (std::size_t r = f; r < o.step.size(); ++r)
    run.span.push_back(double(o.step[r] - (r > 0 ? o.step[r - 1] : 0)) * run.dt);
  run.temperature_observed = subset(observable(o, path, "temperature"), f);
  run.pressure = subset(observable(o, path, "pressure"), f);
  const std::vector<Mat2> kinetic_stress = tensor(o, path, "stress_kinetic");
  for (std::size_t r = f; r < kinetic_stress.size(); ++r) run.p_kinetic.push_back(0.5 * kinetic_stress[r].trace());
  run.shear_stress = subset(observable(o, path, "shear_stress"), f);
  run.collisions = subset(observable(o, path, "collisions"), f);
  run.dissipated_energy = subset(observable(o, path, "dissipated_energy"), f);
  if (o.reader.has_observable("collision_velocity_product"))
    run.velocity_product = subset(observable(o, path, "collision_velocity_product"), f);
  // The thesis' sign of s: −Σxy, as the shear_stress observable.
  for (const char* name : {"stress_static", "stress_collisional"}) {
    const std::vector<Mat2> t = tensor(o, path, name);
    auto& pressure = std::string(name) == "stress_static" ? run.p_static : run.p_collisional;
    auto& shear = std::string(name) == "stress_static" ? run.s_static : run.s_collisional;
    for (std::size_t r = f; r < t.size(); ++r) {
      pressure.push_back(0.5 * (t[r](0, 0) + t[r](1, 1)));
      shear.push_back(-t[r](0, 1));
    }
  }

  const std::vector<std::size_t> frames = window_frames(o, w);
  if (need_frames && frames.empty())
    throw bad("no stored frame in the window (steps " + std::to_string(w.previous_step + 1) + " to " +
              std::to_string(o.step.back()) +
              "); store more frames (gf-shear --frame-every) or start the window earlier");
  for (std::size_t k : frames) {
    check_interrupt();
    const io::Frame frame = o.reader.frame(k);
    double births = 0, product = 0;
    for (std::size_t c = 0; c < frame.contacts.size(); ++c) {
      // The reader checks every value; a pair of one grain with itself is no collision.
      if (frame.contacts.pair[c][0] == frame.contacts.pair[c][1])
        throw bad("/contacts/pair: frame " + std::to_string(k) + ", contact " + std::to_string(c) + " joins grain " +
                  std::to_string(frame.contacts.pair[c][0]) + " with itself");
      if (frame.contacts.age[c] == 1) {
        births += 1;
        product += frame.contacts.pre_normal_velocity[c][0] * frame.contacts.pre_normal_velocity[c][1];
      }
    }
    run.births.push_back(births);
    run.birth_velocity_product.push_back(product);
    const double mean_spin = mean(frame.angular_velocity);
    double rotational = 0;
    for (std::size_t i = 0; i < frame.angular_velocity.size(); ++i) {
      const double dw = grains.radius[i] * (frame.angular_velocity[i] - mean_spin);
      rotational += 0.5 * dw * dw;
    }
    run.rotational_temperature.push_back(rotational / double(run.grains));
    if (frame_done) frame_done();
  }
  // The rotational part is known only at frames: its window mean is subtracted from every row.
  double rotational = 0;
  if (!run.rotational_temperature.empty()) {
    rotational = mean(run.rotational_temperature);
    run.rotational_temperature_error = rotational > 0 ? mean_error(run.rotational_temperature) : 0;
    if (!std::isfinite(run.rotational_temperature_error)) run.rotational_temperature_error = 0;
  }
  for (double t : run.temperature_observed) run.temperature.push_back(t - rotational);
  return run;
}

// ---- Rows

namespace {

struct Common {
  double temperature = 0, temperature_error = 0;
  double omega = 0, omega_error = 0;          // collisions per grain per unit time
  double mean_collisions = 0, mean_span = 0;  // window means of the rows ω is the ratio of
};

Common common(const RunData& run) {
  Common c;
  c.temperature = mean(run.temperature);
  c.temperature_error = std::hypot(mean_error(run.temperature), run.rotational_temperature_error);
  // ω = 2Σcollisions/(NΣΔt): a ratio of window means.
  const double n = double(run.grains);
  const double a = c.mean_collisions = mean(run.collisions), b = c.mean_span = mean(run.span);
  c.omega = 2 * a / (n * b);
  c.omega_error = delta_error({{run.collisions, 2 / (n * b)}, {run.span, -c.omega / b}});
  return c;
}

}  // namespace

EquilibriumRow equilibrium_row(const RunData& run) {
  if (run.restitution != 1)
    throw UsageError("'" + run.path + "': not an equilibrium run: restitution " + format_number(run.restitution) +
                     " (--equilibrium needs elastic runs, e = 1, at rate 0)");
  if (run.rate != 0)
    throw UsageError("'" + run.path + "': not an equilibrium run: sheared at rate " + format_number(run.rate) +
                     " (--equilibrium needs elastic runs, e = 1, at rate 0)");
  const Common c = common(run);
  EquilibriumRow row;
  row.input = run.path;
  row.grains = std::int32_t(run.grains);
  row.packing_fraction = run.packing_fraction;
  row.temperature = c.temperature;
  const std::size_t q = run.temperature.size() / 4;
  const std::span<const double> t(run.temperature);
  row.temperature_drift = q > 0 ? (mean(t.last(q)) - mean(t.first(q))) / c.temperature : kNaN;
  double dissipated = 0;
  for (double d : run.dissipated_energy) dissipated += d;
  row.energy_drift = -dissipated / (mean(run.p_kinetic) * run.area);
  row.collision_frequency = c.omega;
  row.collision_frequency_error = c.omega_error;
  const double n = run.number_density, sigma = run.mean_diameter, nu = run.packing_fraction;
  row.chi = chi_from_collision_frequency(c.omega, n, sigma, c.temperature);
  // χ ∝ ω·T^(−1/2) with ω = 2ā/(Nb̄): linearised in the means of collisions, span and T.
  const double a = c.mean_collisions, b = c.mean_span;
  row.chi_error = std::hypot(
      delta_error(
          {{run.collisions, row.chi / a}, {run.span, -row.chi / b}, {run.temperature, -row.chi / (2 * c.temperature)}}),
      row.chi * run.rotational_temperature_error / (2 * c.temperature));
  // Z = p/(n T_k), n T_k the kinetic pressure ½ tr Σ m ṽṽ/A: T_k = ⟨m|V|²⟩/2 per degree of
  // freedom, what the virial relation holds for with unequal masses.
  const double p = mean(run.pressure), kinetic = mean(run.p_kinetic);
  row.compressibility = p / kinetic;
  row.compressibility_error =
      delta_error({{run.pressure, 1 / kinetic}, {run.p_kinetic, -row.compressibility / kinetic}});
  row.chi_virial = chi_virial(row.compressibility, nu);
  row.chi_virial_error = row.compressibility_error / (2 * nu);
  // The thesis' reading n T_k = p⁰ = n m̄ T/2 (mean mass, unweighted T): for unequal masses in
  // equipartition it is n T_k·⟨m⟩⟨1/m⟩, so Z and χ come out smaller.
  const double p0_value = p0(n, run.mean_mass, c.temperature), z_thesis = p / p0_value;
  row.chi_virial_thesis_temperature = chi_virial(z_thesis, nu);
  row.chi_virial_thesis_temperature_error =
      std::hypot(delta_error({{run.pressure, 1 / p0_value}, {run.temperature, -z_thesis / c.temperature}}),
                 z_thesis * run.rotational_temperature_error / c.temperature) /
      (2 * nu);
  row.chi_henderson = henderson_chi(nu);
  return row;
}

RunRow run_row(const RunData& run, const ChiTable* table, bool extrapolate) {
  const Common c = common(run);
  RunRow row;
  row.input = run.path;
  row.grains = std::int32_t(run.grains);
  row.packing_fraction = run.packing_fraction;
  row.restitution = run.restitution;
  row.friction = run.friction;
  row.tangential_restitution = run.tangential_restitution;
  row.rate = run.rate;
  row.first_strain = run.first_strain;
  row.last_strain = run.last_strain;
  row.temperature = c.temperature;
  row.temperature_error = c.temperature_error;
  const double nu = run.packing_fraction, e = run.restitution, T = c.temperature;
  if (table) {
    if (!table->covers(nu) && !extrapolate)
      throw UsageError("'" + run.path + "': packing fraction " + format_number(nu) +
                       " is outside the equilibrium table's range [" + format_number(table->min_nu()) + ", " +
                       format_number(table->max_nu()) + "] (--extrapolate allows it)");
    const ChiValue chi = table->at(nu, extrapolate);
    row.chi = chi.chi;
    row.chi_error = chi.error;
    row.chi_source = table->covers(nu) ? kChiInterpolated : kChiExtrapolated;
  } else {
    row.chi = henderson_chi(nu);
    row.chi_error = 0;
    row.chi_source = kChiHenderson;
  }
  const double n = run.number_density;
  row.p0 = p0(n, run.mean_mass, T);
  row.eta0 = eta0(run.mean_mass, run.mean_diameter, T);
  auto average = [](const std::vector<double>& x, double& value, double& error) {
    value = mean(x);
    error = mean_error(x);
  };
  average(run.p_static, row.p_static, row.p_static_error);
  average(run.p_collisional, row.p_collisional, row.p_collisional_error);
  average(run.s_static, row.s_static, row.s_static_error);
  average(run.s_collisional, row.s_collisional, row.s_collisional_error);
  row.p_enskog = enskog_collisional_pressure(row.p0, e, row.chi, nu);
  row.p_enskog_error = std::fabs(row.p_enskog) * std::hypot(c.temperature_error / T, row.chi_error / row.chi);
  row.s_enskog_thesis = viscosity_thesis_eq6_10(e, nu, row.chi) * run.rate * row.eta0;
  row.s_enskog_2d = viscosity_garzo_dufty_2d(e, nu, row.chi).collisional * run.rate * row.eta0;

  row.collision_frequency = c.omega;
  row.collision_frequency_error = c.omega_error;
  // Each stored frame's age-1 contacts are the births of the one step that produced it.
  const double births = mean(run.births);
  row.collision_frequency_frames = 2 * births / (double(run.grains) * run.dt);
  row.collision_frequency_frames_error = 2 * mean_error(run.births) / (double(run.grains) * run.dt);

  // C_v = Σ product/(Σ collisions·T), every collision counted once; T the thesis' T.
  auto correlation = [&](const std::vector<double>& product, const std::vector<double>& count, double& value,
                         double& error) {
    const double a = mean(product), b = mean(count);
    if (!(b > 0)) return;
    value = a / (b * T);
    error = std::hypot(delta_error({{product, 1 / (b * T)}, {count, -value / b}, {run.temperature, -value / T}}),
                       value * run.rotational_temperature_error / T);
  };
  if (!run.velocity_product.empty())
    correlation(run.velocity_product, run.collisions, row.velocity_correlation, row.velocity_correlation_error);
  if (!run.births.empty()) {
    // The frames' T: the rows' mean (frames are too few for the per-frame series to help).
    const double a = mean(run.birth_velocity_product), b = births;
    if (b > 0) {
      row.velocity_correlation_frames = a / (b * T);
      row.velocity_correlation_frames_error = std::hypot(
          delta_error({{run.birth_velocity_product, 1 / (b * T)}, {run.births, -row.velocity_correlation_frames / b}}),
          row.velocity_correlation_frames * c.temperature_error / T);
    }
  }

  // Dissipation rate over the work of the shear stress, (ΣD/ΣΔt)/(s·γ̇·A) = ΣD/Σ(s·γ̇·A·Δt).
  if (run.rate != 0) {
    std::vector<double> work(run.span.size());
    for (std::size_t r = 0; r < work.size(); ++r) work[r] = run.shear_stress[r] * run.rate * run.area * run.span[r];
    const double d = mean(run.dissipated_energy), wm = mean(work);
    row.energy_balance = d / wm;
    row.energy_balance_error = delta_error({{run.dissipated_energy, 1 / wm}, {work, -row.energy_balance / wm}});
  }
  return row;
}

Table analyse(const std::vector<std::string>& runs, const std::vector<std::string>& equilibrium,
              const Settings& settings) {
  if (runs.empty()) throw UsageError("no input trajectory");
  Table table;
  table.settings = settings;
  table.has_equilibrium = !equilibrium.empty();
  double total = 0, done = 0;
  for (const auto& path : runs) total += double(window_frame_count(path, settings));
  Progress bar("gf-kinetic", total, settings.quiet);
  std::string status;
  auto frame_done = [&] { bar.update(++done, status); };

  std::vector<ChiNode> nodes;
  for (std::size_t i = 0; i < equilibrium.size(); ++i) {
    status = "equilibrium " + std::to_string(i + 1) + "/" + std::to_string(equilibrium.size());
    {
      // Refused before its window is looked at: the reason that matters comes first.
      const Opened o = open(equilibrium[i]);
      const double e = o.parameters.get_double("restitution");
      if (e != 1 || o.rate != 0)
        throw UsageError("'" + equilibrium[i] + "': not an equilibrium run: " +
                         (e != 1 ? "restitution " + format_number(e) : "sheared at rate " + format_number(o.rate)) +
                         " (--equilibrium needs elastic runs, e = 1, at rate 0)");
    }
    const RunData run = read_run(equilibrium[i], settings, false);
    table.equilibrium.push_back(equilibrium_row(run));
    if (!(table.equilibrium.back().chi > 0))
      throw UsageError("'" + equilibrium[i] + "': no collision in the window: chi cannot be measured");
    nodes.push_back(
        {table.equilibrium.back().packing_fraction, table.equilibrium.back().chi, table.equilibrium.back().chi_error});
  }
  std::stable_sort(
      table.equilibrium.begin(), table.equilibrium.end(),
      [](const EquilibriumRow& a, const EquilibriumRow& b) { return a.packing_fraction < b.packing_fraction; });
  std::optional<ChiTable> chi;
  if (!nodes.empty()) chi.emplace(nodes);

  // Every run's ν is checked against the table before any frame is read.
  if (chi && !settings.extrapolate)
    for (const auto& path : runs) {
      const Opened o = open(path);
      const double nu = o.parameters.get_double("packing_fraction");
      if (!chi->covers(nu))
        throw UsageError("'" + path + "': packing fraction " + format_number(nu) +
                         " is outside the equilibrium table's range [" + format_number(chi->min_nu()) + ", " +
                         format_number(chi->max_nu()) + "] (--extrapolate allows it)");
    }
  for (std::size_t i = 0; i < runs.size(); ++i) {
    status = "run " + std::to_string(i + 1) + "/" + std::to_string(runs.size());
    const RunData run = read_run(runs[i], settings, true, frame_done);
    table.runs.push_back(run_row(run, chi ? &*chi : nullptr, settings.extrapolate));
  }
  bar.finish();
  return table;
}

// ---- Output

const std::vector<io::RowColumn<RunRow>>& run_columns() {
  using io::integer, io::real, io::text;
  const char* stress = "mass/time^2";
  static const std::vector<io::RowColumn<RunRow>> columns = {
      text("input", "path of the trajectory as given on the command line", &RunRow::input),
      integer(io::identity_column("grains"), &RunRow::grains),
      real(io::identity_column("packing_fraction"), &RunRow::packing_fraction),
      real(io::identity_column("restitution"), &RunRow::restitution),
      real(io::identity_column("friction"), &RunRow::friction),
      real(io::identity_column("tangential_restitution"), &RunRow::tangential_restitution),
      real(io::identity_column("rate"), &RunRow::rate),
      real("first_strain", "1", "shear strain of the first observable row averaged", &RunRow::first_strain),
      real("last_strain", "1", "shear strain of the last observable row averaged", &RunRow::last_strain),
      real("temperature", "length^2/time^2", "granular temperature T of the thesis (see temperature_definition)",
           &RunRow::temperature, "blocked standard error of temperature", &RunRow::temperature_error),
      real("chi", "1", "pair correlation at contact χ at the run's ν (see chi_source)", &RunRow::chi,
           "error of chi (0 for Henderson's formula)", &RunRow::chi_error),
      integer("chi_source", "1",
              "origin of chi: 0 interpolated from /equilibrium (piecewise linear ln χ in ν), 1 extrapolated from it "
              "(--extrapolate), 2 Henderson's formula (no --equilibrium)",
              &RunRow::chi_source),
      real("p0", "mass/time^2", "kinetic pressure unit p⁰ = n m T/2 (mean mass m, n = N/(Lx Ly))", &RunRow::p0),
      real("eta0", "mass/time", "viscosity unit η⁰ = (m/σ)√(T/2π) (mean mass m and diameter σ)", &RunRow::eta0),
      real("p_static", stress, "static (contact) pressure p^s = (Σxx + Σyy)/2 of stress_static (eq. 2.8)",
           &RunRow::p_static, "blocked standard error of p_static", &RunRow::p_static_error),
      real("p_collisional", stress, "collisional pressure p^bc of stress_collisional (eq. 6.2)", &RunRow::p_collisional,
           "blocked standard error of p_collisional", &RunRow::p_collisional_error),
      real("s_static", stress, "static shear stress s^s = −Σxy of stress_static (positive for γ̇ > 0)",
           &RunRow::s_static, "blocked standard error of s_static", &RunRow::s_static_error),
      real("s_collisional", stress, "collisional shear stress s^bc = −Σxy of stress_collisional",
           &RunRow::s_collisional, "blocked standard error of s_collisional", &RunRow::s_collisional_error),
      real("p_enskog", stress, "Enskog collisional pressure p⁰(1 + e)χν (eq. 6.9)", &RunRow::p_enskog,
           "error of p_enskog from those of T and χ", &RunRow::p_enskog_error),
      real("s_enskog_thesis", stress, "eq. 6.10 as printed, times γ̇η⁰", &RunRow::s_enskog_thesis),
      real("s_enskog_2d", stress, "2D Garzó–Dufty collisional viscosity times γ̇η⁰", &RunRow::s_enskog_2d),
      real("collision_frequency", "1/time",
           "collisions per grain per unit time ω = 2Σcollisions/(N Δt), from the per-step collisions observable",
           &RunRow::collision_frequency, "blocked standard error of collision_frequency",
           &RunRow::collision_frequency_error),
      real("collision_frequency_frames", "1/time",
           "ω = 2⟨contacts of age 1 per stored frame⟩/(N dt): the births of the step of each frame",
           &RunRow::collision_frequency_frames, "standard error of collision_frequency_frames over the frames",
           &RunRow::collision_frequency_frames_error),
      real("velocity_correlation", "1",
           "C_v (eq. 6.11) = Σcollision_velocity_product/(Σcollisions T), every collision counted once; NaN without "
           "that observable",
           &RunRow::velocity_correlation, "blocked standard error of C_v", &RunRow::velocity_correlation_error),
      real("velocity_correlation_frames", "1",
           "C_v from the pre_normal_velocity of the age-1 contacts of the stored frames",
           &RunRow::velocity_correlation_frames, "standard error of velocity_correlation_frames",
           &RunRow::velocity_correlation_frames_error),
      real("energy_balance", "1",
           "dissipation rate over the work of the shear stress, (Σ dissipated_energy/Δt)/(s γ̇ Lx Ly); NaN at γ̇ = 0",
           &RunRow::energy_balance, "blocked standard error of energy_balance", &RunRow::energy_balance_error)};
  return columns;
}

const std::vector<io::RowColumn<EquilibriumRow>>& equilibrium_columns() {
  using io::integer, io::real, io::text;
  using Row = EquilibriumRow;
  static const std::vector<io::RowColumn<Row>> columns = {
      text("input", "path of the equilibrium run as given on the command line", &Row::input),
      integer(io::identity_column("grains"), &Row::grains),
      real(io::identity_column("packing_fraction"), &Row::packing_fraction),
      real("temperature", "length^2/time^2", "granular temperature T of the thesis over the window", &Row::temperature),
      real("temperature_drift", "1", "relative change of T between the first and last quarter of the window",
           &Row::temperature_drift),
      real("energy_drift", "1",
           "relative change of the kinetic energy over the window, −Σ dissipated_energy / (½ tr stress_kinetic · "
           "Lx·Ly) (0 for an exactly elastic gas)",
           &Row::energy_drift),
      real("collision_frequency", "1/time", "collisions per grain per unit time ω (per-step collisions observable)",
           &Row::collision_frequency, "blocked standard error of ω", &Row::collision_frequency_error),
      real("chi", "1", "χ = ω/(nσ√(2πT)), mean diameter σ", &Row::chi, "blocked standard error of chi",
           &Row::chi_error),
      real("compressibility", "1",
           "Z = p/(n T_k), p the total pressure, n T_k the kinetic pressure (T_k = <m|V|^2>/2, mass-weighted)",
           &Row::compressibility, "blocked standard error of Z", &Row::compressibility_error),
      real("chi_virial", "1", "χ from the pressure, (Z − 1)/(2ν)", &Row::chi_virial,
           "blocked standard error of chi_virial", &Row::chi_virial_error),
      real("chi_virial_thesis_temperature", "1",
           "χ from the pressure with the thesis' reading n T_k = p0 = n m T/2 (mean mass, unweighted T): (p/p0 − "
           "1)/(2ν)",
           &Row::chi_virial_thesis_temperature, "blocked standard error of chi_virial_thesis_temperature",
           &Row::chi_virial_thesis_temperature_error),
      real("chi_henderson", "1", "Henderson's (1 − 7ν/16)/(1 − ν)² at ν (equal disks)", &Row::chi_henderson)};
  return columns;
}

void write_table(const std::string& path, const Table& table, const io::Parameters& provenance) {
  io::AnalysisWriter w(path);
  w.write_parameters(provenance);
  io::TableWriter(w, "/runs", "one row per RUN.h5, in command-line order").write(table.runs, run_columns());
  io::Parameters group;
  group.set("velocity_correlation_convention", "per collision");
  group.set("velocity_correlation_baseline", kCvMolecularChaosPerCollision);
  group.set("temperature_definition", kTemperatureDefinition);
  group.set("from_strain", table.settings.from_strain);
  group.set("from_time", table.settings.from_time);
  group.set("detect_transient", std::int64_t(table.settings.detect_transient));
  group.set("extrapolate", std::int64_t(table.settings.extrapolate));
  w.write_attributes("/runs", group);
  if (table.has_equilibrium)
    io::TableWriter(w, "/equilibrium", "one row per equilibrium run, sorted by packing_fraction")
        .write(table.equilibrium, equilibrium_columns());
  w.close();
}

}  // namespace granflow::kinetic
