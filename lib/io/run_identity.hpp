#pragma once
// A run's identity and parameters as the per-run analysis tables (gf-correlate, gf-kinetic,
// gf-network, gf-stz fit) record them beside their results: ν, e, μ, e_t, γ̇, dt, N and the
// box, read from a gf-shear trajectory's /parameters, /lees_edwards and first frame, and on
// request the SHA-256 of the file. One reader, so that every table names a run alike.
#include <cstddef>
#include <limits>
#include <string>

#include "geometry/box.hpp"
#include "io/trajectory.hpp"

namespace granflow::io {

struct RunIdentity {
  std::string path;    // as given
  std::string sha256;  // empty unless asked for
  std::size_t grains = 0;
  // /parameters: packing_fraction, restitution, friction, dt (each required: UsageError naming
  // the file if absent); tangential-restitution (NaN if absent).
  double packing_fraction = 0, restitution = 0, friction = 0, dt = 0;
  double tangential_restitution = std::numeric_limits<double>::quiet_NaN();
  double rate = 0;  // /lees_edwards rate (0 without)
  Box box{};        // of the first stored frame
};

// Reads the identity of an opened trajectory (reader.parameters() once); hash: also the
// file's SHA-256.
RunIdentity read_run_identity(const TrajectoryReader& reader, const std::string& path, bool hash = false);
RunIdentity read_run_identity(const TrajectoryReader& reader, const Parameters& parameters, const std::string& path,
                              bool hash = false);

}  // namespace granflow::io
