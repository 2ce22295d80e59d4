#pragma once
// gf-stz d2min over files: D²min (stz/d2min.hpp) of every grain between two stored frames of
// a gf-shear trajectory, or between a frame of it and a frame of a branch started from that
// frame, and its output file (docs/file-format.md, "gf-stz d2min output"). Every refusal is a
// UsageError of one line naming the file or the option at fault.
#include <cstdint>
#include <string>
#include <vector>

#include "core/vec.hpp"
#include "geometry/box.hpp"
#include "io/trajectory.hpp"
#include "stz/d2min.hpp"

namespace granflow::stz {

struct D2minRequest {
  std::string trajectory;         // TRAJ
  std::string branch;             // BRANCH, or empty: both frames are TRAJ's
  long long reference_frame = 0;  // A, a frame of TRAJ; negative counts from the end
  long long current_frame = -1;   // B, a frame of TRAJ (or of BRANCH); the same
  double cutoff_diameters = 2;    // neighbours closer than this many mean diameters
  bool quiet = false;             // no progress bar
};

struct D2minResult {
  D2min d2min;
  std::vector<Vec2> reference_position;  // wrapped, as stored
  std::vector<double> radius;
  Box reference_box;
  double cutoff = 0, cutoff_diameters = 0, mean_diameter = 0;
  std::int64_t reference_frame = 0, current_frame = 0;  // resolved indices in TRAJ (and BRANCH)
  std::string current_source;                           // "trajectory" or "branch"
  double reference_time = 0, current_time = 0;
  double offset_change = 0, strain = 0;  // Δδ (accumulated, signed) and Δδ/L_y
  std::int64_t valid_count = 0;
  std::string trajectory_sha256;  // of TRAJ, hashed once (the branch check and the provenance)
};

// Reads the frames (one at a time: memory O(N) whatever the number of frames between them),
// unwraps the displacements over every stored frame between A and B (B before A: the map
// goes backwards in time) or over BRANCH's frames 0..B, and computes D²min. Refuses
// (UsageError): files that are not gf-shear trajectories, frames out of range, a BRANCH
// that is not a gf-shear run started from frame A of TRAJ (its input_sha256, its frame, its
// frame 0 against TRAJ's frame A bit for bit), other grains, a cutoff that is not positive
// or not below half the box.
D2minResult d2min_between_frames(const D2minRequest& request);

// Writes the output (created or truncated) with `provenance` in /parameters.
void write_d2min(const std::string& path, const D2minResult& result, const io::Parameters& provenance);

}  // namespace granflow::stz
