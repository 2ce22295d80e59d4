#pragma once
// The engine's broad phase: which pairs of grains may touch or bind within a step (the
// candidates), found from a pair list with a skin. The list holds the pairs whose gap was
// below reach = alert + skin when it was built, and is rebuilt only when the accumulated
// worst-case relative displacement since then (the drift) could have brought an unlisted
// pair within the alert distance; the candidates are thus exactly those a fresh search
// would find, and the skin changes only the cost.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "dynamics/grains.hpp"
#include "geometry/box.hpp"

namespace granflow {

// A pair of grains i < j within the alert distance, seen through the Lees–Edwards image k
// (|k| ≤ 1) of j. 24 bytes: grain j and the image share a word (N < 2³⁰ grains).
struct Candidate {
  int i;                 // grain i < j
  std::uint32_t packed;  // j | (k + 1) << 30
  double dx, dy;         // r_i − r_j (minimum image)
  Candidate() = default;
  Candidate(int i_, int j_, int image_, double dx_, double dy_)
      : i(i_), packed(std::uint32_t(j_) | std::uint32_t(image_ + 1) << 30), dx(dx_), dy(dy_) {}
  int j() const { return int(packed & 0x3fffffffu); }
  int image() const { return int(packed >> 30) - 1; }
};
static_assert(sizeof(Candidate) == 24);

class BroadPhase {
 public:
  BroadPhase() = default;
  // skin: the list's extra gap; max_radius: the largest grain radius.
  BroadPhase(double skin, double max_radius) : skin_(skin), max_radius_(max_radius) {}

  // The grains have moved by one step of length dt at a shear rate `rate`; vmax, the largest
  // fluctuating speed |ṽ| measured after the move, bounds how much any listed gap shrank.
  void moved(double vmax, double rate, double dt);
  // The candidates of state s at the given alert distance, sorted by (i, j), from the pair
  // list, rebuilt first if it might miss one. Returns whether it was rebuilt.
  bool find(const GrainState& s, const Box& box, double alert, int threads);

  const std::vector<Candidate>& candidates() const { return candidates_; }
  // Largest overlap max(0, −g) over the listed pairs at the last find().
  double overlap() const { return overlap_; }
  std::size_t bytes() const;

 private:
  double select(const GrainState& s, const Box& box, double alert, std::size_t first, std::size_t last,
                std::vector<Candidate>& out) const;
  void rebuild(const GrainState& s, const Box& box, double alert, int threads);

  double skin_ = 0, max_radius_ = 0;
  // Pair list: grains i < j, sorted, whose gap was below reach_ when it was built; drift_
  // bounds how much any gap may have shrunk since.
  double reach_ = 0, drift_ = 0, overlap_ = 0;
  std::vector<std::array<int, 2>> pairs_;
  std::vector<int> bucket_;                               // start of each grain's pairs, while sorting
  std::vector<Candidate> candidates_;                     // sorted by (i, j)
  std::vector<std::vector<Candidate>> candidate_blocks_;  // per block of pairs, with threads
};

}  // namespace granflow
