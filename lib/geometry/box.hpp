#pragma once
// The simulation cell: periodic in x; in y either periodic with a Lees–Edwards
// image offset (simple shear) or open (incline, free surface).
//
// Convention (used by every program and in the files): the periodic image of the
// cell above (y + Ly) is shifted by +offset in x, offset = γ̇·Ly·t wrapped into
// [0, Lx). H5MD edges are the triclinic matrix [[Lx, 0], [offset, Ly]].
#include <cmath>

#include "core/vec.hpp"

namespace granflow {

struct Box {
  double lx = 0, ly = 0;
  bool periodic_y = true;
  double offset = 0;  // Lees–Edwards image offset δ ∈ [0, lx)

  double area() const { return lx * ly; }

  // Shortest separation vector among the periodic images of d = r_i − r_j: exact
  // whenever that shortest image is shorter than min(lx, ly)/2 (all pair searches
  // use cutoffs far below that); otherwise some valid image.
  Vec2 minimum_image(Vec2 d) const {
    if (periodic_y) {
      double k = std::round(d.y() / ly);
      d.y() -= k * ly;
      d.x() -= k * offset;
    }
    d.x() -= lx * std::round(d.x() / lx);
    return d;
  }

  // Brings r into the primary cell [0,lx)×[0,ly). A grain leaving through the top
  // re-enters at the bottom shifted by −offset in x and −γ̇·Ly in v_x (lab frame);
  // through the bottom, the opposite. Returns the number of top crossings (signed).
  int wrap(Vec2& r, Vec2& v, double rate) const {
    int crossings = 0;
    if (periodic_y) {
      double k = std::floor(r.y() / ly);
      if (k != 0) {
        r.y() -= k * ly;
        r.x() -= k * offset;
        v.x() -= k * rate * ly;
        crossings = int(k);
        // Round-off guards, keeping r.y in [0, ly). y just below 0 maps onto ly itself:
        // undo one crossing (y = 0 in the original image), not just y, or x and v_x
        // would carry a shift of a crossing that did not happen.
        if (r.y() >= ly) {
          r.y() -= ly;
          r.x() -= offset;
          v.x() -= rate * ly;
          ++crossings;
        }
        if (r.y() < 0) r.y() = 0;
      }
    }
    r.x() -= lx * std::floor(r.x() / lx);
    if (r.x() >= lx) r.x() -= lx;
    return crossings;
  }

  // Advances the image offset by du (= γ̇·Ly·dt), wrapped into [0, lx).
  void shift_offset(double du) {
    offset = std::fmod(offset + du, lx);
    // A hair below 0 plus lx rounds to lx itself, outside the range: that offset is 0.
    if (offset < 0) offset += lx;
    if (offset >= lx) offset = 0;
  }
};

}  // namespace granflow
