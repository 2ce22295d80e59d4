#include "run/checkpoint.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <cstdio>
#include <filesystem>

#include "core/error.hpp"
#include "run/frames.hpp"

namespace granflow {

void write_checkpoint(const std::string& path, const Engine& engine, const RunStats& stats,
                      const std::string& signature, const CheckpointExtra& extra, const std::string& output) {
  const std::string temp = path + ".new";
  try {
    io::TrajectoryWriter writer(temp);
    io::Parameters info;
    info.set("step", engine.step_count());
    info.set("frames_written", stats.frames_written);
    info.set("unconverged_steps", stats.unconverged_steps);
    info.set("region_solves", stats.region_solves);
    info.set("iterations", stats.iterations);
    info.set("contact_updates", stats.contact_updates);
    info.set("max_residual", stats.max_residual);
    info.set("row_unconverged_steps", stats.row_unconverged_steps);
    info.set("row_unconverged_residual", stats.row_unconverged_residual);
    info.set("wall_seconds", stats.wall_seconds);
    info.set("signature", signature);
    const std::string partial = output.empty() ? "" : own_temporary(output);
    struct stat st {};
    if (!partial.empty() && ::stat(partial.c_str(), &st) == 0) {
      info.set("partial", std::filesystem::path(partial).filename().string());
      info.set("partial_device", std::int64_t(st.st_dev));
      info.set("partial_inode", std::int64_t(st.st_ino));
    }
    writer.write_attributes("/checkpoint", info);
    writer.write_grains(properties_of(engine.state()), engine.box());
    if (engine.box().periodic_y) writer.set_lees_edwards_rate(engine.rate());
    writer.append_frame(frame_of(engine, engine.step_count(), engine.time()));
    if (extra) extra(writer);
    writer.close();
  } catch (...) {
    // The checkpoint before this one stays whole.
    ::unlink(temp.c_str());
    throw;
  }
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    const int error = errno;
    ::unlink(temp.c_str());
    throw WriteFailure("cannot write checkpoint '" + path + "': " + std::strerror(error));
  }
}

Checkpoint read_checkpoint(const std::string& path) {
  io::TrajectoryReader reader(path);
  io::Parameters info = reader.attributes("/checkpoint");
  if (!info.has("signature") || reader.frame_count() != 1)
    throw UsageError("'" + path + "' is not a granflow checkpoint");
  Checkpoint c;
  c.step = info.get_int("step");
  c.stats.frames_written = info.get_int("frames_written");
  c.stats.unconverged_steps = info.get_int("unconverged_steps");
  if (info.has("region_solves")) c.stats.region_solves = info.get_int("region_solves");
  c.stats.iterations = info.get_int("iterations");
  c.stats.contact_updates = info.get_int("contact_updates");
  c.stats.max_residual = info.get_double("max_residual");
  if (!info.has("row_unconverged_steps") || !info.has("row_unconverged_residual"))
    throw UsageError("checkpoint '" + path +
                     "' holds no count of unconverged steps since the last observable row: it was written by an "
                     "older version; run without --resume to start over");
  c.stats.row_unconverged_steps = info.get_int("row_unconverged_steps");
  c.stats.row_unconverged_residual = info.get_double("row_unconverged_residual");
  c.stats.wall_seconds = info.get_double("wall_seconds");
  c.signature = info.get_string("signature");
  if (info.has("partial_inode")) {
    c.partial = info.get_string("partial");
    c.partial_device = info.get_int("partial_device");
    c.partial_inode = info.get_int("partial_inode");
  }
  c.frame = reader.frame(0);
  c.grains = reader.grains();
  return c;
}

}  // namespace granflow
