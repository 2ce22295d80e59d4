#pragma once
// Geometric contacts of a stored frame, the contact definition of thesis App. A.1 ("less than
// or equal to the sum of the radii", found after the position update) beside the engine's
// force-bearing one (P_n > 0). A pair is in contact when its gap at the frame's positions is
// at most `gap` (a length); it is long-lived when its gap one step earlier was at most `gap`
// too. A frame is the state after its step, r_n = r_{n−1} + dt·v_n, so the branch vector one
// step earlier is d − dt·(v_i − v_j − k·γ̇·Ly·x̂) for a pair seen through the image k rows up
// (the image moves at v_j + k·γ̇·Ly·x̂): no other frame is needed, whatever the frame spacing.
#include <vector>

#include "core/contact_records.hpp"
#include "io/trajectory.hpp"

namespace granflow::network {

// The frame's geometric contacts as ContactRecords, pairs (i < j) in increasing order:
// branch = minimum image of r_i − r_j at the frame; age = 2 if also within the gap one step
// earlier, else 1; binary_force = that of the frame's record of the same pair (the force-
// bearing contacts of its step), 0 where the pair bore no force; the other columns empty.
// std::invalid_argument for a negative or non-finite gap or dt, or radii of another length.
ContactRecords geometric_contacts(const io::Frame& frame, const std::vector<double>& radius, double gap, double dt,
                                  double rate);

}  // namespace granflow::network
