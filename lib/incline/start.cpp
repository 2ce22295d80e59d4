#include "incline/start.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include "core/error.hpp"
#include "packing/start_check.hpp"
#include "run/frames.hpp"

namespace granflow {

Vec2 incline_gravity(double g, double angle_degrees) {
  const double theta = angle_degrees * M_PI / 180;
  return g * Vec2(std::sin(theta), -std::cos(theta));
}

void warn_small_angle(const char* program, double angle_degrees) {
  if (angle_degrees >= 1) return;
  std::fprintf(stderr, "%s: warning: --angle %g is in degrees; did you mean %.3g° (%g rad)?\n", program, angle_degrees,
               angle_degrees * 180 / M_PI, angle_degrees);
}

InclineStart incline_start(const io::TrajectoryReader& input, long long frame_index) {
  const std::string& path = input.path();
  const std::size_t index = input.frame_index(frame_index);
  io::Frame frame = input.frame(index);
  if (frame.box.periodic_y)
    throw UsageError("'" + path + "' is a biperiodic packing (box periodic in y): gf-incline needs an incline " +
                     "start (gf-pack --incline) or a gf-incline trajectory");
  InclineStart start;
  start.frame_index = index;
  start.frame_step = frame.step;
  start.frame_time = frame.time;
  const io::Parameters time = input.attributes("/particles/grains/position/time");
  if (time.has("unit")) start.frame_time_unit = time.get_string("unit");
  start.grains = grains_of(frame, input.grains());
  start.box = frame.box;
  if (frame.has_contacts) {
    check_start_contacts(path, index, frame.contacts);
    start.contacts = frame.contacts;
  }
  const GrainState& g = start.grains;
  double radius = 0, mass = 0;
  for (std::size_t i = 0; i < g.size(); ++i) {
    const double y = g.position[i].y();
    if (g.fixed[i]) {
      ++start.base_grains;
      if (y != 0)
        throw UsageError("'" + path + "': fixed grain " + std::to_string(i) + " is at y = " + std::to_string(y) +
                         ", off the base line y = 0");
    } else {
      radius += g.radius[i];
      mass += g.mass[i];
      if (!(y >= 0 && y <= start.box.ly))
        throw UsageError("'" + path + "': grain " + std::to_string(i) + " at y = " + std::to_string(y) +
                         " lies outside the layer [0, " + std::to_string(start.box.ly) + "]");
    }
  }
  require_run_contacts(input);
  check_start_grains(path, index, start.box, g.position, g.radius);
  const std::size_t mobile = g.size() - start.base_grains;
  if (start.base_grains == 0) throw UsageError("'" + path + "' has no fixed base grains (use gf-pack --incline)");
  if (mobile == 0) throw UsageError("'" + path + "' has no mobile grains");
  start.mean_radius = radius / double(mobile);
  start.mean_mass = mass / double(mobile);
  return start;
}

void check_layer(const GrainState& state, const Box& box, std::int64_t step) {
  for (std::size_t i = 0; i < state.size(); ++i) {
    if (state.fixed[i]) continue;
    const double y = state.position[i].y();
    if (y >= 0 && y <= box.ly) continue;
    char message[256];
    if (y < 0)
      std::snprintf(message, sizeof message, "grain %zu crossed the base at step %lld: y = %.6g < 0", i,
                    (long long)step, y);
    else
      std::snprintf(message, sizeof message,
                    "grain %zu left through the free surface at step %lld: y = %.6g above the box top %.6g", i,
                    (long long)step, y, box.ly);
    throw RuntimeFailure(message);
  }
}

}  // namespace granflow
