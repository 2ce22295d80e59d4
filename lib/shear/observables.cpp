#include "shear/observables.hpp"

namespace granflow {

double granular_temperature(const GrainState& state, const Box& box, double rate) {
  Vec2 mean_v = Vec2::Zero();
  double mean_w = 0;
  int n = 0;
  for (std::size_t i = 0; i < state.size(); ++i) {
    if (state.fixed[i]) continue;
    mean_v += fluctuating_velocity(state, box, rate, i);
    mean_w += state.angular_velocity[i];
    ++n;
  }
  if (n == 0) return 0;
  mean_v /= n;
  mean_w /= n;
  double sum = 0;
  for (std::size_t i = 0; i < state.size(); ++i) {
    if (state.fixed[i]) continue;
    const double dw = state.radius[i] * (state.angular_velocity[i] - mean_w);
    sum += (fluctuating_velocity(state, box, rate, i) - mean_v).squaredNorm() + 0.5 * dw * dw;
  }
  return sum / n;
}

StressTensors stress(const GrainState& state, const Box& box, double rate, const ContactRecords& contacts) {
  StressTensors s;
  const double area = box.area();
  Vec2 momentum = Vec2::Zero();
  double mass = 0;
  for (std::size_t i = 0; i < state.size(); ++i) {
    if (state.fixed[i]) continue;
    momentum += state.mass[i] * fluctuating_velocity(state, box, rate, i);
    mass += state.mass[i];
  }
  if (mass > 0) {
    const Vec2 mean_v = momentum / mass;
    for (std::size_t i = 0; i < state.size(); ++i) {
      if (state.fixed[i]) continue;
      const Vec2 v = fluctuating_velocity(state, box, rate, i) - mean_v;
      s.kinetic += state.mass[i] * v * v.transpose();
    }
  }
  for (std::size_t c = 0; c < contacts.size(); ++c) {
    const Vec2& b = contacts.branch[c];
    const double length = b.norm();
    const Vec2 n = b / length;
    const Vec2 force = contacts.normal_force[c] * n + contacts.tangential_force[c] * perp(n);
    s.contact += b * force.transpose();
    s.collisional += (length * contacts.binary_force[c]) * n * n.transpose();
  }
  s.kinetic /= area;
  s.contact /= area;
  s.collisional /= area;
  return s;
}

}  // namespace granflow
