// The Lees–Edwards box (geometry/box.hpp): minimum image against a brute-force search
// over images, and the wrap of grains leaving through the sheared boundaries.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/random.hpp"
#include "geometry/box.hpp"
#include "unit/brute_images.hpp"

using namespace granflow;
using granflow::testing::brute_minimum_image;

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
    ASSERT_GE(a.x(), 0);
    ASSERT_LT(a.x(), box.lx);
    ASSERT_GE(a.y(), 0);
    ASSERT_LT(a.y(), box.ly);
    ASSERT_NEAR((box.minimum_image(a - b) - before).norm(), 0, 1e-9);
  }
}

// A negative rate that brings the offset back to 0 from above leaves it a hair below 0 after
// round-off; the wrapped offset must still lie in [0, lx) (the file format's range), not at lx.
TEST(LeesEdwardsBox, ShiftedOffsetStaysBelowLx) {
  const double lx = 19.371860602357876;
  for (double start : {1e-3, 0.1, 3.7, lx - 1e-12}) {
    for (double tiny : {1e-18, 1e-17, 1e-16, 1e-15, 0.0}) {
      Box box{lx, 14.0, true, start};
      box.shift_offset(-start - tiny);
      ASSERT_GE(box.offset, 0.0) << "start " << start << " tiny " << tiny;
      ASSERT_LT(box.offset, lx) << "start " << start << " tiny " << tiny;
    }
  }
  Box box{lx, 14.0, true, 0.0};
  for (int k = 0; k < 100000; ++k) {
    box.shift_offset(-1e-3 * 14.0 * 0.37);
    ASSERT_GE(box.offset, 0.0) << "step " << k;
    ASSERT_LT(box.offset, lx) << "step " << k;
  }
}
