// gf-shear: simple shear of rigid disks in a Lees–Edwards cell by Contact Dynamics
// (thesis §4.1–4.2, App. A), from a packing or a stored frame of a trajectory.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numeric>

#include "core/cli.hpp"
#include "core/output_file.hpp"
#include "core/tool.hpp"
#include "io/provenance.hpp"
#include "run/checkpoint.hpp"
#include "run/driver.hpp"
#include "run/frames.hpp"
#include "run/shear.hpp"

using namespace granflow;

namespace {
// The options that define the run (all but the ones about this session): a resumed
// run must be given the same.
std::string signature_of(const CommandLine& cli) {
  std::string s;
  for (const auto& [name, value] : cli.values())
    if (name != "resume" && name != "checkpoint-every") s += name + "=" + value + ";";
  return s;
}
}  // namespace

int main(int argc, char** argv) {
  return run_tool("gf-shear", [&] {
    CommandLine cli("gf-shear", "-i PACKING.h5 -o TRAJECTORY.h5 [options]",
                    "Shears rigid disks at constant rate γ̇ in a Lees–Edwards cell (SLLOD start v_x = γ̇(y − Ly/2),\n"
                    "ω = −γ̇/2) with Contact Dynamics: contact impulses from a non-smooth Gauss–Seidel solve of\n"
                    "restitution e, tangential restitution e_t and Coulomb friction μ (App. A). Writes an H5MD\n"
                    "trajectory: frames with contacts every --frame-every steps, observables every --observe-every\n"
                    "steps (stress tensors, p, s, N1, T, strain, solver statistics), and a /run summary.\n"
                    "With --rate 0 it runs an equilibrium (cooling or elastic) gas started at --temperature.\n"
                    "Ctrl-C or SIGTERM writes a checkpoint; the same command with --resume continues bit for bit.");
    cli.option("input", 'i', "FILE", "packing (gf-pack) or trajectory (gf-shear) to start from");
    cli.option("frame", 0, "K", "frame of --input to start from; negative counts from the end", "-1");
    cli.option("output", 'o', "FILE", "trajectory to write");
    cli.option("rate", 0, "GAMMADOT", "shear rate γ̇ (may be negative; 0 for an unsheared gas)", "1");
    cli.option("strain", 0, "S", "total shear strain γ̇·t (ignored with --steps)", "10");
    cli.option("steps", 0, "N", "number of time steps (overrides --strain; needed at --rate 0)");
    cli.option("strain-step", 0, "DGAMMA", "|γ̇|·dt, the strain per step (ignored with --dt)", "1e-3");
    cli.option("dt", 0, "DT", "time step (overrides --strain-step; at --rate 0 default 1e-3·σ/√T0)");
    cli.option("restitution", 0, "E", "normal restitution e in [0, 1]", "0.5");
    cli.option("tangential-restitution", 0, "ET", "tangential restitution e_t in [-1, 1] (eq. 4.1)", "0");
    cli.option("friction", 0, "MU", "Coulomb friction coefficient μ ≥ 0", "0");
    cli.option("tolerance", 0, "TOL", "solver tolerance: residual velocity × dt, a length (Υ = TOL/dt)", "1e-10");
    cli.option("max-iterations", 0, "N", "Gauss–Seidel sweeps per step before a step counts as unconverged",
               "10000");
    cli.option("alert-distance", 0, "D", "smallest gap of candidate contacts; 0 = 0.1 mean diameter", "0");
    cli.option("temperature", 0, "T0", "at --rate 0: granular temperature of the random start velocities", "0");
    cli.option("seed", 0, "SEED", "random seed of the --temperature start", "1");
    cli.option("frame-every", 0, "N", "steps between stored frames; 0 = 100 frames per run", "0");
    cli.option("observe-every", 0, "N", "steps between observable rows", "1");
    cli.option("checkpoint-every", 0, "SECONDS", "wall time between checkpoints (0: only on a signal)", "600");
    cli.flag("resume", 0, "continue from the checkpoint of an interrupted run of the same command, if any");
    if (!cli.parse(argc, argv)) return 0;
    const bool quiet = cli.flag_set("quiet");

    const double rate = cli.real("rate");
    Material material;
    material.restitution = cli.real("restitution");
    material.tangential_restitution = cli.real("tangential-restitution");
    material.friction = cli.real("friction");
    require_in_range("restitution", material.restitution, 0, 1, false, false);
    require_in_range("tangential-restitution", material.tangential_restitution, -1, 1, false, false);
    require_in_range("friction", material.friction, 0, INFINITY, false, true);
    SolverSettings settings;
    settings.tolerance = cli.real("tolerance");
    require_positive("tolerance", settings.tolerance);
    settings.max_iterations = int(cli.integer("max-iterations"));
    if (settings.max_iterations < 1) throw UsageError("option --max-iterations: must be >= 1");
    settings.alert_distance = cli.real("alert-distance");
    require_in_range("alert-distance", settings.alert_distance, 0, INFINITY, false, true);
    const double temperature = cli.real("temperature");
    require_in_range("temperature", temperature, 0, INFINITY, false, true);
    const long long seed = cli.integer("seed");
    if (seed < 0) throw UsageError("option --seed: must be >= 0");
    const long long observe_every = cli.integer("observe-every");
    if (observe_every < 1) throw UsageError("option --observe-every: must be >= 1");
    long long frame_every = cli.integer("frame-every");
    if (frame_every < 0) throw UsageError("option --frame-every: must be >= 0");
    const double checkpoint_every = cli.real("checkpoint-every");
    require_in_range("checkpoint-every", checkpoint_every, 0, INFINITY, false, true);

    // Time step and length of the run.
    double dt = 0;
    if (cli.given("dt")) {
      dt = cli.real("dt");
      require_positive("dt", dt);
    } else if (rate != 0) {
      const double strain_step = cli.real("strain-step");
      require_positive("strain-step", strain_step);
      dt = strain_step / std::fabs(rate);
    } else if (!(temperature > 0)) {
      throw UsageError("with --rate 0 give --dt, or --temperature to derive it");
    }
    long long steps = 0;
    if (cli.given("steps")) {
      steps = cli.integer("steps");
      if (steps < 1) throw UsageError("option --steps: must be >= 1");
    } else if (rate == 0) {
      throw UsageError("with --rate 0 give --steps (there is no strain)");
    }

    const std::string input_path = cli.text("input");
    io::TrajectoryReader input(input_path);
    ShearStart start = shear_start(input, cli.integer("frame"), rate, temperature, std::uint64_t(seed));
    const GrainState& g = start.grains;
    const double mean_radius = std::accumulate(g.radius.begin(), g.radius.end(), 0.0) / double(g.size());
    const double mean_mass = std::accumulate(g.mass.begin(), g.mass.end(), 0.0) / double(g.size());
    if (dt == 0) dt = 1e-3 * 2 * mean_radius / std::sqrt(temperature);
    if (steps == 0) {
      const double strain = cli.real("strain");
      require_positive("strain", strain);
      steps = (long long)std::ceil(strain / (std::fabs(rate) * dt) - 1e-9);
    }
    if (frame_every == 0) frame_every = std::max(1LL, steps / 100);

    OutputFile out(cli.text("output"), /*resumable=*/true);
    RunPlan plan;
    plan.total_steps = steps;
    plan.frame_every = frame_every;
    plan.observe_every = observe_every;
    plan.checkpoint_seconds = checkpoint_every;
    plan.checkpoint_path = checkpoint_path(out.final_path());
    plan.signature = signature_of(cli);
    plan.strain_per_step = rate * dt;
    plan.quiet = quiet;

    std::optional<Checkpoint> resume_from;
    if (cli.flag_set("resume") && std::filesystem::exists(plan.checkpoint_path)) {
      resume_from = read_checkpoint(plan.checkpoint_path);
      if (resume_from->signature != plan.signature)
        throw UsageError("checkpoint '" + plan.checkpoint_path + "' was made with other options (" +
                         resume_from->signature + "); run without --resume to start over");
      if (!std::filesystem::exists(out.temp_path()))
        throw UsageError("checkpoint '" + plan.checkpoint_path + "' has no partial trajectory '" + out.temp_path() +
                         "' beside it; run without --resume to start over");
    } else if (cli.flag_set("resume") && !quiet) {
      std::fprintf(stderr, "gf-shear: no checkpoint for '%s'; starting from the beginning\n",
                   out.final_path().c_str());
    }

    RunStats stats;
    std::optional<Engine> engine;
    std::optional<io::TrajectoryWriter> writer;
    if (resume_from) {
      engine.emplace(grains_of(resume_from->frame, resume_from->grains), resume_from->frame.box, rate, material,
                     settings, dt);
      engine->restore(resume_from->step, memory_of(resume_from->frame.contacts));
      stats = resume_from->stats;
      writer.emplace(io::TrajectoryWriter::reopen_for_append(out.temp_path(), std::size_t(stats.frames_written),
                                                             resume_from->step));
    } else {
      engine.emplace(start.grains, start.box, rate, material, settings, dt);
      engine->restore(0, memory_of(start.contacts));
      io::Parameters parameters = io::provenance(cli);
      io::add_input(parameters, input_path);
      parameters.set("packing_fraction",
                     std::accumulate(g.radius.begin(), g.radius.end(), 0.0,
                                     [](double a, double r) { return a + M_PI * r * r; }) /
                         start.box.area());
      parameters.set("mean_radius", mean_radius);
      parameters.set("mean_mass", mean_mass);
      parameters.set("dt", dt);
      parameters.set("grains", std::int64_t(g.size()));
      parameters.set("total_steps", std::int64_t(steps));
      writer.emplace(out.temp_path());
      writer->write_parameters(parameters);
      writer->write_grains(properties_of(g), start.box);
      writer->set_lees_edwards_rate(rate);
      io::Frame first = frame_of(*engine, 0, 0.0);
      first.contacts = start.contacts;
      first.has_contacts = start.contacts.size() > 0;
      writer->append_frame(first);
      stats.frames_written = 1;
    }

    try {
      stats = run_steps(*engine, *writer, plan, stats, record_shear_observables);
    } catch (const Interrupted&) {
      out.keep_partial();
      writer->close();
      throw;
    } catch (...) {
      std::filesystem::remove(plan.checkpoint_path);
      throw;
    }
    write_run_summary(*writer, *engine, stats);
    writer->close();
    out.commit();
    std::filesystem::remove(plan.checkpoint_path);

    if (stats.unconverged_steps > 0)
      std::fprintf(stderr, "gf-shear: warning: %lld of %lld steps did not converge (largest residual %.2e)\n",
                   (long long)stats.unconverged_steps, steps, stats.max_residual);
    if (!quiet)
      std::fprintf(stderr, "gf-shear: %lld steps, %.1f s, %.0f steps/s, %.1f sweeps/step -> %s\n", steps,
                   stats.wall_seconds, double(steps) / std::max(stats.wall_seconds, 1e-9),
                   double(stats.iterations) / double(steps), out.final_path().c_str());
    return 0;
  });
}
