// gf-correlate: force correlations and contact-force statistics of sheared flows
// (thesis ch. 5: eq. 5.1–5.4, Figs 5.1–5.10) from one or many gf-shear trajectories.
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "core/cli.hpp"
#include "core/output_file.hpp"
#include "core/signals.hpp"
#include "core/tool.hpp"
#include "correlation/analysis.hpp"
#include "correlation/force_distribution.hpp"
#include "correlation/report.hpp"
#include "io/provenance.hpp"

using namespace granflow;

namespace {
int whole(const CommandLine& cli, const std::string& name, long long lo) {
  const long long v = cli.integer(name);
  if (v < lo || v > 1000000000) throw UsageError("option --" + name + ": must be in [" + std::to_string(lo) + ", 1e9]");
  return int(v);
}

// The analysis settings from the parsed options, each checked; references: --reference's files.
correlation::Settings read_settings(const CommandLine& cli, std::vector<std::string>& references) {
  correlation::Settings s;
  s.from_strain = cli.real("from-strain");
  require_in_range("from-strain", s.from_strain, 0, INFINITY, false, true);
  s.detect_transient = cli.flag_set("detect-transient");
  s.bin_width = cli.real("bin-width");
  s.max_lag = cli.real("max-lag");
  s.map_bin = cli.real("map-bin");
  require_in_range("bin-width", s.bin_width, 0, INFINITY, false, true);
  require_in_range("max-lag", s.max_lag, 0, INFINITY, false, true);
  require_in_range("map-bin", s.map_bin, 0, INFINITY, false, true);
  s.whole_box = cli.flag_set("whole-box");
  const std::string method = cli.text("map-method");
  if (method == "pairs") s.map_method = correlation::MapMethod::pairs;
  else if (method == "fft") s.map_method = correlation::MapMethod::fft;
  else if (method == "auto") s.map_method = correlation::MapMethod::automatic;
  else throw UsageError("option --map-method: must be pairs, fft or auto, not '" + method + "'");
  s.fft_cell = cli.real("fft-cell");
  require_in_range("fft-cell", s.fft_cell, 0, INFINITY, false, true);
  s.abs_bin_width = cli.real("abs-bin-width");
  require_in_range("abs-bin-width", s.abs_bin_width, 0, INFINITY, false, true);
  s.magnitude.noise = cli.real("abs-noise");
  require_in_range("abs-noise", s.magnitude.noise, 0, INFINITY, false, true);
  const std::string threshold_kind = cli.text("abs-threshold");
  if (threshold_kind != "soft" && threshold_kind != "hard")
    throw UsageError("option --abs-threshold: must be soft or hard, not '" + threshold_kind + "'");
  s.magnitude.hard = threshold_kind == "hard";
  s.magnitude.max_tail_share = cli.real("max-tail-share");
  require_in_range("max-tail-share", s.magnitude.max_tail_share, 0, 1, false, false);
  s.angle_bins = whole(cli, "angle-bins", 3);
  s.blocks = whole(cli, "blocks", 1);
  s.threshold = cli.real("threshold");
  require_positive("threshold", s.threshold);
  if (cli.given("xi-el")) {
    s.xi_el = cli.real("xi-el");
    require_positive("xi-el", *s.xi_el);
  }
  references = cli.text_list("reference");
  if (cli.given("reference") && references.empty()) throw UsageError("option --reference: no file given");
  s.force_bin_width = cli.real("force-bin-width");
  require_positive("force-bin-width", s.force_bin_width);
  s.force_max = cli.real("force-max");
  if (!(s.force_max >= s.force_bin_width)) throw UsageError("option --force-max: must be >= --force-bin-width");
  s.kde_bandwidth = cli.real("kde-bandwidth");
  require_positive("kde-bandwidth", s.kde_bandwidth);
  if (!(s.force_max >= 4 * s.kde_bandwidth))
    throw UsageError("option --kde-bandwidth: must be at most --force-max/4 (the peak test compares f = 0 and 3h)");
  correlation::check_force_bins(s.force_bin_width, s.force_max, s.kde_bandwidth);
  s.bootstrap = whole(cli, "bootstrap", 0);
  const long long seed = cli.integer("seed");
  if (seed < 0) throw UsageError("option --seed: must be >= 0");
  s.seed = std::uint64_t(seed);
  s.clusters_window = whole(cli, "clusters-window", 0);
  s.clusters_frame = cli.integer("clusters-frame");
  s.quiet = cli.flag_set("quiet");
  return s;
}

// The per-run summary on stderr (unless --quiet).
void print_summary(const correlation::Report& report, const correlation::Settings& s, bool no_reference) {
  if (!s.quiet && !s.xi_el && no_reference)
    std::fprintf(stderr, "gf-correlate: note: no --reference or --xi-el: ξ/ξ_el and ν_bc not computed\n");
  if (!s.quiet)
    for (std::size_t i = 0; i < report.runs.size(); ++i)
      std::fprintf(stderr,
                   "gf-correlate: %s: %zu frames, ξ = %.4g +- %.2g (ξ/ξ_el = %.3g), xi_abs = %.4g +- %.2g "
                   "(xi_abs/xi_abs_el = %.3g%s), P(f) %s (%.0f%%)\n",
                   report.runs[i].path.c_str(), report.runs[i].frames.size(), report.results[i].xi,
                   report.results[i].xi_error, report.xi_ratio[i], report.results[i].magnitude.xi,
                   report.results[i].magnitude.xi_error, report.xi_abs_ratio[i],
                   report.results[i].magnitude.measurable ? "" : ", reaches the box",
                   report.results[i].peak.peak == 1 ? "peaks at f > 0" : "is largest at f = 0",
                   100 * report.results[i].peak.confidence);
  if (!s.quiet && s.map_method == correlation::MapMethod::automatic)
    std::fprintf(stderr, "gf-correlate: pair sums by %s (%s)\n",
                 report.method == correlation::MapMethod::fft ? "fft" : "pairs", report.method_reason.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  return run_tool("gf-correlate", [&] {
    CommandLine cli(
        "gf-correlate", "RUN.h5... -o OUT.h5 [options]",
        "Averages over the frames of each gf-shear trajectory past --from-strain: the force correlation\n"
        "C(l) of eq. 5.1 (total contact force F^i of every grain with a contact; isotropic in radial\n"
        "bins and as a map of lag vectors, exact pair sums over Lees-Edwards minimum images up to\n"
        "--max-lag), the correlation length ξ of eq. 5.2, its angular dependence ξ(θ) with the fit\n"
        "of eq. 5.3 (a0, theta0), and the distributions P(f) of normal forces and of the binary-collision\n"
        "forces F_bc of eq. 5.4, with a robust decision whether P(f) peaks at f > 0; and xi_abs, the decay\n"
        "length of |C(l)| (eq. 5.2 on |C| with a noise floor, the ξ of the thesis' figures), per direction\n"
        "too, with a flag for correlations that reach the box. With reference runs (dilute, binary\n"
        "collisions only) or --xi-el, also ξ/ξ_el per run and, across a sweep, ν_bc(e) where ξ/ξ_el\n"
        "crosses --threshold (for ξ and for xi_abs). Errors are jackknife (bootstrap for the peak)\n"
        "over --blocks blocks of consecutive frames. Lengths in code units; defaults scale with the mean grain\n"
        "diameter σ of the first run. Output: one HDF5 file, one row per run (docs/file-format.md).");
    cli.positionals("RUN.h5", "gf-shear trajectories (with contacts), one row of the output each", 1);
    cli.text_option("output", 'o', "FILE", "output HDF5 file");
    cli.real_option("from-strain", 0, "S", "skip the transient: average frames at shear strain >= S", "0.5");
    cli.flag("detect-transient", 0,
             "start each run later than --from-strain where its own transient ends: MSER on 100 block "
             "means of its T and p (the rule of the pipelines' steady_state.py; dilute flows heat up for "
             "many strain units); the strain used is /runs/first_strain");
    cli.real_option("bin-width", 0, "D", "radial bin width of C(l); 0 = σ/20", "0");
    cli.real_option("max-lag", 0, "L", "largest lag counted anywhere; 0 = min(15 σ, half the shorter box side)", "0");
    cli.flag("whole-box", 0,
             "--max-lag = half the shorter box side of all runs, the largest lag whose minimum image is unique "
             "(with --map-method fft or auto for large runs: the exact pair sums grow as N^2 there)");
    cli.text_option("map-method", 0, "pairs|fft|auto",
                    "pair sums of C(l), ξ and the map: pairs = exact over every pair within --max-lag (the "
                    "reference); fft = by FFT of the forces binned on a grid of --fft-cell (exact for grains moved to "
                    "the cell centres); auto = whichever a cost model expects faster on the largest run",
                    "pairs");
    cli.real_option("fft-cell", 0, "G", "side of the FFT grid's cells (--map-method fft/auto); 0 = σ/20", "0");
    cli.integer_option("angle-bins", 0, "K", "sectors of [0, π) for ξ(θ)", "24");
    cli.real_option("map-bin", 0, "H",
                    "side of the square bins of the C(l) map; 0 = σ/5 (coarser beyond --max-lag 200 σ: at most "
                    "2000 bins per axis)",
                    "0");
    cli.real_option("abs-bin-width", 0, "D",
                    "coarse radial bins of xi_abs, a whole multiple of --bin-width; 0 = the multiple nearest σ/4", "0");
    cli.real_option("abs-noise", 0, "K", "xi_abs: reduce each coarse bin of |C| by K jackknife errors (floored at 0)",
                    "2");
    cli.text_option("abs-threshold", 0, "soft|hard",
                    "xi_abs noise floor: soft subtracts --abs-noise errors from every bin (biased low by a few %), "
                    "hard drops the bins below it and keeps the others whole",
                    "soft");
    cli.real_option("max-tail-share", 0, "S",
                    "xi_abs not measurable (correlations reach the box) when more than S of int l|C| lies beyond "
                    "2/3 of --max-lag",
                    "0.05");
    cli.integer_option("blocks", 0, "B", "blocks of consecutive frames for the errors (fewer if fewer frames)", "20");
    cli.text_option("reference", 0, "FILES",
                    "comma-separated dilute reference runs whose pooled ξ is ξ_el (without it or --xi-el, "
                    "ξ/ξ_el is NaN and ν_bc is not computed); one list, the option given once; a name with a comma "
                    "cannot be listed (link it under another name)");
    cli.real_option("xi-el", 0, "XI", "the elastic reference length ξ_el, instead of --reference");
    cli.real_option("threshold", 0, "C", "ξ/ξ_el at the binary-collision crossover ν_bc", "1.25");
    cli.real_option("force-bin-width", 0, "DF", "bin width of P(f) in units of the mean force", "0.05");
    cli.real_option("force-max", 0, "F", "largest f of P(f) and of the peak search", "10");
    cli.real_option("kde-bandwidth", 0, "H", "bandwidth of the kernel density estimate deciding the peak of P(f)",
                    "0.1");
    cli.integer_option("bootstrap", 0, "N", "bootstrap replicates of the peak decision", "200");
    cli.integer_option("seed", 0, "SEED", "random seed of the bootstrap", "1");
    cli.integer_option("clusters-window", 0, "FRAMES", "write contact clusters over this many stored frames; 0 = none",
                       "0");
    cli.integer_option("clusters-frame", 0, "K", "last frame of the cluster window; negative counts from the end",
                       "-1");
    if (!cli.parse(argc, argv)) return 0;

    std::vector<std::string> references;
    const correlation::Settings s = read_settings(cli, references);

    refuse_output_among_inputs(cli.text("output"), cli.positional(), references);
    OutputFile out(cli.text("output"));
    const correlation::Report report = correlation::correlate(cli.positional(), references, s);
    io::Parameters parameters = io::provenance(cli);
    for (std::size_t k = 0; k < cli.positional().size(); ++k) io::add_input(parameters, cli.positional()[k], int(k));
    for (std::size_t k = 0; k < references.size(); ++k) io::add_input(parameters, references[k], int(k), "reference");
    correlation::write_report(out.temp_path(), report, parameters);
    check_interrupt();
    out.commit();

    print_summary(report, s, references.empty());
    return 0;
  });
}
