#pragma once
// Packings on disk: a one-frame H5MD trajectory (docs/file-format.md, Trajectory files) whose grains are at rest,
// with the packing's own results as one-row observables at step 0:
// packing_fraction, max_overlap (absolute length), minimiser_iterations (no wall time: the
// same command must write the same bytes; gf-pack reports its time on stderr).
#include <string>

#include "io/trajectory.hpp"
#include "packing/packing.hpp"

namespace granflow {

void write_packing(const std::string& path, const Packing& packing, const io::Parameters& parameters);

// Reads frame `frame` (negative: from the end) of a packing or trajectory back as a
// Packing (positions, radii, fixed flags, box); UsageError naming the file on any problem.
Packing read_packing(const std::string& path, long long frame = 0);

}  // namespace granflow
