#include "run/runner.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "core/error.hpp"
#include "core/sha256.hpp"
#include "io/hdf5_handle.hpp"
#include "io/provenance.hpp"
#include "run/frames.hpp"

namespace granflow {

void add_contact_options(CommandLine& cli) {
  cli.real_option("restitution", 0, "E", "normal restitution e in [0, 1]", "0.5");
  cli.real_option("tangential-restitution", 0, "ET", "tangential restitution e_t in [-1, 1] (eq. 4.1)", "0");
  cli.real_option("friction", 0, "MU",
                  "Coulomb friction coefficient μ ≥ 0; the solver is validated for μ ≤ 0.4 (tests and sweeps): much "
                  "higher μ at high density may not converge (see --max-unconverged)",
                  "0");
  cli.real_option("tolerance", 0, "TOL", "solver tolerance: residual velocity × dt, a length (Υ = TOL/dt)", "1e-10");
  cli.integer_option(
      "max-iterations", 0, "N",
      "Gauss–Seidel sweeps per step before a step counts as unconverged [default: " + std::to_string(kMaxIterations) +
          ", with --friction > 0 " + std::to_string(kMaxIterationsWithFriction) +
          ": frictional steps near jamming may take that long and converge]");
  cli.real_option("max-unconverged", 0, "F",
                  "largest share of the steps that may end unconverged (at --max-iterations); one more stops the run "
                  "with exit code 1 and no output",
                  "0.01");
  cli.real_option("alert-distance", 0, "D", "smallest gap of candidate contacts; 0 = 0.01 mean diameter", "0");
  cli.text_option("activation", 0, "RULE",
                  "which pairs the normal law constrains: predicted-gap (Moreau's: pairs that touch or would touch "
                  "within the step bounce, the others may close their gap but never overlap) or overlap (the "
                  "thesis' App. A.1: only pairs found touching or overlapping after the position update, so pairs "
                  "overlap by up to dt·|u_n| before they bounce)",
                  "predicted-gap");
  cli.flag("no-cluster-solves", 0,
           "Gauss–Seidel alone, without the exact solves of contact clusters (nor region solves, nor skipping "
           "settled rows): the same laws and tolerance, many more sweeps (a reference for comparisons)");
  cli.integer_option("region-solve-after", 0, "N",
                     "with friction: sweeps of a step after which the places still holding it up are solved "
                     "exactly (regions of at most 300 contacts, by Lemke's method), then again every 500 sweeps over "
                     "wider regions; 0 = never. No effect without friction; refused with --no-cluster-solves",
                     "1000");
  cli.conflicts("region-solve-after", "no-cluster-solves");
  cli.integer_option(
      "threads", 0, "N",
      "OpenMP threads of the solver; every dataset of the trajectory is the same bit for bit for any N, so "
      "--resume may change it (the file's bytes differ by /parameters, which records N)",
      "1");
}

Material material_option(const CommandLine& cli) {
  Material material;
  material.restitution = cli.real("restitution");
  material.tangential_restitution = cli.real("tangential-restitution");
  material.friction = cli.real("friction");
  require_in_range("restitution", material.restitution, 0, 1, false, false);
  require_in_range("tangential-restitution", material.tangential_restitution, -1, 1, false, false);
  require_in_range("friction", material.friction, 0, INFINITY, false, true);
  return material;
}

Activation activation_named(const std::string& name) {
  if (name == "predicted-gap") return Activation::predicted_gap;
  if (name == "overlap") return Activation::overlap;
  throw UsageError("option --activation: must be predicted-gap or overlap, not '" + name + "'");
}

SolverSettings solver_option(const CommandLine& cli) {
  SolverSettings settings;
  settings.tolerance = cli.real("tolerance");
  require_positive("tolerance", settings.tolerance);
  if (cli.given("max-iterations")) {
    const long long sweeps = cli.integer("max-iterations");
    if (sweeps < 1 || sweeps > (1LL << 30)) throw UsageError("option --max-iterations: must be in [1, 2^30]");
    settings.max_iterations = int(sweeps);
  } else {
    settings.max_iterations = cli.real("friction") > 0 ? kMaxIterationsWithFriction : kMaxIterations;
  }
  settings.alert_distance = cli.real("alert-distance");
  settings.activation = activation_named(cli.text("activation"));
  settings.cluster_solves = !cli.flag_set("no-cluster-solves");
  const long long region_after = cli.integer("region-solve-after");
  if (region_after < 0 || region_after > (1LL << 30)) throw UsageError("option --region-solve-after: must be >= 0");
  // Gauss–Seidel alone means the solver before the cluster solves: without region solves,
  // and with every row of the tiles swept.
  settings.region_solve_after = settings.cluster_solves ? int(region_after) : 0;
  settings.skip_settled_rows = settings.cluster_solves;
  require_in_range("alert-distance", settings.alert_distance, 0, INFINITY, false, true);
  const long long threads = cli.integer("threads");
  if (threads < 1 || threads > 256) throw UsageError("option --threads: must be in [1, 256]");
  settings.threads = int(threads);
  return settings;
}

void add_run_options(CommandLine& cli, const std::string& observe_every) {
  cli.integer_option("frame-every", 0, "N", "steps between stored frames; 0 = 100 frames per run", "0");
  cli.integer_option("observe-every", 0, "N", "steps between observable rows", observe_every);
  cli.real_option("checkpoint-every", 0, "SECONDS", "wall time between checkpoints (0: only on a signal)", "600");
  cli.flag("resume", 0, "continue from the checkpoint of an interrupted run of the same command, if any");
}

std::string run_signature(const CommandLine& cli) {
  std::string s;
  for (const auto& [name, value] : cli.values())
    // Options that cannot change the trajectory may differ on --resume.
    if (name != "resume" && name != "checkpoint-every" && name != "threads" && name != "max-unconverged")
      s += name + "=" + value + ";";
  return s;
}

RunPlan run_plan(const CommandLine& cli) {
  const long long observe_every = cli.integer("observe-every");
  if (observe_every < 1) throw UsageError("option --observe-every: must be >= 1");
  long long frame_every = cli.integer("frame-every");
  if (frame_every < 0) throw UsageError("option --frame-every: must be >= 0");
  const double checkpoint_every = cli.real("checkpoint-every");
  require_in_range("checkpoint-every", checkpoint_every, 0, INFINITY, false, true);
  const double max_unconverged = cli.real("max-unconverged");
  require_in_range("max-unconverged", max_unconverged, 0, 1, false, false);
  RunPlan plan;
  plan.max_unconverged = max_unconverged;
  plan.frame_every = frame_every;
  plan.observe_every = observe_every;
  plan.checkpoint_seconds = checkpoint_every;
  plan.checkpoint_path = checkpoint_path(cli.text("output"));
  plan.output_path = cli.text("output");
  plan.signature = run_signature(cli);
  plan.quiet = cli.flag_set("quiet");
  return plan;
}

void set_length(RunPlan& plan, std::int64_t total_steps) {
  if (plan.frame_every == 0) plan.frame_every = std::max<std::int64_t>(1, total_steps / 100);
  plan.total_steps = total_steps;
}

namespace {

// The partial output a checkpoint belongs to, among the output's temporaries not locked
// by a live process (OutputFile has refused the run otherwise): by inode (a resume
// renames it), else by name; "" if none is left.
std::string find_partial(const Checkpoint& checkpoint, const OutputFile& out) {
  namespace fs = std::filesystem;
  if (checkpoint.partial_inode == 0) {
    // A checkpoint of a granflow that named the partial output ".NAME.part".
    const fs::path p(out.final_path());
    const std::string legacy = (p.parent_path() / ("." + p.filename().string() + ".part")).string();
    std::error_code ec;
    return fs::exists(legacy, ec) && fs::file_size(legacy, ec) > 0 ? legacy : "";
  }
  for (const std::string& t : output_temporaries(out.final_path())) {
    struct stat st {};
    if (t != out.temp_path() && ::stat(t.c_str(), &st) == 0 && std::int64_t(st.st_dev) == checkpoint.partial_device &&
        std::int64_t(st.st_ino) == checkpoint.partial_inode)
      return t;
  }
  // Copied elsewhere (another file system, a backup restored): new inode, same name.
  const std::string by_name = (fs::path(out.final_path()).parent_path() / checkpoint.partial).string();
  std::error_code ec;
  return by_name != out.temp_path() && fs::is_regular_file(by_name, ec) ? by_name : "";
}

}  // namespace

std::optional<Checkpoint> resume_point(const CommandLine& cli, const RunPlan& plan, const OutputFile& out,
                                       const std::string& input_path) {
  if (!cli.flag_set("resume")) return std::nullopt;
  if (!std::filesystem::exists(plan.checkpoint_path)) {
    if (!plan.quiet)
      std::fprintf(stderr, "%s: no checkpoint for '%s'; starting from the beginning\n", cli.program().c_str(),
                   out.final_path().c_str());
    return std::nullopt;
  }
  // Everything is checked before anything is changed: a refused resume leaves the
  // checkpoint and its partial output as they were.
  Checkpoint checkpoint = read_checkpoint(plan.checkpoint_path);
  if (checkpoint.signature != plan.signature)
    throw UsageError("checkpoint '" + plan.checkpoint_path + "' was made with other options (" + checkpoint.signature +
                     "); run without --resume to start over");
  checkpoint.partial_path = find_partial(checkpoint, out);
  if (checkpoint.partial_path.empty())
    throw UsageError("checkpoint '" + plan.checkpoint_path + "': its partial output" +
                     (checkpoint.partial.empty() ? std::string() : " '" + checkpoint.partial + "'") +
                     " is missing; run without --resume to start over");
  // Read first, so that any unreadable chunk or index, also one the shape checks below would
  // meet, is reported as damage. Files are written without reuse of file space
  // (io::create_file), so a kill -9 leaves the data the last flush indexed intact; a partial
  // output damaged all the same (a kill inside a flush, power loss, a disk error, a copy cut
  // short) is refused rather than continued into a final file that cannot be read.
  try {
    io::read_every_dataset(io::open_file(checkpoint.partial_path, /*writable=*/false).get());
  } catch (const std::exception& e) {
    throw UsageError("partial output '" + checkpoint.partial_path + "' is damaged (" + e.what() +
                     "), as a process killed while writing can leave it; run without --resume to start over");
  }
  // Its datasets may be longer than at the checkpoint (a process killed after it), never shorter.
  const io::TrajectoryReader partial = [&] {
    try {
      return io::TrajectoryReader::partial_output(checkpoint.partial_path,
                                                  std::size_t(checkpoint.stats.frames_written));
    } catch (const UsageError& e) {
      throw UsageError(std::string(e.what()) + "; run without --resume to start over");
    }
  }();
  const io::Parameters parameters = partial.parameters();
  if (!input_path.empty() && parameters.has("input_sha256")) {
    const std::string then = parameters.get_string("input_sha256"), now = sha256_file(input_path);
    if (now != then)
      throw UsageError("input '" + input_path + "' has changed since the interrupted run (SHA-256 " + now +
                       ", the run started from " + then + "); run without --resume to start over");
  }
  return checkpoint;
}

io::TrajectoryWriter reopen_output(const Checkpoint& checkpoint, const OutputFile& out) {
  return io::TrajectoryWriter::reopen_for_append(out.temp_path(), std::size_t(checkpoint.stats.frames_written),
                                                 checkpoint.step);
}

StartedRun start_or_resume(const CommandLine& cli, const RunPlan& plan, OutputFile& out, const RunStart& start) {
  if (const std::optional<Checkpoint> checkpoint = resume_point(cli, plan, out, start.input_path)) {
    out.adopt(checkpoint->partial_path);
    out.discard_stale();
    try {
      Engine engine(grains_of(checkpoint->frame, checkpoint->grains), checkpoint->frame.box, start.rate, start.material,
                    start.settings, start.dt, start.gravity);
      engine.restore(checkpoint->step, memory_of(checkpoint->frame.contacts));
      if (start.restore) start.restore(io::TrajectoryReader(plan.checkpoint_path));
      io::TrajectoryWriter writer = reopen_output(*checkpoint, out);
      writer.set_time_unit(plan.time_unit);
      return StartedRun{std::move(engine), std::move(writer), checkpoint->stats};
    } catch (...) {
      // The adopted partial stays resumable: the checkpoint finds it by its inode.
      out.keep_partial();
      throw;
    }
  }
  // Starting over: an interrupted run's checkpoint and partial output are discarded.
  std::filesystem::remove(plan.checkpoint_path);
  out.discard_stale();
  Engine engine(start.grains, start.box, start.rate, start.material, start.settings, start.dt, start.gravity);
  engine.restore(0, memory_of(start.contacts));
  io::Parameters parameters = io::provenance(cli);
  // The cap in force, also when it is the default, which depends on the friction.
  parameters.set("max-iterations", std::int64_t(start.settings.max_iterations));
  io::add_input(parameters, start.input_path);
  if (start.add_parameters) start.add_parameters(parameters);
  io::TrajectoryWriter writer(out.temp_path());
  writer.mark_unfinished();
  writer.set_time_unit(plan.time_unit);
  writer.write_parameters(parameters);
  writer.write_grains(properties_of(start.grains), start.box);
  if (start.box.periodic_y) writer.set_lees_edwards_rate(start.rate);
  io::Frame first = frame_of(engine, 0, 0.0);
  first.contacts = start.contacts;
  first.has_contacts = start.contacts.size() > 0;
  writer.append_frame(first);
  RunStats stats;
  stats.frames_written = 1;
  return StartedRun{std::move(engine), std::move(writer), stats};
}

namespace {

// A write failure of a resumable run (a full file system, a quota, an I/O error): the
// partial output is not written again, so it stays as its last flush left it, which the
// last checkpoint describes (a resume cuts what was written after it). Both are kept, or
// without a checkpoint the partial output goes too.
[[noreturn]] void keep_state_after_write_failure(const WriteFailure& e, io::TrajectoryWriter& writer, OutputFile& out,
                                                 const RunPlan& plan) {
  writer.abandon();
  std::string what = std::string(e.what()) + " on " + file_system_of(out.temp_path());
  std::error_code ec;
  if (std::filesystem::exists(plan.checkpoint_path, ec)) {
    out.keep_partial();
    throw WriteFailure(what + "; the checkpoint '" + plan.checkpoint_path + "' and its partial output '" +
                       out.temp_path() + "' are kept: free space there, then run the same command with --resume");
  }
  throw WriteFailure(what +
                     "; no checkpoint had been written yet, so nothing is kept: free space there, then run "
                     "the same command again");
}

}  // namespace

RunStats run_resumable(Engine& engine, io::TrajectoryWriter& writer, OutputFile& out, const RunPlan& plan,
                       RunStats stats, const Observer& observe) {
  try {
    return run_steps(engine, writer, plan, stats, observe);
  } catch (const Interrupted&) {
    out.keep_partial();
    try {
      writer.close_unfinished();
    } catch (const WriteFailure& e) {
      keep_state_after_write_failure(e, writer, out, plan);
    }
    throw;
  } catch (const WriteFailure& e) {
    keep_state_after_write_failure(e, writer, out, plan);
  } catch (...) {
    std::filesystem::remove(plan.checkpoint_path);
    throw;
  }
}

void finish_run(const CommandLine& cli, io::TrajectoryWriter& writer, OutputFile& out, const Engine& engine,
                const RunStats& stats, const RunPlan& plan, const std::function<void(io::TrajectoryWriter&)>& last) {
  try {
    if (last) last(writer);
    write_run_summary(writer, engine, stats);
    writer.close();
  } catch (const WriteFailure& e) {
    keep_state_after_write_failure(e, writer, out, plan);
  }
  out.commit();
  std::filesystem::remove(plan.checkpoint_path);

  const char* program = cli.program().c_str();
  const long long steps = plan.total_steps;
  if (stats.unconverged_steps > 0)
    std::fprintf(stderr,
                 "%s: warning: %lld of %lld steps did not converge (largest residual %.2e, %.2g times the "
                 "tolerance); each kept its last iterate\n",
                 program, (long long)stats.unconverged_steps, steps, stats.max_residual,
                 stats.max_residual / engine.settings().tolerance);
  if (!plan.quiet)
    // The engine's heap per grain (grain state, pair list, solver, records) at the end of the
    // run: the figure docs/performance.md holds against its 1 KB target.
    std::fprintf(stderr, "%s: %lld steps, %.1f s, %.0f steps/s, %.1f sweeps/step, engine %.0f B/grain -> %s\n", program,
                 steps, stats.wall_seconds, double(steps) / std::max(stats.wall_seconds, 1e-9),
                 double(stats.iterations) / double(steps),
                 double(engine.allocated_bytes()) / double(std::max<std::size_t>(engine.state().size(), 1)),
                 out.final_path().c_str());
}

}  // namespace granflow
