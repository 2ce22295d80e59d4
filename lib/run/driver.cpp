#include "run/driver.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "core/error.hpp"
#include "core/progress.hpp"
#include "core/signals.hpp"
#include "run/frames.hpp"

namespace granflow {
namespace {
using Clock = std::chrono::steady_clock;

void record_solver(const Engine& engine, io::TrajectoryWriter& writer, RunStats& stats) {
  const StepReport& r = engine.last_report();
  const std::int64_t step = engine.step_count();
  const double time = engine.time();
  writer.append_observable("contacts", step, time, double(r.contacts));
  writer.append_observable("solver_iterations", step, time, double(r.iterations));
  writer.append_observable("solver_residual", step, time, r.residual);
  writer.append_observable("max_overlap", step, time, r.max_overlap);
  writer.append_observable("unconverged_steps", step, time, double(stats.row_unconverged_steps));
  writer.append_observable("unconverged_residual", step, time, stats.row_unconverged_residual);
  stats.row_unconverged_steps = 0;
  stats.row_unconverged_residual = 0;
}
}  // namespace

RunStats run_steps(Engine& engine, io::TrajectoryWriter& writer, const RunPlan& plan, RunStats stats,
                   const Observer& observe) {
  const std::int64_t first = engine.step_count();
  Progress bar(plan.strain_per_step != 0 ? "shear" : "run", double(plan.total_steps - first), plan.quiet);
  const auto start = Clock::now();
  const double wall_before = stats.wall_seconds;
  auto last_checkpoint = start;
  auto save = [&] {
    stats.wall_seconds = wall_before + std::chrono::duration<double>(Clock::now() - start).count();
    writer.flush();
    write_checkpoint(plan.checkpoint_path, engine, stats, plan.signature, plan.checkpoint_extra, plan.output_path);
  };
  char status[128];
  const double unconverged_limit = plan.max_unconverged * double(plan.total_steps);
  while (engine.step_count() < plan.total_steps) {
    const StepReport& r = engine.step();
    stats.iterations += r.iterations;
    stats.contact_updates += r.contact_updates;
    stats.max_residual = std::max(stats.max_residual, r.residual);
    if (!r.converged) {
      ++stats.unconverged_steps;
      ++stats.row_unconverged_steps;
      stats.row_unconverged_residual = std::max(stats.row_unconverged_residual, r.residual);
    }
    stats.region_solves += r.region_solves;
    const std::int64_t n = engine.step_count();
    // Checked after every step, not only after unconverged ones: a resume with a lower
    // limit stops at its first step when the count so far already exceeds it.
    if (double(stats.unconverged_steps) > unconverged_limit) {
      char what[256];
      std::snprintf(what, sizeof what,
                    "%lld of %lld steps did not converge by step %lld (largest residual %.2e), more than "
                    "--max-unconverged %g allows; raise --max-iterations or --max-unconverged",
                    (long long)stats.unconverged_steps, (long long)plan.total_steps, (long long)n, stats.max_residual,
                    plan.max_unconverged);
      throw RuntimeFailure(what);
    }
    if (plan.after_step) plan.after_step(engine);
    if (n % plan.observe_every == 0) {
      record_solver(engine, writer, stats);
      observe(engine, writer);
    }
    if (n % plan.frame_every == 0 || n == plan.total_steps) {
      writer.append_frame(frame_of(engine, n, engine.time()));
      ++stats.frames_written;
    }
    const auto now = Clock::now();
    if (bar.active()) {
      const double elapsed = std::chrono::duration<double>(now - start).count();
      const double rate = elapsed > 0 ? double(n - first) / elapsed : 0.0;
      if (plan.strain_per_step != 0)
        std::snprintf(status, sizeof status, "strain %.3f, %.0f steps/s, %d sweeps", double(n) * plan.strain_per_step,
                      rate, r.iterations);
      else
        std::snprintf(status, sizeof status, "t = %.4g, %.0f steps/s, %d sweeps", writer.file_time(engine.time()), rate,
                      r.iterations);
      bar.update(double(n - first), status);
    }
    if (interrupt_requested()) {
      save();
      throw Interrupted("interrupted at step " + std::to_string(n) + " of " + std::to_string(plan.total_steps) +
                        "; checkpoint written: run the same command with --resume to continue");
    }
    if (plan.checkpoint_seconds > 0 &&
        std::chrono::duration<double>(now - last_checkpoint).count() >= plan.checkpoint_seconds) {
      save();
      last_checkpoint = Clock::now();
    }
  }
  bar.finish();
  stats.wall_seconds = wall_before + std::chrono::duration<double>(Clock::now() - start).count();
  return stats;
}

void write_run_summary(io::TrajectoryWriter& writer, const Engine& engine, const RunStats& stats) {
  io::Parameters s;
  const std::int64_t steps = engine.step_count();
  s.set("steps", steps);
  s.set("frames", stats.frames_written);
  s.set("mean_iterations", steps > 0 ? double(stats.iterations) / double(steps) : 0.0);
  s.set("unconverged_steps", stats.unconverged_steps);
  s.set("region_solves", stats.region_solves);
  s.set("max_residual", stats.max_residual);
  writer.write_attributes("/run", s);
}

}  // namespace granflow
