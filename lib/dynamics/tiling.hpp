#pragma once
// The engine's parallel order. Grains are numbered internally (bodies) by cells of a grid,
// tile by tile: horizontal strips at least one contact reach high, an even number of them,
// each cut into tiles of whole cell columns. Contacts of different strips of one parity share
// no grain, so threads sweep those strips at once, in an order, hence with a result, that
// does not depend on the number of threads; and a tile whose contacts and neighbours have
// settled can be skipped (see near_flagged()). Recomputed every step from the state only,
// so that restarts stay bit-identical.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "dynamics/broad_phase.hpp"
#include "dynamics/grains.hpp"
#include "geometry/box.hpp"

namespace granflow {

class Tiling {
 public:
  // margin: the smallest gap the tiles are sized for, whatever the alert distance.
  explicit Tiling(double margin = 0) : margin_(margin) {}

  // Numbers the grains of s into bodies, strips and tiles, for contacts up to
  // 2·max_radius + alert apart.
  void order(const GrainState& s, const Box& box, double max_radius, double alert, int threads);
  // Stores the candidates' rows tile by tile, ties in candidate order: row_of[c] is the row
  // of candidate c, and tile t holds rows first_row(t) … first_row(t + 1) − 1.
  void sort_rows(const std::vector<Candidate>& candidates, std::vector<int>& row_of, int threads);

  int body(int grain) const { return body_of_[grain]; }
  int strips() const { return strips_; }
  int blocks() const { return tiles_; }  // tiles per strip (tile = strip · blocks() + block)
  int tiles() const { return strips_ * tiles_; }
  int first_row(int tile) const { return tile_rows_[tile]; }
  // The tile of a contact between bodies a and b through the image `image` (see tiling.cpp).
  int tile(int a, int b, int image) const;

  // Which of the two strips next to each other across the periodic y boundary, the first
  // and the last, have a flagged tile (none without that boundary or with a single strip).
  struct EdgeFlags {
    bool first = false, last = false;
  };
  EdgeFlags edge_flags(const std::vector<std::uint8_t>& flags) const {
    if (!periodic_y_ || strips_ < 2) return {};
    auto strip_flagged = [&](int strip) {
      const auto first = flags.begin() + std::ptrdiff_t(strip) * tiles_;
      return std::find(first, first + tiles_, std::uint8_t(1)) != first + tiles_;
    };
    return {strip_flagged(0), strip_flagged(strips_ - 1)};
  }
  // Whether tile (strip, block) or one of its eight neighbours is flagged (flags per tile).
  // Across the periodic y boundary the Lees–Edwards offset shifts the columns: the tiles of
  // the first strip count any flagged tile of the last strip as a neighbour, and those of
  // the last strip, whose contacts across it reach grains of the first strip anywhere, any
  // flagged tile of either (edges: edge_flags(flags), taken once by the caller).
  bool near_flagged(const std::vector<std::uint8_t>& flags, int strip, int block, EdgeFlags edges) const {
    if ((strip == 0 && edges.last) || (strip == strips_ - 1 && (edges.first || edges.last))) return true;
    const int tiles = tiles_;
    for (int s : {strip - 1, strip, strip + 1}) {
      if (s < 0 || s >= strips_) continue;
      const std::uint8_t* f = flags.data() + std::size_t(s) * tiles;
      if (f[block] || (tiles > 1 && (f[block > 0 ? block - 1 : tiles - 1] || f[block + 1 < tiles ? block + 1 : 0])))
        return true;
    }
    return false;
  }

  std::size_t bytes() const;

 private:
  double margin_ = 0;
  bool periodic_y_ = false;
  int strips_ = 1, tiles_ = 1;            // strips, and tiles per strip (tile = strip · tiles_ + block)
  std::vector<int> body_of_;              // grain → body (internal spatial order)
  std::vector<int> strip_of_, block_of_;  // body → strip and column block of its tile
  std::vector<int> tile_rows_;            // rows of tile t: tile_rows_[t] … tile_rows_[t + 1] − 1
  std::vector<int> cells_, cell_of_;      // order(): grains per cell, then each grain's cell
};

}  // namespace granflow
