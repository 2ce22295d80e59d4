// The cell list (neighbours/cell_list.hpp) against brute-force searches over the images of a
// Lees–Edwards or open box. The engine's reusable pair list is tested in
// tests/physics/test_cell_list.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <tuple>
#include <utility>
#include <vector>

#include "core/random.hpp"
#include "geometry/box.hpp"
#include "neighbours/cell_list.hpp"
#include "unit/brute_images.hpp"

using namespace granflow;
using granflow::testing::brute_minimum_image;

namespace {
std::vector<Vec2> random_positions(Rng& rng, const Box& box, int n) {
  std::vector<Vec2> r(n);
  for (auto& p : r) p = Vec2(rng.uniform(0, box.lx), box.periodic_y ? rng.uniform(0, box.ly) : rng.uniform(-3, 40));
  return r;
}

std::vector<std::pair<int, int>> brute_pairs(const Box& box, const std::vector<Vec2>& r, double cutoff) {
  std::vector<std::pair<int, int>> out;
  for (int i = 0; i < int(r.size()); ++i)
    for (int j = i + 1; j < int(r.size()); ++j)
      if (brute_minimum_image(box, r[i], r[j]).norm() < cutoff) out.emplace_back(i, j);
  return out;
}
}  // namespace

TEST(CellListSearch, MatchesBruteForceWithLeesEdwardsOffsets) {
  Rng rng(11);
  const double cutoff = 1.9;
  for (double lx : {9.0, 13.7, 30.0})
    for (double offset_frac : {0.0, 0.25, 0.5 - 1e-12, 0.5, 0.73, 1.0 - 1e-12}) {
      Box box{lx, 11.3, true, offset_frac * lx};
      auto r = random_positions(rng, box, 300);
      CellList cells;
      cells.build(r, box, cutoff);
      auto got = cells.pairs(r);
      auto want = brute_pairs(box, r, cutoff);
      ASSERT_EQ(got, want) << "lx " << lx << " offset " << box.offset;
      // No duplicate pairs.
      ASSERT_TRUE(std::adjacent_find(got.begin(), got.end()) == got.end());
    }
}

TEST(CellListSearch, UsesCellsForLargeBoxesAndFallsBackForTinyOnes) {
  Rng rng(5);
  Box big{40.0, 40.0, true, 13.0};
  auto r = random_positions(rng, big, 800);
  CellList cells;
  cells.build(r, big, 2.0);
  EXPECT_FALSE(cells.brute_force());
  EXPECT_EQ(cells.pairs(r), brute_pairs(big, r, 2.0));
  Box tiny{5.0, 5.0, true, 1.0};
  auto r2 = random_positions(rng, tiny, 30);
  cells.build(r2, tiny, 2.0);
  EXPECT_TRUE(cells.brute_force());
  EXPECT_EQ(cells.pairs(r2), brute_pairs(tiny, r2, 2.0));
}

TEST(CellListSearch, OpenBoxMatchesBruteForce) {
  Rng rng(9);
  Box box{25.0, 0.0, false, 0.0};
  auto r = random_positions(rng, box, 400);
  CellList cells;
  cells.build(r, box, 2.2);
  EXPECT_EQ(cells.pairs(r), brute_pairs(box, r, 2.2));
}

// Threads search bands of cell rows (BroadPhase::rebuild): any partition of the rows into
// bands must visit every pair exactly once, as the whole search does, with the same d.
TEST(CellListSearch, BandsOfRowsPartitionThePairs) {
  Rng rng(21);
  for (bool periodic : {true, false}) {
    Box box{40.0, periodic ? 37.0 : 0.0, periodic, periodic ? 17.3 : 0.0};
    auto r = random_positions(rng, box, 900);
    CellList cells;
    cells.build(r, box, 2.1);
    ASSERT_FALSE(cells.brute_force());
    ASSERT_GE(cells.rows(), 8);
    std::vector<std::tuple<int, int, double, double>> whole, banded;
    cells.for_each_pair(r, [&](int i, int j, const Vec2& d) { whole.emplace_back(i, j, d.x(), d.y()); });
    for (int bands : {1, 2, 3, 7}) {
      banded.clear();
      for (int b = 0; b < bands; ++b)
        cells.for_each_pair_in_rows(cells.rows() * b / bands, cells.rows() * (b + 1) / bands, r,
                                    [&](int i, int j, const Vec2& d) { banded.emplace_back(i, j, d.x(), d.y()); });
      // Bands in order reproduce the whole search in its order, bit for bit.
      EXPECT_EQ(banded, whole) << bands << " bands, periodic " << periodic;
    }
    EXPECT_EQ(whole.size(), brute_pairs(box, r, 2.1).size());
  }
  // The brute-force fallback visits everything in the band that starts at row 0.
  Box tiny{5.0, 5.0, true, 1.0};
  auto r = random_positions(rng, tiny, 30);
  CellList cells;
  cells.build(r, tiny, 2.0);
  ASSERT_TRUE(cells.brute_force());
  int first = 0, rest = 0;
  cells.for_each_pair_in_rows(0, 1, r, [&](int, int, const Vec2&) { ++first; });
  cells.for_each_pair_in_rows(1, cells.rows(), r, [&](int, int, const Vec2&) { ++rest; });
  EXPECT_EQ(first, int(brute_pairs(tiny, r, 2.0).size()));
  EXPECT_EQ(rest, 0);
}
