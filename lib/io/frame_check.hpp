#pragma once
// The values a stored frame may hold (docs/file-format.md, Reading errors): what every
// program checks when it reads grains, and what the writer refuses to write, so that no
// program ever reads or writes a state the engine could not have produced.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "io/trajectory.hpp"

namespace granflow::io {

// Each returns "" if every value is acceptable, else one phrase naming the dataset, the
// frame, the grain or contact and the value, e.g. "/particles/grains/radius: grain 3 is
// -0.5, must be finite and > 0".
//   radius and mass: finite and > 0.
std::string grains_problem(const GrainProperties& grains);
//   box edges: width and height finite and > 0, Lees–Edwards offset finite.
std::string box_problem(const Box& box, std::size_t frame);
//   positions, velocities, orientations, angular velocities: finite; contacts: both grains
//   of a pair among the `grains` grains, forces, branch vectors and velocities finite,
//   normal and binary forces >= 0. (What a restart needs beyond values, pairs i < j in
//   increasing order and ages >= 1, is checked where a run starts: packing/start_check.hpp.)
// first_row: the row of /contacts holding the frame's first contact (named in the phrase).
std::string frame_problem(const Frame& frame, std::size_t frame_index, std::size_t grains, std::int64_t first_row);
//   observables: every value (and time) finite. `values` holds dataset
//   /observables/<name>/<column> row after row, `per_row` numbers a row (1 for a scalar, 4
//   for a 2x2 tensor, row-major); the phrase names the row (and the tensor's element).
std::string observable_problem(const std::string& name, const std::string& column, const std::vector<double>& values,
                               std::size_t per_row = 1);

}  // namespace granflow::io
