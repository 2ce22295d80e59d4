#include "packing/packing_io.hpp"

#include <cmath>

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
  io::Frame frame = reader.frame(reader.frame_index(frame_index));
  io::GrainProperties grains = reader.grains();
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
