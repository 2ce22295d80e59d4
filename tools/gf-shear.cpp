// gf-shear: simple shear of rigid disks in a Lees–Edwards cell by Contact Dynamics
// (thesis §4.1–4.2, App. A), from a packing or a stored frame of a trajectory.
#include <cmath>
#include <cstdio>
#include <numeric>

#include "core/cli.hpp"
#include "core/format.hpp"
#include "core/output_file.hpp"
#include "core/tool.hpp"
#include "run/runner.hpp"
#include "shear/shear.hpp"

using namespace granflow;

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
    cli.text_option("input", 'i', "FILE", "packing (gf-pack) or trajectory (gf-shear) to start from");
    cli.integer_option("frame", 0, "K", "frame of --input to start from; negative counts from the end", "-1");
    cli.text_option("output", 'o', "FILE", "trajectory to write");
    cli.real_option("rate", 0, "GAMMADOT", "shear rate γ̇ (may be negative; 0 for an unsheared gas)", "1");
    cli.real_option("strain", 0, "S", "total shear strain |γ̇|·t (not with --steps)", "10");
    cli.integer_option("steps", 0, "N", "number of time steps (instead of --strain; needed at --rate 0)");
    cli.real_option("strain-step", 0, "DGAMMA",
                    "|γ̇|·dt, the strain per step (not with --dt or --rate 0). At 1e-3 the steady p, s/p and T of "
                    "dense frictionless flows are within 1-3 % of their rigid limit (8.5 % in p at ν = 0.82, "
                    "e = 0.92); contact counts, collision frequencies, the binary-collision stress and ξ/ξ_el "
                    "depend on it (docs/results/convergence.md)",
                    "1e-3");
    cli.real_option("dt", 0, "DT", "time step (instead of --strain-step; at --rate 0 default 1e-3·σ/√T0)");
    add_contact_options(cli);
    cli.real_option("temperature", 0, "T0", "only at --rate 0: granular temperature of the random start velocities",
                    "0");
    cli.integer_option("seed", 0, "SEED", "random seed of the --temperature start", "1");
    cli.text_option("branch-velocities", 0, "MODE",
                    "only for a branch from a moving frame sheared at γ̇₀: its velocities and spins at --rate γ̇. "
                    "scale: × γ̇/γ̇₀ (the same trajectory at the new speed); keep: the fluctuations about the "
                    "mean flow kept, the mean flow set to γ̇; reset: the affine flow of γ̇, no fluctuations. "
                    "Contact forces × (γ̇/γ̇₀)² in every mode",
                    "scale");
    add_run_options(cli, "1");
    // Options that would be ignored are refused (and not recorded).
    cli.conflicts("strain", "steps");
    cli.conflicts("strain-step", "dt");
    if (!cli.parse(argc, argv)) return 0;

    const double rate = cli.real("rate");
    // The temperature start is for an unsheared gas; a sheared start has no strain step at
    // rate 0. Decided before run_plan, which signs the options that apply.
    if (rate != 0) cli.not_applicable("temperature", "--rate " + cli.text("rate"));
    else cli.not_applicable("strain-step", "--rate 0");
    const Material material = material_option(cli);
    const SolverSettings settings = solver_option(cli);
    const double temperature = cli.real("temperature");
    require_in_range("temperature", temperature, 0, INFINITY, false, true);
    const long long seed = cli.integer("seed");
    if (seed < 0) throw UsageError("option --seed: must be >= 0");

    // Time step and length of the run.
    double dt = 0;
    if (cli.given("dt")) {
      dt = cli.real("dt");
      require_positive("dt", dt);
      if (!(std::fabs(rate) * dt < 0.5))
        throw UsageError("option --dt: the strain step |rate·dt| = " + format_number(std::fabs(rate) * dt) +
                         " must be below 0.5");
    } else if (rate != 0) {
      const double strain_step = cli.real("strain-step");
      require_in_range("strain-step", strain_step, 0, 0.5, true, true);
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

    const BranchVelocities branch = branch_velocities_named(cli.text("branch-velocities"));

    const std::string input_path = cli.text("input");
    io::TrajectoryReader input(input_path);
    ShearStart start =
        shear_start(input, cli.integer("frame"), rate, temperature, std::uint64_t(seed),
                    cli.given("branch-velocities") ? std::optional<BranchVelocities>(branch) : std::nullopt);
    // A start at rest has no velocities to branch: the option is not recorded (refused
    // by shear_start when given). Decided before run_plan, which signs the options that apply.
    if (start.fresh) cli.not_applicable("branch-velocities", "a start at rest");
    RunPlan plan = run_plan(cli);
    const GrainState& g = start.grains;
    const double mean_radius = std::accumulate(g.radius.begin(), g.radius.end(), 0.0) / double(g.size());
    const double mean_mass = std::accumulate(g.mass.begin(), g.mass.end(), 0.0) / double(g.size());
    if (dt == 0) dt = 1e-3 * 2 * mean_radius / std::sqrt(temperature);
    if (steps == 0) {
      const double strain = cli.real("strain");
      require_positive("strain", strain);
      steps = (long long)std::ceil(strain / (std::fabs(rate) * dt) - 1e-9);
    }
    set_length(plan, steps);
    plan.strain_per_step = rate * dt;
    ShearTally tally;
    // The first step's energy change, recorded (and warned of) as soon as it is taken; a
    // resumed run took it before, unless its checkpoint is at step 0.
    FirstStepEnergy first_step;
    io::TrajectoryWriter* output = nullptr;
    plan.after_step = [&](const Engine& e) {
      tally.add(e.last_report());
      if (e.step_count() != 1) return;
      first_step.after = kinetic_energy_about_mean_flow(e.state(), e.box(), rate);
      first_step.write(*output);
      if (const std::string w = first_step.warning(rate, material); !w.empty())
        std::fprintf(stderr, "gf-shear: warning: %s\n", w.c_str());
    };
    plan.checkpoint_extra = [&](io::TrajectoryWriter& w) { tally.write(w); };

    const RunStart run_start{
        .grains = start.grains,
        .box = start.box,
        .contacts = start.contacts,
        .rate = rate,
        .gravity = Vec2::Zero(),
        .material = material,
        .settings = settings,
        .dt = dt,
        .input_path = input_path,
        .add_parameters =
            [&](io::Parameters& parameters) {
              parameters.set("packing_fraction", std::accumulate(g.radius.begin(), g.radius.end(), 0.0,
                                                                 [](double a, double r) { return a + M_PI * r * r; }) /
                                                     start.box.area());
              parameters.set("mean_radius", mean_radius);
              parameters.set("mean_mass", mean_mass);
              parameters.set("dt", dt);
              // As used, when --steps or --dt (or --rate 0) decided them.
              if (!parameters.has("strain")) parameters.set("strain", std::fabs(rate) * dt * double(steps));
              if (!parameters.has("strain-step")) parameters.set("strain-step", std::fabs(rate) * dt);
              parameters.set("grains", std::int64_t(g.size()));
              parameters.set("total_steps", std::int64_t(steps));
            },
        // The collisions and dissipation counted since the last observable row.
        .restore = [&](const io::TrajectoryReader& checkpoint) { tally.restore(checkpoint); },
    };

    refuse_output_among_inputs(cli.text("output"), {input_path});
    OutputFile out(cli.text("output"), /*resumable=*/true);
    StartedRun run = start_or_resume(cli, plan, out, run_start);
    output = &run.writer;
    if (run.engine.step_count() == 0)
      first_step.before = kinetic_energy_about_mean_flow(run.engine.state(), run.engine.box(), rate);
    const RunStats stats =
        run_resumable(run.engine, run.writer, out, plan, run.stats,
                      [&](const Engine& e, io::TrajectoryWriter& w) { record_shear_observables(e, w, tally); });
    finish_run(cli, run.writer, out, run.engine, stats, plan);
    return 0;
  });
}
