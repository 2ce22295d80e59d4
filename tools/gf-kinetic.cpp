// gf-kinetic: the kinetic-theory check of thesis §6.1 (eqs. 6.2, 6.9–6.11, Figs 6.1–6.3) over
// gf-shear trajectories, with χ measured in elastic unsheared runs.
#include <cmath>
#include <cstdio>

#include "core/cli.hpp"
#include "core/output_file.hpp"
#include "core/signals.hpp"
#include "core/tool.hpp"
#include "io/provenance.hpp"
#include "kinetic/table.hpp"

using namespace granflow;

int main(int argc, char** argv) {
  return run_tool("gf-kinetic", [&] {
    CommandLine cli("gf-kinetic", "RUN.h5... -o OUT.h5 [--equilibrium EQ.h5,...] [options]",
                    "Kinetic theory against gf-shear trajectories (thesis 6.1). Per run, over a window past the\n"
                    "transient: the thesis' temperature T (translational, not mass-weighted), the static and\n"
                    "collisional pressure and shear stress (eqs. 2.8, 6.2), the Enskog predictions p0(1+e)χ ν\n"
                    "(eq. 6.9) and s (eq. 6.10 as printed, and the 2D Garzo-Dufty viscosity), the collision\n"
                    "frequency counted two ways (per-step observable; age-1 contacts of the stored frames), the\n"
                    "pre-collisional velocity correlation C_v (eq. 6.11, per collision, baseline -1/4) and the\n"
                    "energy balance (dissipation rate over s·γ̇·Lx·Ly). χ is measured in --equilibrium runs\n"
                    "(e = 1, rate 0) from the collision frequency, χ = ω/(nσ√(2πT)), beside χ\n"
                    "from their pressure, and interpolated at each run's ν; without them, Henderson's formula.\n"
                    "Errors are blocked standard errors. Output: one HDF5 table, one row per run\n"
                    "(docs/file-format.md).");
    cli.positionals("RUN.h5", "gf-shear trajectories (with contacts), one row of /runs each", 1);
    cli.text_option("output", 'o', "FILE", "output HDF5 file");
    cli.text_option("equilibrium", 0, "FILES",
                    "comma-separated elastic (e = 1) unsheared (rate 0) gf-shear runs that measure χ(ν): the "
                    "/equilibrium table; without it χ is Henderson's formula (chi_source 2); one list, the option "
                    "given once; a name with a comma cannot be listed (link it under another name)");
    cli.real_option("from-strain", 0, "S", "sheared runs: average the rows at shear strain >= S", "0.5");
    cli.real_option("from-time", 0, "T",
                    "runs at rate 0 (equilibrium runs): average the rows at time >= T; negative = the second half "
                    "of each run",
                    "-1");
    cli.flag("detect-transient", 0,
             "start each run later than --from-strain (--from-time) where its own transient ends: MSER on 100 "
             "block means of its T and p (the rule of gf-correlate and the pipelines' steady_state.py)");
    cli.flag("extrapolate", 0,
             "allow runs outside the equilibrium table's ν range (χ extrapolated, chi_source 1); without it "
             "such a run is refused");
    if (!cli.parse(argc, argv)) return 0;

    kinetic::Settings s;
    s.from_strain = cli.real("from-strain");
    require_in_range("from-strain", s.from_strain, 0, INFINITY, false, true);
    s.from_time = cli.real("from-time");
    s.detect_transient = cli.flag_set("detect-transient");
    s.extrapolate = cli.flag_set("extrapolate");
    s.quiet = cli.flag_set("quiet");
    const std::vector<std::string> equilibrium = cli.text_list("equilibrium");
    if (cli.given("equilibrium") && equilibrium.empty()) throw UsageError("option --equilibrium: no file given");
    if (s.extrapolate && equilibrium.empty())
      throw UsageError("option --extrapolate: needs --equilibrium (without it χ is Henderson's formula)");

    refuse_output_among_inputs(cli.text("output"), cli.positional(), equilibrium);
    OutputFile out(cli.text("output"));
    const kinetic::Table table = kinetic::analyse(cli.positional(), equilibrium, s);
    io::Parameters parameters = io::provenance(cli);
    for (std::size_t k = 0; k < cli.positional().size(); ++k) io::add_input(parameters, cli.positional()[k], int(k));
    for (std::size_t k = 0; k < equilibrium.size(); ++k)
      io::add_input(parameters, equilibrium[k], int(k), "equilibrium");
    kinetic::write_table(out.temp_path(), table, parameters);
    check_interrupt();
    out.commit();

    if (!s.quiet) {
      if (equilibrium.empty())
        std::fprintf(stderr, "gf-kinetic: note: no --equilibrium: χ is Henderson's formula for equal disks\n");
      for (const auto& e : table.equilibrium)
        std::fprintf(
            stderr, "gf-kinetic: %s: ν = %.4g, χ = %.4g +- %.2g, chi_virial = %.4g +- %.2g (Henderson %.4g)\n",
            e.input.c_str(), e.packing_fraction, e.chi, e.chi_error, e.chi_virial, e.chi_virial_error, e.chi_henderson);
      for (const auto& r : table.runs)
        std::fprintf(stderr,
                     "gf-kinetic: %s: ν = %.4g, e = %.3g, T = %.4g, p_bc/p_enskog = %.3g, omega = %.4g +- %.2g "
                     "(frames %.4g +- %.2g), energy balance %.4g +- %.2g\n",
                     r.input.c_str(), r.packing_fraction, r.restitution, r.temperature, r.p_collisional / r.p_enskog,
                     r.collision_frequency, r.collision_frequency_error, r.collision_frequency_frames,
                     r.collision_frequency_frames_error, r.energy_balance, r.energy_balance_error);
    }
    return 0;
  });
}
