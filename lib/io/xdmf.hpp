#pragma once
// An XDMF 2 description of a trajectory (docs/programs/gf-xdmf.md): XML that points into
// the trajectory's HDF5 datasets, so that ParaView shows the grains, the contacts and the
// box of every stored frame without a copy of the data.
//
// Why XDMF 2 and not 3: ParaView 5.11's "Xdmf Reader" (the XDMF 2 library) evaluates
// Function items with index selection ($0[$1]) and interlacing (","), which draw each
// contact from r_i to r_i - branch (the segment the minimum image spans, also across the
// periodic and Lees–Edwards boundaries) from the stored columns alone.
#include <cstddef>
#include <string>

#include "io/trajectory.hpp"

namespace granflow::io {

struct XdmfSummary {
  std::size_t frames = 0, grains = 0, contacts = 0;  // contacts over all frames
};

// The XDMF text for the trajectory `reader` reads; `h5_name` is how the text names the
// trajectory file (a path relative to the XDMF file's directory, as ParaView resolves it).
// Reads the frame offsets, the box of each frame and, for frames with a single contact,
// that contact's pair; UsageError naming the file for a bad trajectory.
std::string xdmf_description(const TrajectoryReader& reader, const std::string& h5_name,
                             XdmfSummary* summary = nullptr);

}  // namespace granflow::io
