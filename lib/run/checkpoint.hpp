#pragma once
// Checkpoints of a running simulation: one stored frame (the complete dynamical state,
// see run/frames.hpp) plus the bookkeeping needed to continue the partial trajectory
// exactly where it stood. Written to a temporary name and renamed, so a checkpoint
// on disk is always complete.
#include <cstdint>
#include <functional>
#include <string>

#include "core/output_file.hpp"
#include "dynamics/engine.hpp"
#include "io/trajectory.hpp"

namespace granflow {

struct RunStats {
  std::int64_t frames_written = 0;  // frames in the partial trajectory
  std::int64_t unconverged_steps = 0;
  std::int64_t region_solves = 0;    // exact solves of stalled regions, summed over steps
  std::int64_t iterations = 0;       // Gauss–Seidel sweeps, summed over steps
  std::int64_t contact_updates = 0;  // local contact solves, summed over steps
  double max_residual = 0;           // largest final residual of any step (a length)
  // Steps at the sweep cap since the last observable row, and the largest final residual
  // among them (0 if none): the row's unconverged_steps and unconverged_residual.
  std::int64_t row_unconverged_steps = 0;
  double row_unconverged_residual = 0;
  double wall_seconds = 0;  // of all invocations of the run (resumes)
};

struct Checkpoint {
  std::int64_t step = 0;
  RunStats stats;
  std::string signature;  // the options that define the run; must match to resume
  // The partial output the checkpoint belongs to: the temporary of the process that
  // wrote it, by name and by device and inode (which a rename keeps, so a resume that
  // adopted it under its own name and was killed before its next checkpoint still
  // finds it). Empty and 0 when no such temporary existed (tests, older checkpoints).
  std::string partial;
  std::int64_t partial_device = 0, partial_inode = 0;
  std::string partial_path;  // where resume_point found it
  io::Frame frame;
  io::GrainProperties grains;
};

// checkpoint_path(output): "<dir>/.<name>.checkpoint" beside an output path (see
// core/output_file.hpp).

// Adds a caller's own state to a checkpoint file (read back with a TrajectoryReader).
using CheckpointExtra = std::function<void(io::TrajectoryWriter&)>;

// Writes `path` (as path + ".new", renamed when complete; on failure the ".new" file is
// removed and the previous checkpoint left as it was). Records this process's temporary of
// `output` (own_temporary), if given, as the partial output it belongs to.
void write_checkpoint(const std::string& path, const Engine& engine, const RunStats& stats,
                      const std::string& signature, const CheckpointExtra& extra = {}, const std::string& output = "");
// UsageError naming the file if it is not a checkpoint.
Checkpoint read_checkpoint(const std::string& path);

}  // namespace granflow
