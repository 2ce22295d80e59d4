#pragma once
// gf-stz fit (docs/programs/gf-stz.md, docs/file-format.md "gf-stz fit table"): the STZ law
// (eq. 6.36) and μ(I) fitted, per friction coefficient, to the steady means of gf-shear runs,
// and their predictions for every run and every flowing incline-bulk row.
//
// Per run, over the steady window of shear/steady_window.hpp (the rule of gf-kinetic and
// gf-network): window means of p (the `pressure` observable, total), s = −Σxy (the
// `shear_stress` observable, total) and T (the `temperature` observable, eq. 4.5 with
// rotation, the T of the incline bulk table); then, as ratios of means,
//   μ = s̄/p̄,   x = |γ̇|⟨R⟩/√T̄,   I = |γ̇| d/√(p̄/ρ_p),   d = 2⟨R⟩,   ρ_p = Σm/Σ(πR²),
// with errors by the delta method over the blocked standard errors (statistics/delta.hpp).
// A run sheared with γ̇ < 0 is the mirror image of one with |γ̇|: s is taken as −sign(γ̇)Σxy.
//
// Incline rows (flowing rows of an incline-bulk table): x = /bulk/inertial, μ = /bulk/s_over_p,
// and I = 2x √(q/π), q = /bulk/mT_over_pR2 = m̄T/(p⟨R⟩²): the same I with ρ_p = m̄/(π⟨R⟩²),
// which is exact for equal disks and high by √(⟨R²⟩/⟨R⟩²) (1.1 % at gf-pack's default
// polydispersity) otherwise, the table holding no ⟨R²⟩. Its error adds the relative errors of
// x and √q in quadrature.
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "io/table_writer.hpp"
#include "io/trajectory.hpp"
#include "shear/steady_window.hpp"
#include "stz/constitutive.hpp"

namespace granflow::stz {

struct FitSettings {
  shear_run::WindowSettings window{};
  std::string correlation;  // gf-correlate table (with --reference); empty: the packing-fraction rule
  bool signed_xi = false;   // xi_ratio instead of xi_abs_ratio
  double dense_ratio = 1.25;
  double min_packing_fraction = kNaN;  // used without a correlation table
  double fit_restitution = 0;
  std::vector<std::string> incline;  // incline-bulk tables
  StzObjective objective = StzObjective::least_squares_mu;
  bool quiet = false;
};

struct FitRunRow {
  std::string input, input_sha256, kind;  // kind: "shear" | "incline"
  double friction = kNaN, restitution = kNaN, packing_fraction = kNaN;
  double rate_R_over_sqrt_T = kNaN, rate_R_over_sqrt_T_error = kNaN;
  double s_over_p = kNaN, s_over_p_error = kNaN;
  double inertial_number = kNaN, inertial_number_error = kNaN;
  double xi_ratio = kNaN;
  // The table's measurable flag: 0 where the correlations reach the cell, whose ratio is then
  // a lower bound (dense when that bound reaches the rule's ratio).
  bool xi_measurable = false;
  bool dense = false, fitted = false;
  double prediction = kNaN, residual = kNaN, prediction_mu_of_I = kNaN, residual_mu_of_I = kNaN;
};

struct FitRow {
  double friction = kNaN;
  std::int64_t points = 0, dof = 0, predicted_count = 0, incline_count = 0;
  StzFit stz;
  double tan_theta_star_jackknife_error = kNaN;  // stz_repose_jackknife_error over the fitted points
  MuIFit mu_of_I;
  bool has_mu_of_I = false;
  double stz_rms = kNaN, mu_of_I_rms = kNaN, predicted_rms = kNaN, incline_rms = kNaN;
  double mu_of_I_predicted_rms = kNaN, mu_of_I_incline_rms = kNaN;
};

struct FitTable {
  FitSettings settings;
  std::vector<FitRunRow> runs;     // shear rows in the order given, then incline rows
  std::vector<FitRow> fits;        // one per friction coefficient with a fit, by increasing μ
  std::vector<std::string> notes;  // one line each: frictions without a fit, μ(I) fits that failed
};

// One shear row (no dense/fitted decision, no prediction). UsageError naming the file: not a
// gf-shear trajectory, not sheared (γ̇ = 0), an observable missing, an empty window.
FitRunRow read_shear_row(const std::string& path, const shear_run::WindowSettings& window);

// The flowing rows of an incline-bulk table. UsageError naming the file: not HDF5, not an
// incline-bulk table (/parameters program, a dataset missing or of another length).
std::vector<FitRunRow> read_incline_rows(const std::string& path);

// The whole analysis. UsageError: a run given twice (same sha256), no friction coefficient
// with 3 fitted points ("fewer points than parameters"), the settings' own refusals (no dense
// rule, dense_ratio ≤ 0, orthogonal objective without the errors of every fitted point), and
// those of the readers; RuntimeFailure when the STZ minimiser fails.
FitTable analyse_fit(const std::vector<std::string>& runs, const FitSettings& settings);

// Writes the table with the provenance in /parameters.
// The columns of /runs and /fit, each declared once (docs/file-format.md, gf-stz fit table, is
// checked against them).
const std::vector<io::RowColumn<FitRunRow>>& run_columns();
const std::vector<io::RowColumn<FitRow>>& fit_columns();

void write_fit_table(const std::string& path, const FitTable& table, const io::Parameters& provenance);

}  // namespace granflow::stz
