#pragma once
// The time loop shared by gf-shear and gf-incline: steps the engine, records the
// solver's statistics and the geometry's observables, stores frames, writes
// checkpoints periodically and on SIGINT/SIGTERM, and shows progress. The physics of
// what is observed stays with the caller (an Observer).
#include <functional>
#include <string>

#include "dynamics/engine.hpp"
#include "io/trajectory.hpp"
#include "run/checkpoint.hpp"

namespace granflow {

struct RunPlan {
  std::int64_t total_steps = 0;     // stop when the engine's step count reaches this
  std::int64_t frame_every = 0;     // store a frame every this many steps (and at the end)
  std::int64_t observe_every = 1;   // record observables every this many steps
  double checkpoint_seconds = 600;  // wall time between checkpoints; 0: only on a signal
  std::string checkpoint_path;      // where checkpoints go
  std::string output_path;          // the output whose partial the checkpoints belong to
  std::string signature;            // stored in checkpoints (what a resume must match)
  // Largest share of total_steps that may end unconverged (at the sweep cap): one more
  // and the run stops (RuntimeFailure), since it could no longer end within the limit.
  double max_unconverged = 1;
  double strain_per_step = 0;  // for the progress line (γ̇·dt); 0 shows time instead
  bool quiet = false;
  // The unit of the output's times (io::TrajectoryWriter::set_time_unit), on a new
  // output and on a resumed one (start_or_resume), and of the progress line.
  io::TimeUnit time_unit;
  // Called after every step, before anything is recorded (gf-incline: checks that no
  // grain left the layer, samples the profiles); throws to abort the run. Optional.
  std::function<void(const Engine&)> after_step;
  // Writes the caller's own state (e.g. accumulated profiles) into every checkpoint,
  // so that a resumed run continues it exactly. Optional.
  CheckpointExtra checkpoint_extra;
};

// Records the geometry's observables of the engine's current step.
using Observer = std::function<void(const Engine&, io::TrajectoryWriter&)>;

// Runs until plan.total_steps. Throws Interrupted (with a message saying how to
// resume) after writing a checkpoint when a signal arrives, and RuntimeFailure as soon as
// more than plan.max_unconverged × plan.total_steps steps (of all sessions of a resumed
// run) did not converge. Returns the updated stats.
RunStats run_steps(Engine& engine, io::TrajectoryWriter& writer, const RunPlan& plan, RunStats stats,
                   const Observer& observe);

// The run's statistics as the /run group of a trajectory (steps, frames, mean iterations,
// unconverged steps, largest residual): the summary a user checks first. Only what the
// run computed, nothing of the invocation (no wall time or speed: those go to stderr),
// so that the same command writes the same bytes.
void write_run_summary(io::TrajectoryWriter& writer, const Engine& engine, const RunStats& stats);

}  // namespace granflow
