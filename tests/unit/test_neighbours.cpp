// Lees–Edwards minimum image and cell lists against brute-force searches over images.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <tuple>

#include "core/random.hpp"
#include "geometry/box.hpp"
#include "neighbours/cell_list.hpp"

using namespace granflow;

namespace {
// Shortest separation by explicit search over images k = -2..2 in both directions.
Vec2 brute_minimum_image(const Box& box, const Vec2& ri, const Vec2& rj) {
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

TEST(LeesEdwardsBox, MinimumImageMatchesBruteForce) {
  Rng rng(7);
  int checked = 0;
  for (double offset : {0.0, 1e-9, 3.3, 9.999, 10.0 - 1e-9, 17.2}) {
    Box box{20.0, 14.0, true, offset};
    for (int t = 0; t < 2000; ++t) {
      Vec2 a(rng.uniform(0, box.lx), rng.uniform(0, box.ly));
      Vec2 b(rng.uniform(0, box.lx), rng.uniform(0, box.ly));
      Vec2 d = box.minimum_image(a - b);
      Vec2 ref = brute_minimum_image(box, a, b);
      // Exact whenever the nearest image is closer than half the smaller box side,
      // which is all a cutoff-limited search needs; beyond that it is a valid image.
      if (ref.norm() < 0.5 * std::min(box.lx, box.ly)) {
        ASSERT_NEAR(d.norm(), ref.norm(), 1e-12) << "offset " << offset;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 3000);
}

TEST(LeesEdwardsBox, WrapShiftsPositionAndVelocity) {
  Box box{10.0, 8.0, true, 2.5};
  const double rate = 0.3;
  Vec2 r(1.0, 8.2), v(0.4, 1.0);
  EXPECT_EQ(box.wrap(r, v, rate), 1);  // left through the top
  EXPECT_NEAR(r.y(), 0.2, 1e-12);
  EXPECT_NEAR(r.x(), 1.0 - 2.5 + 10.0, 1e-12);
  EXPECT_NEAR(v.x(), 0.4 - rate * 8.0, 1e-12);
  EXPECT_NEAR(v.y(), 1.0, 0);
  Vec2 r2(9.5, -0.1), v2(0.0, -1.0);
  EXPECT_EQ(box.wrap(r2, v2, rate), -1);  // left through the bottom
  EXPECT_NEAR(r2.y(), 7.9, 1e-12);
  EXPECT_NEAR(r2.x(), 9.5 + 2.5 - 10.0, 1e-12);
  EXPECT_NEAR(v2.x(), rate * 8.0, 1e-12);
}

TEST(LeesEdwardsBox, WrappedImageIsTheSamePoint) {
  // Wrapping must not change any minimum-image separation.
  Rng rng(3);
  Box box{12.0, 9.0, true, 4.7};
  for (int t = 0; t < 1000; ++t) {
    Vec2 a(rng.uniform(-20, 30), rng.uniform(-20, 30)), b(rng.uniform(0, 12), rng.uniform(0, 9));
    Vec2 before = box.minimum_image(a - b);
    Vec2 v(0, 0);
    box.wrap(a, v, 0.0);
    ASSERT_GE(a.x(), 0); ASSERT_LT(a.x(), box.lx);
    ASSERT_GE(a.y(), 0); ASSERT_LT(a.y(), box.ly);
    ASSERT_NEAR((box.minimum_image(a - b) - before).norm(), 0, 1e-9);
  }
}

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

// Threads search bands of cell rows (Engine::rebuild_pairs): any partition of the rows into
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
