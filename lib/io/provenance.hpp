#pragma once
// Provenance for /parameters (docs/file-format.md, Parameters and provenance): every option value, the exact command
// line, the program and its version, and the identity of each input file, so that any output can be traced back to the
// run and the code that made it.
#include <string>

#include "core/cli.hpp"
#include "io/trajectory.hpp"

namespace granflow::io {

// Every option of cli that applies to the run (given or defaulted; CommandLine::values())
// as an attribute of its declared kind — integers and flags (0/1) as int64, reals as double
// whatever was typed, text as strings — plus command_line, program, version.
Parameters provenance(const CommandLine& cli);

// Records an input file: input (path) and input_sha256; the k-th extra input of a
// multi-input program goes to input_<k> and input_<k>_sha256. Inputs of another role
// take another key (e.g. "reference": reference, reference_1, ...).
void add_input(Parameters& parameters, const std::string& path, int index = 0, const std::string& key = "input");
// The same with the SHA-256 already computed (a large input read for a check is hashed once).
void add_hashed_input(Parameters& parameters, const std::string& path, const std::string& sha256, int index = 0,
                      const std::string& key = "input");

// Records which stored frame of the input a run starts from (a branch from another run's
// trajectory): input_frame (index), input_step, input_time, and the parent run's own
// program, angle, friction, restitution, tangential-restitution, rate, input and
// input_sha256 when its /parameters has them, as parent_<name> with <name> the parent's
// own attribute name — so a branched run names
// its parent's physics (and the grandparent file) without opening the parent.
void add_input_frame(Parameters& parameters, const TrajectoryReader& input, std::size_t index, std::int64_t step,
                     double time);

}  // namespace granflow::io
