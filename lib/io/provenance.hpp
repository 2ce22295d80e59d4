#pragma once
// Provenance for /parameters (docs/file-format.md, Parameters and provenance): every option value, the exact command
// line, the program and its version, and the identity of each input file, so that any output can be traced back to the
// run and the code that made it.
#include <string>

#include "core/cli.hpp"
#include "io/trajectory.hpp"

namespace granflow::io {

// Every option of cli (given or defaulted) as an attribute — whole numbers as int64,
// other numbers as double, the rest as strings — plus command_line, program, version.
Parameters provenance(const CommandLine& cli);

// Records an input file: input (path) and input_sha256; the k-th extra input of a
// multi-input program goes to input_<k> and input_<k>_sha256. Inputs of another role
// take another key (e.g. "reference": reference, reference_1, ...).
void add_input(Parameters& parameters, const std::string& path, int index = 0, const std::string& key = "input");

// Records which stored frame of the input a run starts from (a branch from another run's
// trajectory): input_frame (index), input_step, input_time, and the parent run's own
// program, angle, friction, restitution, tangential_restitution, rate, input and
// input_sha256 when its /parameters has them, as parent_<name> — so a branched run names
// its parent's physics (and the grandparent file) without opening the parent.
void add_input_frame(Parameters& parameters, const TrajectoryReader& input, std::size_t index, std::int64_t step,
                     double time);

}  // namespace granflow::io
