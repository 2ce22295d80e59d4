#include "dynamics/tiling.hpp"

#include <cmath>

#include "dynamics/capacity.hpp"
#include "dynamics/parallel.hpp"

namespace granflow {

namespace {

// Width of the sweep tiles in cell columns (≈ 8 largest diameters): narrow enough that a
// few unsettled contacts keep little else busy, wide enough to hold a few dozen contacts.
constexpr int kTileColumns = 8;

}  // namespace

// Internal numbering of the grains by cells of a grid, tile by tile (see below) and row by
// row within a tile, so that the bodies of neighbouring grains, and the contacts between
// them, lie close together in memory, and each tile's rows are swept in one stretch.
void Tiling::order(const GrainState& s, const Box& box, double max_radius, double alert, int threads) {
  const int n = int(s.size());
  periodic_y_ = box.periodic_y;
  double y0 = 0, height = box.ly;
  if (!box.periodic_y) {
    const auto [lo, hi] = std::minmax_element(s.position.begin(), s.position.end(),
                                              [](const Vec2& a, const Vec2& b) { return a.y() < b.y(); });
    y0 = lo->y();
    height = hi->y() - lo->y();
  }
  const double h = 2 * max_radius;
  const int columns = std::max(1, int(box.lx / h));
  const int rows = std::clamp(int(height / h), 1, std::max(1, 2 * n / columns));  // at most ~2n cells
  const double to_column = columns / box.lx, to_row = height > 0 ? rows / height : 0.0;

  // Sweep strips: whole cell rows, at least a contact reach (2R_max + alert) high, and an
  // even number of them (or one), so that the two strips next to each other across the
  // periodic boundary, the first and the last, have different parity. Each strip is cut
  // into tiles of whole columns, at least kTileColumns and a contact reach wide (one tile,
  // or at least three, so that a tile's left and right neighbours differ); the last strip
  // and the last tile of a strip take the rows and columns left over. The reach here is at
  // least 2R_max + 0.1σ, whatever the alert: strips of one cell row change the sweep order,
  // and piles coming to rest on an incline converge far worse with it (5°: 536 steps at the
  // sweep cap instead of 193, 7°: 4801 instead of 13, when the alert floor went from 0.1σ to
  // 0.01σ).
  const double reach = 2 * max_radius + std::max(alert, margin_);
  const double row_height = height > 0 ? height / rows : h;
  const int per_strip = std::max(1, int(std::ceil(reach / row_height)));
  strips_ = rows / per_strip;
  strips_ = strips_ > 1 ? strips_ - strips_ % 2 : 1;
  const int per_tile = std::max(kTileColumns, int(std::ceil(reach / (box.lx / columns))));
  tiles_ = strips_ > 1 ? columns / per_tile : 1;
  if (tiles_ < 3) tiles_ = 1;
  auto strip_of_row = [&](int row) { return std::min(row / per_strip, strips_ - 1); };
  auto block_of_column = [&](int column) { return std::min(column / per_tile, tiles_ - 1); };
  // Cells ranked tile by tile, row by row within a tile: counted per cell, then summed in
  // that order.
  cells_.assign(std::size_t(columns) * rows, 0);
  cell_of_.resize(n);
  parallel_for(threads, n, [&](int g) {
    const Vec2& r = s.position[g];
    const int column = std::clamp(int(r.x() * to_column), 0, columns - 1);
    const int row = std::clamp(int((r.y() - y0) * to_row), 0, rows - 1);
    cell_of_[g] = row * columns + column;
  });
  for (int g = 0; g < n; ++g) ++cells_[cell_of_[g]];
  int next = 0;
  for (int strip = 0; strip < strips_; ++strip)
    for (int block = 0; block < tiles_; ++block)
      for (int row = strip * per_strip; row < rows && strip_of_row(row) == strip; ++row)
        for (int column = block * per_tile; column < columns && block_of_column(column) == block; ++column) {
          int& cell = cells_[std::size_t(row) * columns + column];
          const int count = cell;
          cell = next;
          next += count;
        }
  body_of_.resize(n);
  strip_of_.resize(n);
  block_of_.resize(n);
  for (int g = 0; g < n; ++g) body_of_[g] = cells_[cell_of_[g]]++;
  parallel_for(threads, n, [&](int g) {
    const int b = body_of_[g];
    strip_of_[b] = strip_of_row(cell_of_[g] / columns);
    block_of_[b] = block_of_column(cell_of_[g] % columns);
  });
}

// The tile of a contact between bodies a and b: the strip of the lower one and the column
// block of the left one (across the periodic x boundary, the last). A contact thus moves only
// bodies of its own tile and of the tiles above and to the right of it, and a body is moved
// only by contacts of its own tile and of the tiles below and to the left, so a tile needs
// a sweep only if it or one of its eight neighbours moved. Across the periodic y boundary
// (a contact through the image k ≠ 0), where the Lees–Edwards offset breaks the columns'
// alignment, the tile of the upper body (see GaussSeidel::sweep()).
int Tiling::tile(int a, int b, int image) const {
  if (image != 0) {
    const int upper = image > 0 ? a : b;
    return strip_of_[upper] * tiles_ + block_of_[upper];
  }
  const int ba = block_of_[a], bb = block_of_[b];
  const int block = std::abs(ba - bb) <= 1 ? std::min(ba, bb) : std::max(ba, bb);
  return std::min(strip_of_[a], strip_of_[b]) * tiles_ + block;
}

void Tiling::sort_rows(const std::vector<Candidate>& candidates, std::vector<int>& row_of, int threads) {
  const std::size_t count = candidates.size();
  // Each candidate's tile (in parallel: it reads scattered bodies), then its row: counting
  // sort by tile, ties in candidate order.
  parallel_for(threads, count, [&](std::size_t c) {
    const Candidate& k = candidates[c];
    row_of[c] = tile(body_of_[k.i], body_of_[k.j()], k.image());
  });
  counting_sort(
      std::size_t(tiles()), tile_rows_,
      [&](auto emit) {
        for (std::size_t c = 0; c < count; ++c) emit(row_of[c], c);
      },
      [](std::size_t) {}, [&](std::size_t c, int slot) { row_of[c] = slot; });
}

std::size_t Tiling::bytes() const {
  return heap_bytes(body_of_) + heap_bytes(strip_of_) + heap_bytes(block_of_) + heap_bytes(tile_rows_) +
         heap_bytes(cells_) + heap_bytes(cell_of_);
}

}  // namespace granflow
