#pragma once
// Brute-force references over periodic images, shared by the box and cell-list tests.
#include "geometry/box.hpp"

namespace granflow::testing {

// Shortest separation by explicit search over images k = -2..2 in both directions.
inline Vec2 brute_minimum_image(const Box& box, const Vec2& ri, const Vec2& rj) {
  Vec2 best(1e300, 1e300);
  int ky_range = box.periodic_y ? 2 : 0;
  for (int ky = -ky_range; ky <= ky_range; ++ky)
    for (int kx = -2; kx <= 2; ++kx) {
      Vec2 image = rj + Vec2(kx * box.lx + ky * box.offset, ky * box.ly);
      Vec2 d = ri - image;
      if (d.squaredNorm() < best.squaredNorm()) best = d;
    }
  return best;
}

}  // namespace granflow::testing
