#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include "core/error.hpp"
#include "packing/input_rules.hpp"
#include "packing/packing.hpp"

namespace granflow {

Packing tile(const Packing& cell, long long copies) {
  const auto t0 = std::chrono::steady_clock::now();
  if (copies < 1) throw UsageError("--tile: " + std::to_string(copies) + " must be >= 1");
  require_biperiodic_input(cell, "tiled");
  const std::size_t n = cell.radius.size();
  if (n == 0) throw UsageError("--input: has no grains");
  const long long k = copies;
  // Grain indices are int throughout (cell lists, contact pairs).
  if (double(n) * double(k) * double(k) > double(std::numeric_limits<int>::max()))
    throw UsageError("--tile: " + std::to_string(k) + " copies per side of " + std::to_string(n) +
                     " grains make more than 2147483647");

  // Copy (a, b) of the cell sits at a·(Lx, 0) + b·(δ, Ly): the images of the cell itself, so
  // that every copy meets its neighbours as the cell meets its own images. Across the large
  // box's top, copy (a, K) is copy (a, 0) shifted by K·δ: that is the large box's offset.
  const Box& small = cell.box;
  Packing out;
  out.box = Box{double(k) * small.lx, double(k) * small.ly, true, 0.0};
  out.box.shift_offset(double(k) * small.offset);
  const std::size_t total = n * std::size_t(k * k);
  std::vector<Vec2> position(total);
  std::vector<double> radius(total);
  Vec2 no_velocity = Vec2::Zero();
  std::size_t q = 0;
  for (long long b = 0; b < k; ++b)
    for (long long a = 0; a < k; ++a)
      for (std::size_t i = 0; i < n; ++i, ++q) {
        Vec2 r = cell.position[i];
        small.wrap(r, no_velocity, 0.0);
        r += Vec2(double(a) * small.lx + double(b) * small.offset, double(b) * small.ly);
        out.box.wrap(r, no_velocity, 0.0);
        position[q] = r;
        radius[q] = cell.radius[i];
      }

  // Numbered band by band, as gf-pack numbers its packings (copies never tie: they lie whole
  // box widths apart).
  const double sigma = 2 * std::accumulate(cell.radius.begin(), cell.radius.end(), 0.0) / double(n);
  std::vector<std::size_t> order(total);
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::sort(order.begin(), order.end(),
            [&](std::size_t i, std::size_t j) { return numbered_before(position[i], position[j], sigma); });
  out.position.resize(total);
  out.radius.resize(total);
  for (std::size_t p = 0; p < total; ++p) {
    out.position[p] = position[order[p]];
    out.radius[p] = radius[order[p]];
  }
  out.fixed.assign(total, 0);
  double area = 0;
  for (double r : out.radius) area += M_PI * r * r;
  out.packing_fraction = area / out.box.area();
  out.max_overlap = max_overlap(out.box, out.position, out.radius);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace granflow
