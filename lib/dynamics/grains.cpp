#include "dynamics/grains.hpp"

#include <cmath>
#include <utility>

namespace granflow {

double disk_mass(double radius) { return M_PI * radius * radius; }

GrainState make_grains(std::vector<Vec2> positions, const std::vector<double>& radii) {
  GrainState s;
  const std::size_t n = positions.size();
  s.position = std::move(positions);
  s.velocity.assign(n, Vec2::Zero());
  s.orientation.assign(n, 0.0);
  s.angular_velocity.assign(n, 0.0);
  s.radius = radii;
  s.mass.resize(n);
  for (std::size_t i = 0; i < n; ++i) s.mass[i] = disk_mass(radii[i]);
  s.fixed.assign(n, 0);
  return s;
}

void add_affine_flow(GrainState& state, const Box& box, double rate) {
  for (std::size_t i = 0; i < state.size(); ++i) {
    if (state.fixed[i]) continue;
    state.velocity[i] += streaming_velocity(box, rate, state.position[i].y());
    state.angular_velocity[i] -= 0.5 * rate;
  }
}

void remove_affine_flow(GrainState& state, const Box& box, double rate) {
  for (std::size_t i = 0; i < state.size(); ++i) {
    if (state.fixed[i]) continue;
    state.velocity[i] = fluctuating_velocity(state, box, rate, i);
    state.angular_velocity[i] += 0.5 * rate;
  }
}

}  // namespace granflow
