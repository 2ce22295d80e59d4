#pragma once
// Conversions between the engine's state and stored frames. A stored frame holds the
// whole dynamical state (positions, velocities, orientations, angular velocities, the
// Lees–Edwards offset, and the contacts' forces and ages, which are the engine's warm
// start): any frame of a trajectory is an exact restart point.
#include "dynamics/engine.hpp"
#include "io/trajectory.hpp"

namespace granflow {

// The engine's current state and the contacts of the step that produced it.
io::Frame frame_of(const Engine& engine, std::int64_t step, double time);
// The engine memory a frame's contacts encode (forces and ages of contacts with F_n > 0).
ContactMemory memory_of(const io::ContactRecords& contacts);
// Grain state of a stored frame (masses and fixed flags from the grain properties).
GrainState grains_of(const io::Frame& frame, const io::GrainProperties& grains);
io::GrainProperties properties_of(const GrainState& state);

}  // namespace granflow
