#pragma once
// Checkpoints of a running simulation: one stored frame (the complete dynamical state,
// see run/frames.hpp) plus the bookkeeping needed to continue the partial trajectory
// exactly where it stood. Written to a temporary name and renamed, so a checkpoint
// on disk is always complete.
#include <cstdint>
#include <functional>
#include <string>

#include "dynamics/engine.hpp"
#include "io/trajectory.hpp"

namespace granflow {

struct RunStats {
  std::int64_t frames_written = 0;  // frames in the partial trajectory
  std::int64_t unconverged_steps = 0;
  std::int64_t iterations = 0;       // Gauss–Seidel sweeps, summed over steps
  std::int64_t contact_updates = 0;  // local contact solves, summed over steps
  double max_residual = 0;           // largest final residual of any step (a length)
  double wall_seconds = 0;           // of all invocations of the run (resumes)
};

struct Checkpoint {
  std::int64_t step = 0;
  RunStats stats;
  std::string signature;  // the options that define the run; must match to resume
  io::Frame frame;
  io::GrainProperties grains;
};

// "<dir>/.<name>.checkpoint" beside an output path.
std::string checkpoint_path(const std::string& output);

// Adds a caller's own state to a checkpoint file (read back with a TrajectoryReader).
using CheckpointExtra = std::function<void(io::TrajectoryWriter&)>;

void write_checkpoint(const std::string& path, const Engine& engine, const RunStats& stats,
                      const std::string& signature, const CheckpointExtra& extra = {});
// UsageError naming the file if it is not a checkpoint.
Checkpoint read_checkpoint(const std::string& path);

}  // namespace granflow
