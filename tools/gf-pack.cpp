// gf-pack: initial configurations (thesis App. A.3) — a biperiodic packing at a
// target packing fraction, or a dilute layer above a fixed rough base (--incline).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "core/cli.hpp"
#include "core/output_file.hpp"
#include "core/progress.hpp"
#include "core/signals.hpp"
#include "core/tool.hpp"
#include "io/provenance.hpp"
#include "packing/packing.hpp"
#include "packing/packing_io.hpp"

using namespace granflow;

int main(int argc, char** argv) {
  return run_tool("gf-pack", [&] {
    CommandLine cli("gf-pack", "-o PACKING.h5 [options]",
                    "Makes a packing of polydisperse disks (diameters uniform in [σ−Δ, σ+Δ], mass πR²):\n"
                    "a biperiodic square cell at exactly --packing-fraction, grown from a dilute start\n"
                    "while soft overlaps are relaxed away (FIRE), or, with --incline, a base row of\n"
                    "touching fixed grains along x at y = 0 with mobile grains placed dilute above it.\n"
                    "With --input, the grains of an existing packing (or of a trajectory frame) are\n"
                    "brought to --packing-fraction instead: same radii, box and positions scaled, relaxed;\n"
                    "with --tile K as well, they are copied K × K times into a box K times wider and\n"
                    "taller, unchanged (a start for large N: a sheared frame of a small run, tiled).\n"
                    "The output is a one-frame H5MD trajectory that gf-shear / gf-incline read.");
    cli.text_option("input", 'i', "FILE",
                    "repack (or with --tile, tile) the grains of this packing or trajectory (see --frame)");
    cli.integer_option("frame", 0, "K", "with --input: frame to start from (negative counts from the end)", "-1");
    cli.text_option("output", 'o', "FILE", "packing file to write (HDF5, H5MD layout)");
    cli.integer_option("grains", 'n', "N",
                       "number of grains, not with --input (with --incline: mobile grains; 0 = from --height)", "1000");
    cli.real_option("packing-fraction", 0, "NU", "target area fraction ν, in (0, 0.91) (not with --incline)", "0.8");
    cli.real_option("mean-diameter", 0, "SIGMA", "mean grain diameter σ (not with --input)", "1.4");
    cli.real_option("polydispersity", 0, "DELTA",
                    "half-width of the diameter distribution Δ/σ, in [0, 1) (not with --input)", "0.26");
    cli.integer_option("seed", 0, "SEED", "random seed, not with --input (same seed and options: identical packing)",
                       "1");
    cli.real_option("tolerance", 0, "TOL", "relax until the largest overlap is below TOL·σ (not with --incline)",
                    "1e-9");
    cli.integer_option("tile", 0, "K",
                       "with --input: K × K copies of its grains, as its periodic images lie (Lees–Edwards\n"
                       "offset included), at its packing fraction, without relaxing: the start of a\n"
                       "large run at a cost linear in N (docs/programs/gf-pack.md)",
                       "1");
    cli.flag("incline", 0, "make an incline start instead of a biperiodic packing");
    cli.real_option("width", 0, "W", "with --incline: base length in mean diameters", "40");
    cli.real_option("height", 0, "H",
                    "with --incline: layer thickness in mean diameters, when --grains is not given (or 0)", "25");
    // Options that cannot apply are refused, not ignored (and not recorded): a repack takes
    // its grains, sizes and count from the input; an incline start is not relaxed to a
    // packing fraction.
    for (const char* option : {"grains", "seed", "polydispersity", "mean-diameter"}) cli.conflicts(option, "input");
    cli.needs("frame", "input");
    cli.needs("tile", "input");
    cli.conflicts("packing-fraction", "tile");
    cli.conflicts("tolerance", "tile");
    cli.needs("width", "incline");
    cli.needs("height", "incline");
    cli.conflicts("packing-fraction", "incline");
    cli.conflicts("tolerance", "incline");
    cli.conflicts("input", "incline");
    if (!cli.parse(argc, argv)) return 0;
    const bool quiet = cli.flag_set("quiet");
    const bool incline = cli.flag_set("incline");
    const long long seed = cli.integer("seed");
    if (seed < 0) throw UsageError("option --seed: must be >= 0");

    Packing packing;
    if (incline) {
      InclineParams p;
      p.width = cli.real("width");
      p.grains = cli.given("grains") ? cli.integer("grains") : 0;
      // With a grain count, the layer's thickness follows from it.
      if (p.grains != 0) cli.not_applicable("height", "--grains");
      p.height = cli.real("height");
      p.mean_diameter = cli.real("mean-diameter");
      p.polydispersity = cli.real("polydispersity");
      p.seed = std::uint64_t(seed);
      validate(p);
      io::Parameters parameters = io::provenance(cli);
      OutputFile out(cli.text("output"));
      packing = make_incline_packing(p);
      // The count used, also when --height gave it.
      parameters.set("grains", std::int64_t(std::count(packing.fixed.begin(), packing.fixed.end(), 0)));
      write_packing(out.temp_path(), packing, parameters);
      check_interrupt();
      out.commit();
    } else {
      PackingParams p;
      p.grains = cli.integer("grains");
      p.packing_fraction = cli.real("packing-fraction");
      p.mean_diameter = cli.real("mean-diameter");
      p.polydispersity = cli.real("polydispersity");
      p.seed = std::uint64_t(seed);
      p.overlap_tolerance = cli.real("tolerance");
      require_positive("tolerance", p.overlap_tolerance);
      validate(p);
      if (!cli.given("tile")) cli.not_applicable("tile", "");  // a repack: nothing tiled, nothing recorded
      io::Parameters parameters = io::provenance(cli);
      Packing start;
      if (cli.given("input")) {
        start = read_packing(cli.text("input"), cli.integer("frame"));
        io::add_input(parameters, cli.text("input"));
      }
      refuse_output_among_inputs(cli.text("output"), {cli.given("input") ? cli.text("input") : ""});
      OutputFile out(cli.text("output"));
      Progress bar("gf-pack", 1.0, quiet);
      char status[64];
      auto report = [&](double done, double overlap) {
        std::snprintf(status, sizeof status, "max overlap %.1e σ", overlap);
        bar.update(done, status);
      };
      if (cli.given("tile"))
        packing = tile(start, cli.integer("tile"));
      else
        packing = cli.given("input") ? repack(start, p.packing_fraction, p.overlap_tolerance, report)
                                     : make_biperiodic_packing(p, report);
      bar.finish();
      parameters.set("grains", std::int64_t(packing.radius.size()));
      write_packing(out.temp_path(), packing, parameters);
      check_interrupt();
      out.commit();
    }
    if (!quiet) {
      // σ of the grains written (a repack keeps the input's sizes).
      const double sigma = cli.given("input") ? 2 * std::accumulate(packing.radius.begin(), packing.radius.end(), 0.0) /
                                                    double(packing.radius.size())
                                              : cli.real("mean-diameter");
      std::fprintf(stderr, "gf-pack: %zu grains, ν = %.12f, max overlap = %.2e σ, %lld iterations, %.2f s -> %s\n",
                   packing.radius.size(), packing.packing_fraction, packing.max_overlap / sigma,
                   (long long)packing.iterations, packing.seconds, cli.text("output").c_str());
    }
    return 0;
  });
}
