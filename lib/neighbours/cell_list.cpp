#include "neighbours/cell_list.hpp"

#include <algorithm>
#include <cmath>

namespace granflow {

int CellList::cell_of(const Vec2& r) const {
  int cx = std::clamp(int(r.x() / width_), 0, nx_ - 1);
  int cy = std::clamp(int((r.y() - y0_) / height_), 0, ny_ - 1);
  return cy * nx_ + cx;
}

void CellList::build(const std::vector<Vec2>& positions, const Box& box, double cutoff) {
  box_ = box;
  cutoff2_ = cutoff * cutoff;
  double y_extent = box.ly;
  y0_ = 0;
  if (!box.periodic_y && !positions.empty()) {
    auto [lo, hi] = std::minmax_element(positions.begin(), positions.end(),
                                        [](const Vec2& a, const Vec2& b) { return a.y() < b.y(); });
    y0_ = lo->y();
    y_extent = std::max(hi->y() - lo->y(), cutoff) * (1 + 1e-12) + 1e-300;
  }
  nx_ = std::max(1, int(std::floor(box.lx / cutoff)));
  ny_ = std::max(1, int(std::floor(y_extent / cutoff)));
  // Rows in an open box need no wrap, so 1 row is fine there; cap the grid for sparse data.
  brute_ = nx_ < 4 || (box.periodic_y && ny_ < 3);
  if (!box.periodic_y && ny_ > 4 * int(positions.size()) + 4) ny_ = 4 * int(positions.size()) + 4;
  if (brute_) return;
  width_ = box.lx / nx_;
  height_ = y_extent / ny_;
  const int cells = nx_ * ny_;
  start_.assign(cells + 1, 0);
  std::vector<int> cell(positions.size());
  for (std::size_t i = 0; i < positions.size(); ++i) {
    cell[i] = cell_of(positions[i]);
    ++start_[cell[i] + 1];
  }
  for (int c = 0; c < cells; ++c) start_[c + 1] += start_[c];
  order_.resize(positions.size());
  std::vector<int> fill(start_.begin(), start_.end() - 1);
  for (std::size_t i = 0; i < positions.size(); ++i) order_[fill[cell[i]]++] = int(i);
}

std::vector<std::pair<int, int>> CellList::pairs(const std::vector<Vec2>& positions) const {
  std::vector<std::pair<int, int>> out;
  for_each_pair(positions, [&](int i, int j, const Vec2&) { out.emplace_back(std::min(i, j), std::max(i, j)); });
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace granflow
