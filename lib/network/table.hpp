#pragma once
// gf-network's analysis (thesis §6.2, docs/programs/gf-network.md): one row per gf-shear
// trajectory of the contact-network quantities measured on its stored frames (network.hpp:
// coordination of long-lived contacts, deflections Φ, Ψ, fabric and force fabric, the 4θ
// components of the angular histograms) and of both sides of eqs. 6.27–6.29: the measured
// (p^s − p^bc)/p^bc, (s^s − s^bc)/p^bc, (Σxx^s − Σxx^bc)/p^bc from the observable rows, and
// the network model's prediction with ξ/ξ_el read from a gf-correlate table.
//
// The window is gf-kinetic's (shear/steady_window.hpp). Errors: every frame quantity is a
// smooth function of the window means of the per-frame sums (network::FrameSums); its error is
// the delta method over those series (statistics/delta.hpp, covariances included), with the
// derivatives taken by central differences of relative step 1e-6; the predictions add
// ∂rhs/∂(ξ/ξ_el)·δ(ξ/ξ_el) in quadrature. The 4θ components of the pooled histograms have
// block-jackknife errors over contiguous blocks of frames.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "correlation/table_lookup.hpp"
#include "io/table_writer.hpp"
#include "io/trajectory.hpp"
#include "shear/steady_window.hpp"

namespace granflow::network {

struct TableSettings {
  shear_run::WindowSettings window{};
  std::size_t angle_bins = 36, deflection_bins = 36, blocks = 10;
  std::string correlation;  // gf-correlate table with --reference; empty: no prediction
  // --xi: which ξ/ξ_el of the table (abs: xi_abs_ratio, signed: xi_ratio, signed-length: xi_length_ratio)
  correlation::XiReading xi = correlation::XiReading::abs;
  // --contact-gap: geometric contacts (geometric_contacts.hpp) within this gap, in mean
  // diameters, instead of the force-bearing ones; NaN: force-bearing (the default).
  double contact_gap = std::numeric_limits<double>::quiet_NaN();
  bool quiet = false;
};

// One run's row: every real-valued dataset of /runs and /prediction by its name (the
// names of docs/file-format.md, gf-network table), and its histograms.
struct RunRow {
  std::string input;
  std::int32_t grains = 0, frames = 0, xi_measurable = 0, continuation_real = 0;
  std::map<std::string, double> runs, prediction;
  std::vector<double> C, binary_force, sigma, P_C;
};

struct Table {
  TableSettings settings;
  bool has_correlation = false;
  std::vector<RunRow> runs;  // in input order
};

// ξ/ξ_el of the runs, read from a gf-correlate table and matched by the sha256 of each
// run's file. UsageError naming the file: not a gf-correlate table, no ξ_el (made without
// --reference), a run it does not hold.
// (correlation/table_lookup.hpp, shared with gf-stz fit; messages name gf-network.)
using correlation::XiValue;
std::vector<XiValue> read_correlation(const std::string& table, const std::vector<std::string>& runs,
                                      correlation::XiReading reading);

// The whole analysis, with a progress bar over the stored frames of every run unless
// settings.quiet. UsageError (one line naming the file) for any input it cannot use.
Table analyse(const std::vector<std::string>& runs, const TableSettings& settings);

// The columns of /runs and of /prediction (whose xi_ratio names the --xi reading), each
// declared once (docs/file-format.md, gf-network table, is checked against them).
const std::vector<io::Column>& run_columns();
std::vector<io::Column> prediction_columns(correlation::XiReading xi);

// Writes the table with the provenance in /parameters.
void write_table(const std::string& path, const Table& table, const io::Parameters& provenance);

}  // namespace granflow::network
