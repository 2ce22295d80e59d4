// gf-stz fit: the STZ law (eq. 6.36) and mu(I) fitted to steady gf-shear runs per friction
// coefficient, with their predictions for every run and incline-bulk row (lib/stz/fit_table).
#include <cmath>
#include <cstdio>

#include "core/cli.hpp"
#include "core/error.hpp"
#include "core/output_file.hpp"
#include "core/signals.hpp"
#include "io/provenance.hpp"
#include "stz/commands.hpp"
#include "stz/fit_table.hpp"

namespace granflow::stz_tool {

int fit_command(int argc, char** argv) {
  CommandLine cli("gf-stz fit", "RUN.h5... -o FIT.h5 (--correlation TABLE.h5 | --min-packing-fraction NU) [options]",
                  "The STZ law of thesis eq. 6.36, x = A[sinh(κμ) − cosh(κμ)/(ζμ)], x = γ̇⟨R⟩/√T,\n"
                  "μ = s/p, fitted per friction coefficient to the steady means of gf-shear runs (the window of\n"
                  "gf-kinetic and gf-network) of restitution --fit-restitution that are dense (ξ/ξ_el >=\n"
                  "--dense-ratio from a gf-correlate table, or ν >= --min-packing-fraction), with its repose\n"
                  "angle θ* (eq. 6.35); μ(I) = μ_s + (μ_2 - μ_s)/(1 + I0/I) fitted to the same points;\n"
                  "both laws' predictions and residuals in s/p for every run and for the flowing rows of\n"
                  "incline-bulk tables (--incline). Output: one HDF5 table (docs/file-format.md, gf-stz fit table).");
  cli.positionals("RUN.h5", "steady gf-shear runs (sheared), one row of /runs each", 1);
  cli.text_option("output", 'o', "FILE", "output HDF5 file");
  cli.text_option("correlation", 0, "TABLE.h5",
                  "gf-correlate table made with --reference that holds every RUN (matched by sha256): dense = "
                  "ξ/ξ_el >= --dense-ratio");
  cli.real_option("min-packing-fraction", 0, "NU", "without --correlation: dense = the run's packing fraction >= NU");
  cli.real_option("dense-ratio", 0, "R", "with --correlation: dense = ξ/ξ_el >= R", "1.25");
  cli.text_option("xi", 0, "abs|signed", "with --correlation: abs reads the table's xi_abs_ratio, signed its xi_ratio",
                  "abs");
  cli.real_option("fit-restitution", 0, "E", "fit the dense runs of restitution E (exactly)", "0");
  cli.text_option("incline", 0, "FILES",
                  "comma-separated incline-bulk tables (pipelines/analysis/incline_bulk.py): their flowing rows are "
                  "predicted, never fitted; one list, the option given once; a name with a comma cannot be listed "
                  "(link it under another name)");
  cli.real_option("from-strain", 0, "S", "average the observable rows at shear strain >= S", "0.5");
  cli.flag("detect-transient", 0,
           "start each run later than --from-strain where its own transient ends: MSER on 100 block means of its "
           "T and p (the rule of gf-kinetic and gf-network)");
  cli.text_option("objective", 0, "least-squares|orthogonal",
                  "least-squares: minimise the weighted residuals in s/p at the measured x; orthogonal: "
                  "orthogonal distance regression, both errors (never least squares in log x: biased near "
                  "tan θ*)",
                  "least-squares");
  cli.conflicts("min-packing-fraction", "correlation");
  cli.needs("dense-ratio", "correlation");
  cli.needs("xi", "correlation");
  if (!cli.parse(argc, argv)) return 0;

  stz::FitSettings s;
  s.window.from_strain = cli.real("from-strain");
  require_in_range("from-strain", s.window.from_strain, 0, INFINITY, false, true);
  s.window.detect_transient = cli.flag_set("detect-transient");
  s.quiet = cli.flag_set("quiet");
  if (cli.given("correlation")) {
    s.correlation = cli.text("correlation");
    if (s.correlation.empty()) throw UsageError("option --correlation: no file given");
  }
  // The dense rule's checks (one of the two given, a positive ratio) are analyse_fit's.
  if (cli.given("min-packing-fraction")) s.min_packing_fraction = cli.real("min-packing-fraction");
  s.dense_ratio = cli.real("dense-ratio");
  const std::string xi = cli.text("xi");
  if (xi != "abs" && xi != "signed") throw UsageError("option --xi: expected abs or signed, got '" + xi + "'");
  s.signed_xi = xi == "signed";
  s.fit_restitution = cli.real("fit-restitution");
  const std::string objective = cli.text("objective");
  if (objective == "least-squares") s.objective = stz::StzObjective::least_squares_mu;
  else if (objective == "orthogonal") s.objective = stz::StzObjective::orthogonal_distance;
  else throw UsageError("option --objective: expected least-squares or orthogonal, got '" + objective + "'");
  s.incline = cli.text_list("incline");
  if (cli.given("incline") && s.incline.empty()) throw UsageError("option --incline: no file given");

  std::vector<std::string> others = s.incline;
  if (!s.correlation.empty()) others.push_back(s.correlation);
  refuse_output_among_inputs(cli.text("output"), cli.positional(), others);
  OutputFile out(cli.text("output"));
  const stz::FitTable table = stz::analyse_fit(cli.positional(), s);
  io::Parameters parameters = io::provenance(cli);
  // The program is gf-stz, the command an attribute of its own; cli saw argv from the command on.
  parameters.set("program", "gf-stz");
  parameters.set("command", "fit");
  parameters.set("command_line", "gf-stz " + cli.command_line());
  for (std::size_t k = 0; k < cli.positional().size(); ++k) io::add_input(parameters, cli.positional()[k], int(k));
  if (!s.correlation.empty()) io::add_input(parameters, s.correlation, 0, "correlation");
  for (std::size_t k = 0; k < s.incline.size(); ++k) io::add_input(parameters, s.incline[k], int(k), "incline");
  stz::write_fit_table(out.temp_path(), table, parameters);
  check_interrupt();
  out.commit();

  if (!s.quiet) {
    for (const std::string& note : table.notes) std::fprintf(stderr, "gf-stz: note: %s\n", note.c_str());
    for (const stz::FitRow& f : table.fits)
      std::fprintf(stderr,
                   "gf-stz: friction %.4g: %lld points, A = %.4g +- %.2g, kappa = %.4g +- %.2g, zeta = %.4g +- %.2g, "
                   "θ* = %.4g +- %.2g deg; rms residual STZ %.3g, μ(I) %.3g; predicted rms %.3g (%lld), "
                   "incline rms %.3g (%lld)\n",
                   f.friction, static_cast<long long>(f.points), f.stz.value.A, f.stz.error.A, f.stz.value.kappa,
                   f.stz.error.kappa, f.stz.value.zeta, f.stz.error.zeta, f.stz.theta_star * 180 / M_PI,
                   f.stz.theta_star_error * 180 / M_PI, f.stz_rms, f.mu_of_I_rms, f.predicted_rms,
                   static_cast<long long>(f.predicted_count), f.incline_rms, static_cast<long long>(f.incline_count));
  }
  return 0;
}

}  // namespace granflow::stz_tool
