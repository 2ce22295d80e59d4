#pragma once
// Flow down a rough incline (thesis §4.3): the start state of a run, gravity in the
// frame of the base, and the check that every grain stays in the layer.
//
// Frame: x along the base (periodic), y perpendicular to it; the base is a row of fixed
// grains centred on y = 0 (gf-pack --incline), the box is open in y with its top at ly.
// Tilting the base by θ puts gravity at g(sin θ, −cos θ): x points down the slope.
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/vec.hpp"
#include "dynamics/grains.hpp"
#include "geometry/box.hpp"
#include "io/trajectory.hpp"

namespace granflow {

struct InclineStart {
  GrainState grains;
  Box box;
  // Contacts of a stored frame (empty for a packing): the warm start of the first step
  // and the contacts of the run's first frame.
  io::ContactRecords contacts;
  std::size_t base_grains = 0;  // fixed grains
  double mean_radius = 0;       // ⟨R⟩ of the mobile grains
  double mean_mass = 0;         // their mean mass
  // The stored frame used: its index in the input, its step and time there.
  std::size_t frame_index = 0;
  std::int64_t frame_step = 0;
  double frame_time = 0;
  // The unit of frame_time: the input's (its time datasets' `unit` attribute: "T", or
  // "code" in files before the units module; io::kCodeTime where absent).
  std::string frame_time_unit = io::kCodeTime;
};

// g(sin θ, −cos θ) for θ in degrees.
Vec2 incline_gravity(double g, double angle_degrees);

// One warning line on stderr when --angle is below 1°, where a flow is unlikely to be
// meant and an angle in radians typed by mistake likely: it names the value in degrees
// those radians would be. Nothing otherwise.
void warn_small_angle(const char* program, double angle_degrees);

// Frame `frame` (negative: from the end) of an incline packing (gf-pack --incline) or
// of a gf-incline trajectory, velocities kept. UsageError naming the file for a box
// periodic in y, no fixed or no mobile grains, a fixed grain off the base line y = 0,
// or a mobile grain outside [0, ly].
InclineStart incline_start(const io::TrajectoryReader& input, long long frame);

// RuntimeFailure naming the grain, the step and its height when a mobile grain has left
// the layer: its centre above the box top ly (out through the free surface: the input's
// ly is a grain diameter above the dilute start, far above the settled layer) or below
// y = 0 (through the base). Either means a broken base or a flow the run cannot hold.
void check_layer(const GrainState& state, const Box& box, std::int64_t step);

}  // namespace granflow
