// gf-incline: flow of rigid disks down a rough incline under gravity by Contact Dynamics
// (thesis §4.3), from an incline packing (gf-pack --incline) or a stored frame of a
// gf-incline trajectory, with the steady depth profiles of §4.3.1–4.3.2.
#include <cmath>
#include <optional>

#include "core/cli.hpp"
#include "core/output_file.hpp"
#include "core/tool.hpp"
#include "incline/observer.hpp"
#include "incline/start.hpp"
#include "io/provenance.hpp"
#include "io/units.hpp"
#include "run/runner.hpp"

using namespace granflow;

int main(int argc, char** argv) {
  return run_tool("gf-incline", [&] {
    CommandLine cli("gf-incline", "-i INCLINE.h5 -o TRAJECTORY.h5 --angle THETA [options]",
                    "Lets rigid disks flow down a rough incline: a base of fixed grains along x (periodic) at y = 0,\n"
                    "tilted by θ, so that gravity is g(sin θ, −cos θ) in the frame of the base (x down the slope).\n"
                    "Contact Dynamics as in gf-shear (restitution e, e_t, Coulomb friction μ; App. A). Times, in\n"
                    "the options (but --dt), the output and on stderr, are in units of τ = √(⟨R⟩/g), ⟨R⟩ the\n"
                    "mobile grains' mean radius. Writes an H5MD trajectory: frames, observables (flow_rate,\n"
                    "kinetic_energy, height, solver statistics), a /run summary, and\n"
                    "/profiles: depth profiles of packing fraction, V_x, γ̇, T, stresses, the Bagnold invariants\n"
                    "and the weight above each layer, averaged over x and over the steady part of the run (found\n"
                    "by MSER truncation of flow_rate and kinetic_energy, or --from-time), with the time blocks\n"
                    "they come from in /profiles/blocks. A grain leaving the layer (through the free surface\n"
                    "above the box top, or through the base) stops the run with exit code 1.\n"
                    "Ctrl-C or SIGTERM writes a checkpoint; the same command with --resume continues bit for bit.");
    cli.text_option("input", 'i', "FILE", "incline packing (gf-pack --incline) or gf-incline trajectory to start from");
    cli.integer_option("frame", 0, "K", "frame of --input to start from; negative counts from the end", "-1");
    cli.text_option("output", 'o', "FILE", "trajectory to write");
    cli.real_option("angle", 0, "THETA", "incline angle θ in degrees, in (0, 90); below 1° a warning (radians meant?)");
    cli.real_option("gravity", 0, "G", "magnitude g of gravity > 0", "1");
    cli.real_option("time", 0, "T",
                    "duration in units of τ (not with --steps); a layer 25 diameters thick at 12° (μ = 0) is steady "
                    "after ≈ 700 τ",
                    "2000");
    cli.integer_option("steps", 0, "N", "number of time steps (instead of --time)");
    cli.real_option("time-step", 0, "DT",
                    "time step in units of τ (not with --dt): CD's accuracy rests on small relative displacements "
                    "per step, and 2e-3 keeps the local strain per step γ̇·dt below 1e-3 up to γ̇τ = 0.5 (γ̇τ ≈ 0.16 at "
                    "the base of a 25-diameter layer at 12°)",
                    "2e-3");
    cli.real_option("dt", 0, "DT", "time step in code units (instead of --time-step)");
    add_contact_options(cli);
    cli.real_option("profile-bin", 0, "H", "thickness of the profile layers, in mean diameters of the mobile grains",
                    "3");
    cli.integer_option(
        "profile-block", 0, "N",
        "steps per time block of the profiles (sampled at every step); 0: automatic, min(5000, steps/20)", "0");
    cli.real_option("from-time", 0, "T", "average the profiles from this time (units of τ) instead of detecting it");
    add_run_options(cli, "10");
    // Options that would be ignored are refused (and not recorded).
    cli.conflicts("time", "steps");
    cli.conflicts("time-step", "dt");
    if (!cli.parse(argc, argv)) return 0;

    const Material material = material_option(cli);
    const SolverSettings settings = solver_option(cli);
    RunPlan plan = run_plan(cli);
    const double angle = cli.real("angle");
    require_in_range("angle", angle, 0, 90, true, true);
    const double g = cli.real("gravity");
    require_positive("gravity", g);
    if (cli.given("dt")) require_positive("dt", cli.real("dt"));
    else require_positive("time-step", cli.real("time-step"));
    if (cli.given("steps") && cli.integer("steps") < 1) throw UsageError("option --steps: must be >= 1");
    const double bin = cli.real("profile-bin");
    require_positive("profile-bin", bin);
    const long long block_option = cli.integer("profile-block");
    if (block_option < 0) throw UsageError("option --profile-block: must be >= 1, or 0 for automatic");
    std::optional<double> from_tau;
    if (cli.given("from-time")) {
      from_tau = cli.real("from-time");
      require_in_range("from-time", *from_tau, 0, INFINITY, false, true);
    }

    const std::string input_path = cli.text("input");
    io::TrajectoryReader input(input_path);
    InclineStart start = incline_start(input, cli.integer("frame"));
    const double tau = std::sqrt(start.mean_radius / g);
    const double dt = cli.given("dt") ? cli.real("dt") : cli.real("time-step") * tau;
    long long steps = 0;
    if (cli.given("steps")) {
      steps = cli.integer("steps");
    } else {
      const double duration = cli.real("time");
      require_positive("time", duration);
      steps = (long long)std::ceil(duration * tau / dt - 1e-9);
    }
    if (steps < block_option)
      throw UsageError("option --profile-block: " + std::to_string(block_option) + " steps is longer than the run (" +
                       std::to_string(steps) + " steps)");
    const long long block = block_option > 0 ? block_option : automatic_profile_block(steps);
    const InclineUnits units{dt, tau, g, start.mean_radius, start.mean_mass};
    const double last_block_start = units.time_of_step((steps - 1) / block * block);
    if (from_tau && *from_tau > last_block_start)
      throw UsageError("option --from-time: " + std::to_string(*from_tau) + " τ is after the start of the last " +
                       "profile block (" + std::to_string(last_block_start) + " τ)");
    set_length(plan, steps);
    // The files speak τ, as the options do.
    plan.time_unit = {io::kTauUnit, tau};

    const Vec2 gravity = incline_gravity(g, angle);
    ProfileAccumulator profiles(profile_grid(start.box, bin * 2 * start.mean_radius), block);
    const std::string kBlocks = "/profile_blocks";
    plan.after_step = [&](const Engine& e) { sample_incline(e, profiles, plan.time_unit); };
    plan.checkpoint_extra = [&](io::TrajectoryWriter& w) { write_blocks(w, kBlocks, profiles); };

    const RunStart run_start{
        .grains = start.grains,
        .box = start.box,
        .contacts = start.contacts,
        .rate = 0.0,
        .gravity = gravity,
        .material = material,
        .settings = settings,
        .dt = dt,
        .input_path = input_path,
        .add_parameters =
            [&](io::Parameters& parameters) {
              io::add_input_frame(parameters, input, start.frame_index, start.frame_step, start.frame_time);
              parameters.set("input_time_unit", start.frame_time_unit);  // input_time is in the input's unit
              parameters.set("mean_radius", start.mean_radius);
              parameters.set("mean_mass", start.mean_mass);
              parameters.set("tau", tau);
              parameters.set("dt", dt);
              // As used, when --steps or --dt decided them.
              if (!parameters.has("time")) parameters.set("time", double(steps) * dt / tau);
              if (!parameters.has("time-step")) parameters.set("time-step", dt / tau);
              parameters.set("grains", std::int64_t(start.grains.size() - start.base_grains));
              parameters.set("base_grains", std::int64_t(start.base_grains));
              parameters.set("total_steps", std::int64_t(steps));
              parameters.set("gravity_x", gravity.x());
              parameters.set("gravity_y", gravity.y());
              parameters.set("profile_bin_length", profiles.grid().bin);
              parameters.set("profile-block", std::int64_t(block));  // the length used, automatic or given
            },
        // The profiles accumulated so far, which plan.checkpoint_extra wrote.
        .restore =
            [&](const io::TrajectoryReader& checkpoint) {
              profiles.restore(read_blocks(checkpoint, kBlocks, profiles.grid()));
            },
    };

    refuse_output_among_inputs(cli.text("output"), {input_path});
    OutputFile out(cli.text("output"), /*resumable=*/true);
    StartedRun run = start_or_resume(cli, plan, out, run_start);
    warn_small_angle("gf-incline", angle);
    const RunStats stats = run_resumable(run.engine, run.writer, out, plan, run.stats, record_incline_observables);
    const ProfileAnalysis analysis = analyse_profiles(profiles, units, from_tau);
    report_steady("gf-incline", profiles, analysis, units, plan.quiet);
    finish_run(cli, run.writer, out, run.engine, stats, plan,
               [&](io::TrajectoryWriter& w) { write_profiles(w, profiles, analysis, units); });
    return 0;
  });
}
