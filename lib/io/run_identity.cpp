#include "io/run_identity.hpp"

#include <limits>

#include "core/sha256.hpp"

namespace granflow::io {

RunIdentity read_run_identity(const TrajectoryReader& reader, const Parameters& p, const std::string& path, bool hash) {
  RunIdentity run;
  run.path = path;
  if (hash) run.sha256 = sha256_file(path);
  run.packing_fraction = p.get_double("packing_fraction");
  run.restitution = p.get_double("restitution");
  run.friction = p.get_double("friction");
  run.tangential_restitution = p.has("tangential-restitution") ? p.get_double("tangential-restitution")
                                                               : std::numeric_limits<double>::quiet_NaN();
  run.dt = p.get_double("dt");
  run.rate = reader.lees_edwards_rate();
  run.grains = reader.grain_count();
  run.box = reader.box(0);
  return run;
}

RunIdentity read_run_identity(const TrajectoryReader& reader, const std::string& path, bool hash) {
  return read_run_identity(reader, reader.parameters(), path, hash);
}

}  // namespace granflow::io
