#include "packing/packing_io.hpp"

#include <cmath>

#include "core/error.hpp"
#include "io/frame_check.hpp"
#include "packing/start_check.hpp"

namespace granflow {

void write_packing(const std::string& path, const Packing& packing, const io::Parameters& parameters) {
  const std::size_t n = packing.radius.size();
  io::GrainProperties grains;
  grains.radius = packing.radius;
  grains.mass.resize(n);
  for (std::size_t i = 0; i < n; ++i) grains.mass[i] = M_PI * packing.radius[i] * packing.radius[i];
  grains.fixed = packing.fixed.empty() ? std::vector<std::uint8_t>(n, 0) : packing.fixed;

  io::Frame frame;
  frame.box = packing.box;
  frame.position = packing.position;
  frame.velocity.assign(n, Vec2::Zero());
  frame.orientation.assign(n, 0.0);
  frame.angular_velocity.assign(n, 0.0);

  // Checked before the file is created: a packing with a non-finite number is never written.
  std::string problem = io::grains_problem(grains);
  if (problem.empty()) problem = io::frame_problem(frame, 0, n, 0);
  if (problem.empty() && !(std::isfinite(packing.packing_fraction) && std::isfinite(packing.max_overlap)))
    problem = "/observables: packing_fraction " + std::to_string(packing.packing_fraction) + " or max_overlap " +
              std::to_string(packing.max_overlap) + " not finite";
  if (!problem.empty()) throw RuntimeFailure("'" + path + "': refusing to write " + problem);

  io::TrajectoryWriter writer(path);
  writer.write_parameters(parameters);
  writer.write_grains(grains, packing.box);
  writer.append_frame(frame);
  writer.append_observable("packing_fraction", 0, 0.0, packing.packing_fraction);
  writer.append_observable("max_overlap", 0, 0.0, packing.max_overlap);
  writer.append_observable("minimiser_iterations", 0, 0.0, double(packing.iterations));
  writer.close();
}

Packing read_packing(const std::string& path, long long frame_index) {
  io::TrajectoryReader reader(path);
  const std::size_t index = reader.frame_index(frame_index);
  io::Frame frame = reader.frame(index);
  io::GrainProperties grains = reader.grains();
  check_start_grains(path, index, frame.box, frame.position, grains.radius);
  Packing p;
  p.box = frame.box;
  p.position = std::move(frame.position);
  p.radius = std::move(grains.radius);
  p.fixed = std::move(grains.fixed);
  double area = 0;
  for (std::size_t i = 0; i < p.radius.size(); ++i)
    if (!p.fixed[i]) area += M_PI * p.radius[i] * p.radius[i];
  p.packing_fraction = p.box.periodic_y ? area / p.box.area() : 0.0;
  p.max_overlap = max_overlap(p.box, p.position, p.radius);
  return p;
}

}  // namespace granflow
