#pragma once
// The pairs of grains close enough to touch, through the periodic images of the box: the
// one cell-list walk behind the overlap report of a packing and the start check.
#include <algorithm>
#include <vector>

#include "core/vec.hpp"
#include "geometry/box.hpp"
#include "neighbours/cell_list.hpp"

namespace granflow {

// Calls visit(i, j, d) for every pair within the largest diameter, d the minimum-image
// separation; nothing for fewer than two grains.
template <class Visit>
void for_each_close_pair(const Box& box, const std::vector<Vec2>& position, const std::vector<double>& radius,
                         Visit&& visit) {
  if (position.size() < 2) return;
  const double r_max = *std::max_element(radius.begin(), radius.end());
  std::vector<Vec2> wrapped = position;
  Vec2 unused_velocity = Vec2::Zero();
  for (Vec2& r : wrapped) box.wrap(r, unused_velocity, 0);
  CellList cells;
  cells.build(wrapped, box, 2 * r_max);
  cells.for_each_pair(wrapped, visit);
}

}  // namespace granflow
