#pragma once
// Cell lists for pair searches in a Box, Lees–Edwards aware: every unordered pair
// whose minimum-image centre distance is below the cutoff is visited exactly once.
// Small cells (fewer than 4 columns or 3 rows) fall back to an all-pairs loop,
// which is exact but O(N²).
#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/vec.hpp"
#include "geometry/box.hpp"

namespace granflow {

class CellList {
 public:
  // positions must already be wrapped (Box::wrap) when the box is periodic in y;
  // for an open y they may lie anywhere.
  void build(const std::vector<Vec2>& positions, const Box& box, double cutoff);

  // Calls f(i, j, d) for every pair i != j with |d| < cutoff, d = minimum_image(r_i − r_j).
  // Order is deterministic (cell by cell); i < j is not guaranteed.
  template <class F>
  void for_each_pair(const std::vector<Vec2>& positions, F&& f) const;

  // The part of for_each_pair() that starts in cell rows [first, last) (all pairs for the
  // brute-force fallback if first == 0, none otherwise): disjoint row ranges visit disjoint
  // pairs, so threads can share the rows.
  template <class F>
  void for_each_pair_in_rows(int first, int last, const std::vector<Vec2>& positions, F&& f) const;

  // Same, collected as (i, j) with i < j, sorted: the reference order used by tests.
  std::vector<std::pair<int, int>> pairs(const std::vector<Vec2>& positions) const;

  int columns() const { return nx_; }
  int rows() const { return ny_; }
  bool brute_force() const { return brute_; }

 private:
  template <class F>
  void visit_cells(int a, int b, const std::vector<Vec2>& positions, F& f) const;
  int cell_of(const Vec2& r) const;

  Box box_;
  double cutoff2_ = 0;
  int nx_ = 0, ny_ = 0;
  double width_ = 0, height_ = 0, y0_ = 0;
  bool brute_ = true;
  std::vector<int> start_;  // [nx*ny + 1] offsets into order_
  std::vector<int> order_;  // grain indices sorted by cell
};

template <class F>
void CellList::visit_cells(int a, int b, const std::vector<Vec2>& positions, F& f) const {
  for (int p = start_[a]; p < start_[a + 1]; ++p) {
    int i = order_[p];
    int q0 = (a == b) ? p + 1 : start_[b];
    for (int q = q0; q < start_[b + 1]; ++q) {
      int j = order_[q];
      Vec2 d = box_.minimum_image(positions[i] - positions[j]);
      if (d.squaredNorm() < cutoff2_) f(i, j, d);
    }
  }
}

template <class F>
void CellList::for_each_pair(const std::vector<Vec2>& positions, F&& f) const {
  for_each_pair_in_rows(0, ny_, positions, f);
}

template <class F>
void CellList::for_each_pair_in_rows(int first, int last, const std::vector<Vec2>& positions, F&& f) const {
  const int n = int(positions.size());
  if (brute_) {
    if (first != 0) return;
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j) {
        Vec2 d = box_.minimum_image(positions[i] - positions[j]);
        if (d.squaredNorm() < cutoff2_) f(i, j, d);
      }
    return;
  }
  auto wrapx = [this](int c) { return ((c % nx_) + nx_) % nx_; };
  for (int cy = std::max(first, 0); cy < std::min(last, ny_); ++cy) {
    for (int cx = 0; cx < nx_; ++cx) {
      const int a = cy * nx_ + cx;
      visit_cells(a, a, positions, f);
      visit_cells(a, cy * nx_ + wrapx(cx + 1), positions, f);
      if (cy + 1 < ny_) {
        for (int k = cx - 1; k <= cx + 1; ++k) visit_cells(a, (cy + 1) * nx_ + wrapx(k), positions, f);
      } else if (box_.periodic_y) {
        // Row above the top is row 0 seen through the Lees–Edwards image, shifted by +offset:
        // its grains at x appear at x + offset, so the window [cx−1, cx+2) of columns moves by −offset.
        int k0 = int(std::floor(cx - 1 - box_.offset / width_));
        for (int k = k0; k < k0 + 4; ++k) visit_cells(a, wrapx(k), positions, f);
      }
    }
  }
}

}  // namespace granflow
