#pragma once
// gf-correlate's output file (docs/file-format.md, gf-correlate table). R input runs, B radial bins,
// K sectors, M map bins per axis, F force bins, G (e, μ) series of the sweep:
//
//   /parameters         provenance: every option, command line, program, version,
//                       input[_k] + sha256 per run, reference[_k] + sha256 per reference
//   /runs/              one row per input run: input (path), packing_fraction,
//                       restitution, tangential_restitution, friction, rate, grains,
//                       frames, blocks, first_strain, last_strain, contacts
//   /correlation/       attrs: mean_diameter, bin_width, max_lag, angle_bins, map_bin,
//                       from_strain and the estimator's definition
//     r [B], C, C_error, xi_truncated [R][B]; xi, xi_error [R]; xi_el, xi_el_error [];
//     xi_ratio, xi_ratio_error [R]; (C per unit length:) xi_length, xi_length_error [R],
//     xi_length_truncated [R][B], xi_length_el, xi_length_el_error [],
//     xi_length_ratio, xi_length_ratio_error [R]; (decay length of |C|, decay_length.hpp:) xi_abs,
//     xi_abs_error, xi_abs_tail, xi_abs_tail_error, measurable [R]; xi_abs_theta,
//     xi_abs_theta_error [R][K]; a0_abs, a0_abs_error, theta0_abs, theta0_abs_error,
//     fit_abs_chi2_dof [R]; xi_abs_el, xi_abs_el_error []; xi_abs_ratio, xi_abs_ratio_error [R];
//     theta [K], xi_theta, xi_theta_error [R][K];
//     a0, a0_error, theta0, theta0_error, fit_chi2_dof [R], fit_weighted [R];
//     map [R][M][M] (row = y lag), map_x, map_y [M]
//   /forces/            f, f_bc [F]; P, P_error, P_bc, P_bc_error [R][F];
//     mean_force, mean_force_error, mean_binary_force, mean_binary_force_error [R];
//     peak, peak_confidence, mode, mode_error, p0_over_pmax [R]
//   /reference/         (with --reference) input, packing_fraction, restitution, friction,
//                       xi, xi_error, xi_length, xi_length_error, xi_abs, xi_abs_error,
//                       one row per reference run
//   /sweep/             (when ξ_el is known) restitution, friction, nu_bc, nu_bc_error,
//                       nu_below, nu_above, runs, sign_changes, status [G]; regime [R];
//                       the same for xi_abs over the measurable runs: nu_bc_abs, nu_bc_abs_error,
//                       nu_below_abs, nu_above_abs, runs_abs, sign_changes_abs, status_abs [G];
//                       regime_abs [R] (-2: not measurable)
//   /clusters/          (with --clusters-window) label [ΣN], position [ΣN][2],
//                       grain_offset [R+1], first_frame, last_frame, first_step, last_step,
//                       count [R], box [R][3] (Lx, Ly, Lees–Edwards offset)
#include <cstdint>
#include <string>
#include <vector>

#include "correlation/analysis.hpp"
#include "io/run_identity.hpp"
#include "io/table_writer.hpp"
#include "io/trajectory.hpp"

namespace granflow::correlation {

// One row of /runs and of /reference, as their column declarations read them.
struct RunsRow {
  const io::RunIdentity& run;
  std::int32_t frames = 0, blocks = 0;
  double first_strain = 0, last_strain = 0, contacts = 0;
};
struct ReferenceRow {
  const io::RunIdentity& run;
  double xi = 0, xi_error = 0, xi_length = 0, xi_length_error = 0, xi_abs = 0, xi_abs_error = 0;
};

// One row of /correlation's per-run datasets: the run's result and its ratios to the elastic
// lengths. /forces' per-run datasets read the RunResult itself.
struct CorrelationRow {
  const RunResult& result;
  double xi_ratio = 0, xi_ratio_error = 0, xi_length_ratio = 0, xi_length_ratio_error = 0, xi_abs_ratio = 0,
         xi_abs_ratio_error = 0;
};

// The columns of /runs and /reference, and the per-run ([R]) datasets of /correlation and
// /forces, each declared once (docs/file-format.md, gf-correlate table, is checked against them).
const std::vector<io::RowColumn<RunsRow>>& run_columns();
const std::vector<io::RowColumn<ReferenceRow>>& reference_columns();
const std::vector<io::RowColumn<CorrelationRow>>& correlation_columns();
const std::vector<io::RowColumn<RunResult>>& force_columns();

// Writes the file at path (the caller's temporary; see OutputFile).
void write_report(const std::string& path, const Report& report, const io::Parameters& provenance);

}  // namespace granflow::correlation
