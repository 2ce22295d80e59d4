// gf-network: the force-network model of thesis §6.2 (eqs. 6.12–6.29, Figs 6.5–6.8) over
// gf-shear trajectories, with xi/xi_el from a gf-correlate table.
#include <cmath>
#include <cstdio>
#include <optional>

#include "core/cli.hpp"
#include "core/output_file.hpp"
#include "core/signals.hpp"
#include "core/tool.hpp"
#include "io/provenance.hpp"
#include "network/table.hpp"

using namespace granflow;

int main(int argc, char** argv) {
  return run_tool("gf-network", [&] {
    CommandLine cli("gf-network", "RUN.h5... -o OUT.h5 [--correlation TABLE.h5] [options]",
                    "The force-network model (thesis 6.2) against gf-shear trajectories. Per run, over the stored\n"
                    "frames of a window past the transient: the coordination z of long-lived contacts (age >= 2),\n"
                    "the deflection x between consecutive links through a grain (its distribution P_C(x), <cos\n"
                    "x>, <cos x cos 2x>, and Φ, Ψ = twice those, eq. 6.23), the fabric and force-fabric\n"
                    "tensors and from them a_c, a'_c, a_f, a'_f (eqs. 6.20-6.21), the 4θ components of the\n"
                    "angular histograms of C(θ) and F_bc(θ), and both sides of eqs. 6.27-6.29: (p^s -\n"
                    "p^bc)/p^bc, (s^s - s^bc)/p^bc and (Sxx^s - Sxx^bc)/p^bc measured from the stress\n"
                    "observables, and predicted from the contacts with the sums over links up to ξ/ξ_el - 1\n"
                    "(ξ/ξ_el read from --correlation; the sums continued to a non-integer limit, and up to its\n"
                    "floor). Errors: delta method over the frames. Output: one HDF5 table, one row per run\n"
                    "(docs/file-format.md, gf-network table).");
    cli.positionals("RUN.h5", "gf-shear trajectories with stored frames (contacts), one row of /runs each", 1);
    cli.text_option("output", 'o', "FILE", "output HDF5 file");
    cli.text_option("correlation", 0, "TABLE",
                    "gf-correlate table made with --reference on these runs (matched by each run file's sha256): "
                    "ξ/ξ_el for the sums of eqs. 6.27-6.29; without it the predicted sides are NaN");
    cli.text_option("xi", 0, "abs|signed|signed-length",
                    "which ξ/ξ_el of the table: abs = xi_abs_ratio (decay length of |C|, the ξ of the thesis' "
                    "figures), signed = xi_ratio (eq. 5.2 on the signed C per unit area), signed-length = "
                    "xi_length_ratio (eq. 5.2 on the signed C per unit length)",
                    "abs");
    cli.needs("xi", "correlation");
    cli.real_option("from-strain", 0, "S", "average the rows and frames at shear strain >= S", "0.5");
    cli.flag("detect-transient", 0,
             "start each run later than --from-strain where its own transient ends: MSER on 100 block means of "
             "its T and p (the rule of gf-kinetic and gf-correlate)");
    cli.real_option("contact-gap", 0, "H",
                    "count geometric contacts instead of force-bearing ones: pairs whose gap at a frame's positions is "
                    "at most H mean diameters, long-lived when within it one step earlier too (thesis App. A.1; H >= 0; "
                    "F_bc of a contact is its pair's recorded one, 0 if it bore no force)");
    cli.integer_option("angle-bins", 0, "K", "bins of the contact angle θ over [0, π) (>= 4)", "36");
    cli.integer_option("deflection-bins", 0, "D", "bins of the deflection |x| over [0, π] (>= 4)", "36");
    cli.integer_option("blocks", 0, "B",
                       "contiguous blocks of frames for the jackknife errors of the 4θ components (>= 2)", "10");
    if (!cli.parse(argc, argv)) return 0;

    network::TableSettings s;
    s.window.from_strain = cli.real("from-strain");
    require_in_range("from-strain", s.window.from_strain, 0, INFINITY, false, true);
    s.window.detect_transient = cli.flag_set("detect-transient");
    auto count = [&](const char* name, long long least) {
      const long long v = cli.integer(name);
      if (v < least || v > 100000)
        throw UsageError(std::string("option --") + name + ": must be between " + std::to_string(least) +
                         " and 100000, got " + std::to_string(v));
      return std::size_t(v);
    };
    s.angle_bins = count("angle-bins", 4);
    s.deflection_bins = count("deflection-bins", 4);
    s.blocks = count("blocks", 2);
    const std::string xi = cli.text("xi");
    const std::optional<correlation::XiReading> reading = correlation::parse_xi_reading(xi);
    if (!reading) throw UsageError("option --xi: must be abs, signed or signed-length, got '" + xi + "'");
    s.xi = *reading;
    if (cli.given("correlation")) {
      s.correlation = cli.text("correlation");
      if (s.correlation.empty()) throw UsageError("option --correlation: no file given");
    }
    if (cli.given("contact-gap")) {
      s.contact_gap = cli.real("contact-gap");
      require_in_range("contact-gap", s.contact_gap, 0, 1, false, false);
    }
    s.quiet = cli.flag_set("quiet");

    refuse_output_among_inputs(
        cli.text("output"), cli.positional(),
        s.correlation.empty() ? std::vector<std::string>{} : std::vector<std::string>{s.correlation});
    OutputFile out(cli.text("output"));
    const network::Table table = network::analyse(cli.positional(), s);
    io::Parameters parameters = io::provenance(cli);
    for (std::size_t k = 0; k < cli.positional().size(); ++k) io::add_input(parameters, cli.positional()[k], int(k));
    if (!s.correlation.empty()) io::add_input(parameters, s.correlation, 0, "correlation");
    network::write_table(out.temp_path(), table, parameters);
    check_interrupt();
    out.commit();

    if (!s.quiet) {
      if (s.correlation.empty())
        std::fprintf(stderr, "gf-network: note: no --correlation: the predicted sides (rhs_*) are NaN\n");
      for (const auto& r : table.runs) {
        auto v = [&](const char* name) { return r.runs.at(name); };
        auto q = [&](const char* name) { return r.prediction.at(name); };
        std::fprintf(stderr,
                     "gf-network: %s: ν = %.4g, e = %.3g, z = %.4g, Φ = %.4g +- %.2g, Ψ = %.4g +- %.2g, "
                     "pressure lhs = %.4g +- %.2g, rhs = %.4g +- %.2g\n",
                     r.input.c_str(), v("packing_fraction"), v("restitution"), v("coordination"), v("Phi"),
                     v("Phi_error"), v("Psi"), v("Psi_error"), q("lhs_pressure"), q("lhs_pressure_error"),
                     q("rhs_pressure"), q("rhs_pressure_error"));
      }
    }
    return 0;
  });
}
