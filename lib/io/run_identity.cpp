#include "io/run_identity.hpp"

#include "core/sha256.hpp"

namespace granflow::io {

RunIdentity read_run_identity(const TrajectoryReader& reader, const Parameters& p, const std::string& path,
                              IdentityNeeds needs) {
  RunIdentity run;
  run.path = path;
  if (needs.hash) run.sha256 = sha256_file(path);
  run.packing_fraction = p.get_double("packing_fraction");
  run.restitution = p.get_double("restitution");
  run.friction = p.get_double("friction");
  if (p.has("tangential-restitution")) run.tangential_restitution = p.get_double("tangential-restitution");
  if (needs.dt) run.dt = p.get_double("dt");
  run.rate = reader.lees_edwards_rate();
  run.grains = reader.grain_count();
  run.box = reader.box(0);
  return run;
}

}  // namespace granflow::io
