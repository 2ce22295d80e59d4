#include "run/frames.hpp"

namespace granflow {

io::Frame frame_of(const Engine& engine, std::int64_t step, double time) {
  const GrainState& s = engine.state();
  io::Frame f;
  f.step = step;
  f.time = time;
  f.box = engine.box();
  f.position = s.position;
  f.velocity = s.velocity;
  f.orientation = s.orientation;
  f.angular_velocity = s.angular_velocity;
  f.contacts = engine.contacts();
  f.has_contacts = true;
  return f;
}

ContactMemory memory_of(const io::ContactRecords& c) {
  ContactMemory m;
  m.pair.reserve(c.size());
  for (const auto& p : c.pair) m.pair.push_back({int(p[0]), int(p[1])});
  m.normal_force = c.normal_force;
  m.tangential_force = c.tangential_force;
  m.age.assign(c.age.begin(), c.age.end());
  return m;
}

GrainState grains_of(const io::Frame& frame, const io::GrainProperties& grains) {
  GrainState s;
  s.position = frame.position;
  s.velocity = frame.velocity;
  s.orientation = frame.orientation;
  s.angular_velocity = frame.angular_velocity;
  s.radius = grains.radius;
  s.mass = grains.mass;
  s.fixed = grains.fixed;
  return s;
}

io::GrainProperties properties_of(const GrainState& state) {
  return io::GrainProperties{state.radius, state.mass, state.fixed};
}

}  // namespace granflow
