#pragma once
// Rules shared by the ways gf-pack makes a packing: the order grains are numbered in, and
// what an input packing or frame must be for a repack or a tiling.
#include <string>

#include "core/error.hpp"
#include "core/vec.hpp"
#include "packing/packing.hpp"

namespace granflow {

// Band by band: bands one mean diameter σ high, by x within a band. The engine reads its
// per-grain arrays in grain order, so neighbours in space are then near in memory (N = 10⁵:
// a few % per sweep).
inline bool numbered_before(const Vec2& a, const Vec2& b, double sigma) {
  const long long ra = (long long)(a.y() / sigma), rb = (long long)(b.y() / sigma);
  return ra != rb ? ra < rb : a.x() < b.x();
}

// UsageError naming --input unless `input` is biperiodic without fixed grains; `made` says
// what would be made of it ("repacked", "tiled").
inline void require_biperiodic_input(const Packing& input, const std::string& made) {
  if (!input.box.periodic_y)
    throw UsageError("--input: not biperiodic (its box is open in y); only a biperiodic packing or frame can be " +
                     made);
  for (auto f : input.fixed)
    if (f) throw UsageError("--input: has fixed grains; only a biperiodic packing or frame can be " + made);
}

}  // namespace granflow
