#pragma once
// gf-kinetic's analysis (thesis §6.1, docs/programs/gf-kinetic.md): one row per gf-shear
// trajectory of the measured temperature, static and collisional stresses, collision
// frequency (counted two ways) and pre-collisional velocity correlation, beside the Enskog
// predictions of kinetic.hpp with χ measured in elastic unsheared runs (the /equilibrium
// table) and interpolated at each run's ν.
//
// Averages run over a window of the run's observable rows: rows at |strain| ≥ from_strain
// (sheared runs) or at time ≥ from_time (γ̇ = 0), later where the run's own transient ends
// with detect_transient (MSER on T and p, statistics/steady.hpp's mser_first_row, the rule
// gf-correlate and steady_state.py use). Stored frames enter through their age-1 contacts
// (the births of the step that produced the frame) and their spins.
//
// Errors: every quantity is a smooth function f of window means x̄_k of per-row (or per-frame)
// series; its error is the standard error of the mean of the linearised series
// Σ_k (∂f/∂x̄_k)·x_k (the delta method, covariances included), by blocking
// (statistics/blocking.hpp) with at least kBlockingMinSamples values, else the plain standard
// error (stored frames are usually far apart in time).
#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "io/run_identity.hpp"
#include "io/table_writer.hpp"
#include "io/trajectory.hpp"
#include "statistics/delta.hpp"

namespace granflow::kinetic {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---- χ(ν) from the equilibrium table ----

struct ChiNode {
  double nu = 0, chi = 0, error = 0;
};

struct ChiValue {
  double chi = kNaN, error = kNaN;
};

// Monotone interpolation of the measured χ in ν: piecewise linear in ν of ln χ between the
// neighbouring nodes, so exact at the nodes and monotone between them; the error of ln χ is
// the neighbours' relative errors combined as independent, δ ln χ = √((1−w)²(δ_a/χ_a)² +
// w²(δ_b/χ_b)²), w the interpolation weight. Nodes at the same ν (within 1e-9) are first
// merged by the inverse-variance mean of ln χ. Outside [min_nu, max_nu] the two end nodes'
// line is extended (extrapolate), or, with a single node, that node scaled by Henderson's
// χ(ν)/χ(ν_node); the error is then the nearest node's relative error.
class ChiTable {
 public:
  // std::invalid_argument when empty or a χ ≤ 0 or not finite.
  explicit ChiTable(std::vector<ChiNode> nodes);
  double min_nu() const { return nodes_.front().nu; }
  double max_nu() const { return nodes_.back().nu; }
  bool covers(double nu) const;
  // std::out_of_range outside [min_nu, max_nu] unless extrapolate.
  ChiValue at(double nu, bool extrapolate = false) const;
  const std::vector<ChiNode>& nodes() const { return nodes_; }

 private:
  std::vector<ChiNode> nodes_;
};

// ---- Window means and their errors ----

// statistics/delta.hpp: the delta method over window means, shared with gf-network.
using statistics::delta_error;
using statistics::mean;
using statistics::mean_error;

// ---- One trajectory read over its window ----

struct Settings {
  double from_strain = 0.5;  // sheared runs
  double from_time = -1;     // γ̇ = 0 runs; negative: the second half of the run
  bool detect_transient = false;
  bool extrapolate = false;
  bool quiet = false;
};

// The run's identity (io::read_run_identity: path, N, ν, e, μ, e_t, γ̇, dt, box) and its window.
struct RunData : io::RunIdentity {
  double area = 0, number_density = 0, mean_mass = 0, mean_diameter = 0;
  double first_strain = 0, last_strain = 0, first_time = 0, last_time = 0;
  // Per window row: its span (steps since the previous row × dt) and the observables.
  std::vector<double> span, temperature_observed, pressure, p_kinetic, p_static, p_collisional, s_static, s_collisional,
      shear_stress, collisions, dissipated_energy, velocity_product;  // velocity_product empty if absent
  // Per stored frame in the window (step > 0): births (contacts of age 1), the sum over them of
  // the product of the pre-collisional normal velocities, and the rotational part of the
  // temperature observable, ½Σ R²(ω − Ω̄)²/N.
  std::vector<double> births, birth_velocity_product, rotational_temperature;
  std::vector<double> temperature;  // per row: the thesis' T = temperature_observed − mean rotational part
  double rotational_temperature_error = 0;
};

// Reads and checks a trajectory; UsageError naming the file: not a gf-shear trajectory, a
// packing, a box open in y, an observable missing or of another length, no /contacts or no
// stored frame in the window (when frames are needed), an empty window. frame_done is
// called after each stored frame read.
RunData read_run(const std::string& path, const Settings& settings, bool need_frames,
                 const std::function<void()>& frame_done = {});

// The stored frames read_run will read (for a progress bar): those past the window start.
std::size_t window_frame_count(const std::string& path, const Settings& settings);

// ---- The table ----

struct EquilibriumRow {
  std::string input;
  std::int32_t grains = 0;
  double packing_fraction = 0, temperature = 0, temperature_drift = 0;
  // −Σ dissipated_energy over the window / the translational kinetic energy (½ tr Σ m ṽṽ):
  // the relative change of the energy an elastic gas must conserve.
  double energy_drift = 0;
  double collision_frequency = 0, collision_frequency_error = 0, chi = 0, chi_error = 0;
  // Z = p/(n T_k) with n T_k the kinetic pressure (T_k = ⟨m|V|²⟩/2, mass-weighted), and the
  // same with the thesis' reading n T_k = n m̄ T/2 (p⁰), which differs for unequal masses.
  double compressibility = 0, compressibility_error = 0, chi_virial = 0, chi_virial_error = 0;
  double chi_virial_thesis_temperature = 0, chi_virial_thesis_temperature_error = 0;
  double chi_henderson = 0;
};

struct RunRow {
  std::string input;
  std::int32_t grains = 0;
  double packing_fraction = 0, restitution = 0, friction = 0, tangential_restitution = kNaN, rate = 0;
  double first_strain = 0, last_strain = 0, temperature = 0, temperature_error = 0, chi = 0, chi_error = 0;
  std::int32_t chi_source = 0;
  double p0 = 0, eta0 = 0, p_static = 0, p_static_error = 0, p_collisional = 0, p_collisional_error = 0;
  double s_static = 0, s_static_error = 0, s_collisional = 0, s_collisional_error = 0;
  double p_enskog = 0, p_enskog_error = 0, s_enskog_thesis = 0, s_enskog_2d = 0;
  double collision_frequency = 0, collision_frequency_error = 0;
  double collision_frequency_frames = 0, collision_frequency_frames_error = 0;
  double velocity_correlation = kNaN, velocity_correlation_error = kNaN;
  double velocity_correlation_frames = kNaN, velocity_correlation_frames_error = kNaN;
  double energy_balance = kNaN, energy_balance_error = kNaN;
};

inline constexpr std::int32_t kChiInterpolated = 0, kChiExtrapolated = 1, kChiHenderson = 2;

struct Table {
  Settings settings;
  bool has_equilibrium = false;
  std::vector<EquilibriumRow> equilibrium;  // sorted by packing_fraction
  std::vector<RunRow> runs;                 // in input order
};

// One equilibrium row; UsageError naming the file when the run is not elastic (e ≠ 1) or
// sheared (γ̇ ≠ 0).
EquilibriumRow equilibrium_row(const RunData& run);

// One row; table null: χ from Henderson's formula (chi_source 2).
RunRow run_row(const RunData& run, const ChiTable* table, bool extrapolate);

// The whole analysis, with a progress bar over the stored frames unless settings.quiet.
// UsageError (one line naming the run, its ν and the table's range) for a run outside the
// equilibrium table's ν range without extrapolate.
Table analyse(const std::vector<std::string>& runs, const std::vector<std::string>& equilibrium,
              const Settings& settings);

// The columns of /runs and /equilibrium, each declared once (docs/file-format.md, gf-kinetic
// table, is checked against them).
const std::vector<io::RowColumn<RunRow>>& run_columns();
const std::vector<io::RowColumn<EquilibriumRow>>& equilibrium_columns();

// Writes the table (docs/file-format.md, gf-kinetic table) with the provenance in /parameters.
void write_table(const std::string& path, const Table& table, const io::Parameters& provenance);

// The thesis' temperature, as stated in /runs' temperature_definition attribute.
extern const char* const kTemperatureDefinition;

}  // namespace granflow::kinetic
