#include "stz/d2min_file.hpp"

#include <hdf5.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <optional>
#include <stdexcept>

#include "core/error.hpp"
#include "core/format.hpp"
#include "core/progress.hpp"
#include "core/sha256.hpp"
#include "core/signals.hpp"
#include "io/analysis_writer.hpp"
#include "io/hdf5_handle.hpp"
#include "shear/steady_window.hpp"

namespace granflow::stz {

namespace {

constexpr const char* kProgram = "gf-stz d2min";

std::string quoted(const std::string& path) { return "'" + path + "'"; }

// How an out-of-range index of --frames is named (TrajectoryReader::frame_index).
constexpr const char* kFramesOption = "--frames: frame";

bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

// BRANCH must be a gf-shear run started from frame `a` of TRAJ, with TRAJ's grains.
void check_branch(const io::TrajectoryReader& trajectory, const std::string& trajectory_sha256, std::size_t a,
                  const io::Frame& reference, const io::TrajectoryReader& branch, const io::Frame& branch_start) {
  const std::string& tpath = trajectory.path();
  const std::string& bpath = branch.path();
  const std::string not_branch = quoted(bpath) + " is not a branch of " + quoted(tpath) + " frame " + std::to_string(a);
  const io::Parameters p = branch.parameters();
  if (!p.has("input_sha256")) throw UsageError(not_branch + ": its /parameters name no input_sha256");
  if (p.get_string("input_sha256") != trajectory_sha256)
    throw UsageError(not_branch + ": it started from another file (its input_sha256 is not " + quoted(tpath) +
                     "'s sha256)");
  if (!p.has("frame")) throw UsageError(not_branch + ": its /parameters name no frame");
  const long long k = p.get_int("frame");
  const long long frames = (long long)trajectory.frame_count();
  const long long started = k < 0 ? k + frames : k;
  if (started != (long long)a)
    throw UsageError(not_branch + ": it started from frame " + std::to_string(started) + " (--frame " +
                     std::to_string(k) + ")");
  const io::GrainProperties tg = trajectory.grains(), bg = branch.grains();
  if (tg.radius.size() != bg.radius.size())
    throw UsageError(quoted(bpath) + " has " + std::to_string(bg.radius.size()) + " grains, " + quoted(tpath) + " " +
                     std::to_string(tg.radius.size()) + ": not the same grains");
  for (std::size_t i = 0; i < tg.radius.size(); ++i)
    if (!same_bits(tg.radius[i], bg.radius[i]))
      throw UsageError(quoted(bpath) + ": grain " + std::to_string(i) + " has radius " +
                       format_number(bg.radius[i], 17) + ", in " + quoted(tpath) + " " +
                       format_number(tg.radius[i], 17) + ": not the same grains");
  const Box& rb = reference.box;
  const Box& bb = branch_start.box;
  if (!same_bits(rb.lx, bb.lx) || !same_bits(rb.ly, bb.ly) || !same_bits(rb.offset, bb.offset))
    throw UsageError(not_branch + ": its frame 0 has another box or Lees–Edwards offset");
  for (std::size_t i = 0; i < reference.position.size(); ++i)
    if (!same_bits(reference.position[i].x(), branch_start.position[i].x()) ||
        !same_bits(reference.position[i].y(), branch_start.position[i].y()))
      throw UsageError(not_branch + ": grain " + std::to_string(i) + " is elsewhere in its frame 0");
}

// The box as D²min reads it: an offset stored as exactly L_x is the offset 0 (the same
// images). A wrap computed as "a hair below 0, plus L_x" rounds to L_x; Box::shift_offset
// stores 0 there, but a file from another writer may hold it.
Box normalised(Box box) {
  if (box.periodic_y && box.offset == box.lx) box.offset = 0;
  return box;
}

StoredFrame stored(const io::Frame& frame) { return StoredFrame{frame.position, normalised(frame.box), frame.time}; }

}  // namespace

D2minResult d2min_between_frames(const D2minRequest& request) {
  if (!(std::isfinite(request.cutoff_diameters) && request.cutoff_diameters > 0))
    throw UsageError("option --cutoff: must be > 0 mean diameters, got " + format_number(request.cutoff_diameters));
  const shear_run::Opened traj = shear_run::open(request.trajectory, kProgram);
  const io::TrajectoryReader& reader = traj.reader;
  const std::string& tpath = request.trajectory;
  const std::size_t a = reader.frame_index(request.reference_frame, kFramesOption);
  D2minResult out;
  out.trajectory_sha256 = sha256_file(tpath);

  std::optional<shear_run::Opened> branch;
  std::size_t b = 0;
  if (!request.branch.empty()) {
    branch.emplace(shear_run::open(request.branch, kProgram));
    b = branch->reader.frame_index(request.current_frame, kFramesOption);
  } else {
    b = reader.frame_index(request.current_frame, kFramesOption);
  }

  const io::Frame reference = reader.frame(a);
  const std::size_t n = reference.position.size();
  out.radius = reader.grains().radius;
  out.reference_position = reference.position;
  out.reference_box = normalised(reference.box);
  out.reference_frame = std::int64_t(a);
  out.current_frame = std::int64_t(b);
  out.reference_time = reference.time;
  out.cutoff_diameters = request.cutoff_diameters;
  double sum = 0;
  for (double r : out.radius) sum += r;
  out.mean_diameter = n ? 2 * sum / double(n) : 0;
  out.cutoff = request.cutoff_diameters * out.mean_diameter;

  // Every frame from the first to the last of the interval, in time order, one at a time.
  const io::TrajectoryReader& source = branch ? branch->reader : reader;
  const std::string& spath = branch ? request.branch : tpath;
  const std::size_t first = branch ? 0 : std::min(a, b), last = branch ? b : std::max(a, b);
  const double rate = branch ? branch->rate : traj.rate;
  auto name = [&](std::size_t k) { return quoted(spath) + " frame " + std::to_string(k); };
  Progress bar("gf-stz d2min", double(last - first + 1), request.quiet);
  io::Frame frame = branch ? source.frame(0) : (first == a ? reference : reader.frame(first));
  if (branch) check_branch(reader, out.trajectory_sha256, a, reference, source, frame);
  const double first_time = frame.time;
  try {
    Unwrapper unwrapper(stored(frame), rate, name(first));
    bar.update(1);
    for (std::size_t k = first + 1; k <= last; ++k) {
      check_interrupt();
      frame = source.frame(k);
      unwrapper.add(stored(frame), name(k));
      bar.update(double(k - first + 1));
    }
    bar.finish();
    Unwrapped u = unwrapper.result();
    out.current_time = frame.time;
    if (!branch && b < a) {
      // Unwrapped from B forwards to A: the map from A back to B is the opposite motion.
      for (Vec2& d : u.displacement) d = -d;
      u.offset_change = -u.offset_change;
      out.current_time = first_time;
    }
    out.offset_change = u.offset_change;
    out.strain = u.offset_change / out.reference_box.ly;

    ReferenceBonds bonds;
    try {
      bonds = reference_bonds(reference.position, out.reference_box, out.cutoff);
    } catch (const std::invalid_argument& e) {
      if (!(out.cutoff < 0.5 * std::min(reference.box.lx, reference.box.ly)))
        throw UsageError("option --cutoff: " + format_number(request.cutoff_diameters) + " mean diameters (" +
                         format_number(out.cutoff) + ") is not below half the smaller box side (" +
                         format_number(0.5 * std::min(reference.box.lx, reference.box.ly)) + ") of " + quoted(tpath));
      throw UsageError(quoted(tpath) + " frame " + std::to_string(a) + ": " + e.what());
    }
    out.d2min = compute_d2min(bonds, u.displacement, u.offset_change);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  out.current_source = branch ? "branch" : "trajectory";
  out.valid_count = std::count(out.d2min.valid.begin(), out.d2min.valid.end(), std::uint8_t(1));
  return out;
}

void write_d2min(const std::string& path, const D2minResult& r, const io::Parameters& provenance) {
  const std::size_t n = r.reference_position.size();
  {
    io::AnalysisWriter w(path);
    w.write_parameters(provenance);
    io::Parameters d;
    d.set("cutoff", r.cutoff);
    d.set("cutoff_diameters", r.cutoff_diameters);
    d.set("mean_diameter", r.mean_diameter);
    d.set("reference_frame", r.reference_frame);
    d.set("current_frame", r.current_frame);
    d.set("current_source", r.current_source);
    d.set("reference_time", r.reference_time);
    d.set("current_time", r.current_time);
    d.set("strain", r.strain);
    d.set("offset_change", r.offset_change);
    d.set("valid_count", r.valid_count);
    w.write_attributes("/d2min", d);
    const std::string per_grain = " (NaN where valid is 0)";
    w.write("/d2min/value", {n}, r.d2min.value,
            "D2min = sum over the reference neighbours n of |d_n - F d0_n|^2 (Falk-Langer, eq. 6.32)" + per_grain,
            "length^2");
    w.write("/d2min/per_neighbour", {n}, r.d2min.per_neighbour, "D2min / neighbours" + per_grain, "length^2");
    w.write("/d2min/valid", {n}, r.d2min.valid,
            "1: D2min computed; 0: fewer than 2 neighbours or their bonds (nearly) collinear (Y singular): value, "
            "per_neighbour and F are NaN",
            "1");
    w.write("/d2min/neighbours", {n}, r.d2min.neighbours,
            "neighbours in the reference frame: centre distance < cutoff (Lees-Edwards minimum image)", "1");
    std::vector<double> f(4 * n);
    for (std::size_t i = 0; i < n; ++i)
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b) f[4 * i + std::size_t(2 * a + b)] = r.d2min.F[i](a, b);
    w.write("/d2min/F", {n, 2, 2}, f, "best local affine map F = X Y^-1, F[i][a][b] row a column b" + per_grain, "1");
    std::vector<double> position(2 * n);
    for (std::size_t i = 0; i < n; ++i) {
      position[2 * i] = r.reference_position[i].x();
      position[2 * i + 1] = r.reference_position[i].y();
    }
    w.write("/reference/position", {n, 2}, position, "grain centres in the reference frame, wrapped as stored",
            "length");
    w.write("/reference/radius", {n}, r.radius, "grain radii", "length");
    io::Parameters ref;
    ref.set("offset", r.reference_box.offset);
    w.write_attributes("/reference", ref);
    w.close();
  }
  // The analysis writer has no array attribute of doubles: the box is written here, on the
  // file it closed.
  io::File file = io::open_file(path, true);
  io::Group reference = io::open_group(file.get(), "/reference");
  const hsize_t two = 2;
  const double box[2] = {r.reference_box.lx, r.reference_box.ly};
  io::Dataspace space(io::check(H5Screate_simple(1, &two, nullptr), reference.get(), "create dataspace for box"));
  io::Attribute attribute(
      io::check(H5Acreate2(reference.get(), "box", H5T_IEEE_F64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT),
                reference.get(), "create attribute box"));
  io::check(H5Awrite(attribute.get(), H5T_NATIVE_DOUBLE, box), reference.get(), "write attribute box");
  attribute.reset();
  space.reset();
  reference.reset();
  io::close_file(file, path);
}

}  // namespace granflow::stz
