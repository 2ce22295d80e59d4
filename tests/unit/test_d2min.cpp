// D²min (stz/d2min.hpp): the known answer of REFERENCES.md, affine maps, Lees–Edwards
// motion through wrapped stored frames (strains past lx/2 and lx, negative strain, grains
// crossing the sheared boundary), an all-images brute force, the singular flag, bad input.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/random.hpp"
#include "geometry/box.hpp"
#include "stz/d2min.hpp"

using namespace granflow;
using namespace granflow::stz;

namespace {

// A square lattice of spacing ≈ 1 filling the primary cell, each point jittered by up to
// ±0.3 (≈ 12 points within 2 of each other, like disks of diameter 1 in a dense flow).
std::vector<Vec2> jittered_lattice(Rng& rng, double x0, double y0, double w, double h) {
  const int nx = int(std::round(w)), ny = int(std::round(h));
  std::vector<Vec2> r;
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix)
      r.push_back(
          Vec2(x0 + (ix + 0.5 + rng.uniform(-0.3, 0.3)) * w / nx, y0 + (iy + 0.5 + rng.uniform(-0.3, 0.3)) * h / ny));
  return r;
}

// A motion consistent with the Lees–Edwards images: at progress s ∈ [0, 1], simple shear
// of strain γ(s) = strain·s about the line y = y0, a translation s·lift, and s·noise[i] on
// grain i (non-affine when noise is not zero). Applied to an image r + k(δ₀, ly) it gives
// the image in row k of the box whose offset moved by strain·ly.
struct Motion {
  double strain = 0, y0 = 0;
  Vec2 lift = Vec2::Zero();
  std::vector<Vec2> noise;
  Vec2 at(const Vec2& r0, std::size_t i, double s) const {
    Vec2 r = r0 + Vec2(strain * s * (r0.y() - y0), 0) + s * lift;
    if (!noise.empty()) r += s * noise[i];
    return r;
  }
};

// Frames as gf-shear stores them: the box offset advanced by γ̇·ly·t and wrapped into
// [0, lx), each true position wrapped into the primary cell (Box::wrap: a grain that left
// through the top sits at −offset in x). The primary-cell image is unique, so wrapping the
// true position once equals the engine's step-by-step wrapping.
struct StoredRun {
  double rate = 0;
  std::vector<Box> box;
  std::vector<double> time;
  std::vector<std::vector<Vec2>> position;  // wrapped
  std::vector<std::vector<Vec2>> truth;     // unwrapped
  std::vector<StoredFrame> frames() const {
    std::vector<StoredFrame> out;
    for (std::size_t f = 0; f < box.size(); ++f) out.push_back({position[f], box[f], time[f]});
    return out;
  }
};

StoredRun store(const std::vector<Vec2>& r0, const Box& box0, const Motion& motion, int frames) {
  StoredRun run;
  const double duration = 2.5;
  run.rate = motion.strain / duration;
  for (int f = 0; f < frames; ++f) {
    const double s = double(f) / (frames - 1);
    Box box = box0;
    box.shift_offset(run.rate * box0.ly * s * duration);
    std::vector<Vec2> wrapped, truth;
    for (std::size_t i = 0; i < r0.size(); ++i) {
      Vec2 r = motion.at(r0[i], i, s), v = Vec2::Zero();
      truth.push_back(r);
      box.wrap(r, v, run.rate);
      wrapped.push_back(r);
    }
    run.box.push_back(box);
    run.time.push_back(s * duration);
    run.position.push_back(wrapped);
    run.truth.push_back(truth);
  }
  return run;
}

// All-images D²min, written from the definition with no cell list, bonds or unwrapping: the
// neighbours of i are the images r0_j + kx·lx + ky·(δ₀, ly) within the cutoff of r0_i, and
// the current bond goes to the same image of the true current position, whose box offset
// moved by Δδ.
struct Brute {
  double value;
  int neighbours;
  Mat2 F;
};
std::vector<Brute> brute_d2min(const std::vector<Vec2>& r0, const std::vector<Vec2>& r1, const Box& box0,
                               double offset_change, double cutoff) {
  std::vector<Brute> out;
  for (std::size_t i = 0; i < r0.size(); ++i) {
    std::vector<Vec2> before, after;
    for (std::size_t j = 0; j < r0.size(); ++j)
      for (int ky = -2; ky <= 2; ++ky)
        for (int kx = -2; kx <= 2; ++kx) {
          if (j == i && kx == 0 && ky == 0) continue;
          const Vec2 d0 = r0[j] + Vec2(kx * box0.lx + ky * box0.offset, ky * box0.ly) - r0[i];
          if (d0.norm() >= cutoff) continue;
          before.push_back(d0);
          after.push_back(r1[j] + Vec2(kx * box0.lx + ky * (box0.offset + offset_change), ky * box0.ly) - r1[i]);
        }
    Mat2 X = Mat2::Zero(), Y = Mat2::Zero();
    for (std::size_t b = 0; b < before.size(); ++b) {
      X += after[b] * before[b].transpose();
      Y += before[b] * before[b].transpose();
    }
    const Mat2 F = X * Y.inverse();
    double sum = 0;
    for (std::size_t b = 0; b < before.size(); ++b) sum += (after[b] - F * before[b]).squaredNorm();
    out.push_back({sum, int(before.size()), F});
  }
  return out;
}

std::vector<Vec2> displacement_field(const std::vector<Vec2>& r, const Mat2& A, const Vec2& centre, const Vec2& shift) {
  std::vector<Vec2> u;
  for (const Vec2& p : r) u.push_back((A - Mat2::Identity()) * (p - centre) + shift);
  return u;
}

}  // namespace

TEST(D2min, KnownAnswerOfFalkLangerNeighbourhood) {
  // Grain 0 with neighbours (±1, 0), (0, ±1); simple shear γ = 0.1 plus (0, 0.05) on (1, 0).
  const Box box{10, 10, true, 3.0};
  const std::vector<Vec2> r = {{5, 5}, {6, 5}, {4, 5}, {5, 6}, {5, 4}};
  std::vector<Vec2> u;
  for (const Vec2& p : r) u.push_back(Vec2(0.1 * (p.y() - 5), 0));
  u[1].y() += 0.05;
  const D2min d = compute_d2min(r, box, u, 0.0, 1.2);
  ASSERT_EQ(d.value.size(), 5u);
  EXPECT_EQ(d.neighbours[0], 4);
  EXPECT_EQ(d.valid[0], 1);
  EXPECT_NEAR(d.value[0], 1.25e-3, 1e-15);
  EXPECT_NEAR(d.per_neighbour[0], 3.125e-4, 1e-16);
  const Mat2 expected = (Mat2() << 1, 0.1, 0.025, 1).finished();
  EXPECT_LT((d.F[0] - expected).cwiseAbs().maxCoeff(), 1e-14) << d.F[0];
  // The outer grains see only grain 0 (their mutual distance √2 > 1.2): flagged, not 0.
  for (int i = 1; i < 5; ++i) {
    EXPECT_EQ(d.neighbours[i], 1);
    EXPECT_EQ(d.valid[i], 0);
    EXPECT_TRUE(std::isnan(d.value[i]));
    EXPECT_TRUE(std::isnan(d.per_neighbour[i]));
    EXPECT_TRUE(d.F[i].array().isNaN().all());
  }
}

TEST(D2min, AffineMapsRotationsAndTranslationsGiveZero) {
  Rng rng(23);
  const Box box{60, 60, true, 0.37 * 60};
  // Away from the boundary: a general affine map is not compatible with the periodic images.
  const std::vector<Vec2> r = jittered_lattice(rng, 20, 20, 20, 20);
  const double c = std::cos(0.7), s = std::sin(0.7);
  const std::vector<Mat2> maps = {(Mat2() << c, -s, s, c).finished(), (Mat2() << 1.2, 0.3, -0.4, 0.9).finished(),
                                  (Mat2() << 1, 0.8, 0, 1).finished(), Mat2::Identity()};
  for (const Mat2& A : maps) {
    SCOPED_TRACE(::testing::Message() << "A = " << A.reshaped().transpose());
    const D2min d = compute_d2min(r, box, displacement_field(r, A, Vec2(31, 27), Vec2(3.3, -7.1)), 0.0, 2.0);
    for (std::size_t i = 0; i < r.size(); ++i) {
      ASSERT_EQ(d.valid[i], 1) << "grain " << i;
      EXPECT_GE(d.neighbours[i], 2);
      EXPECT_LT(std::abs(d.value[i]), 1e-20) << "grain " << i;
      EXPECT_LT((d.F[i] - A).cwiseAbs().maxCoeff(), 1e-12) << "grain " << i;
    }
  }
}

TEST(D2min, NonAffineDisplacementIsPositive) {
  // A single grain moved off the affine field: it and its neighbours see D²min > 0.
  Rng rng(5);
  const Box box{40, 40, true, 0};
  const std::vector<Vec2> r = jittered_lattice(rng, 10, 10, 20, 20);
  std::vector<Vec2> u = displacement_field(r, (Mat2() << 1, 0.05, 0, 1).finished(), Vec2(20, 20), Vec2::Zero());
  u[210] += Vec2(0.1, -0.05);
  const D2min d = compute_d2min(r, box, u, 0.0, 2.0);
  EXPECT_GT(d.value[210], 1e-4);
  int positive = 0;
  for (std::size_t i = 0; i < r.size(); ++i) positive += d.value[i] > 1e-12;
  EXPECT_EQ(positive, d.neighbours[210] + 1);
}

TEST(D2min, TooFewOrCollinearNeighboursAreFlaggedNaN) {
  const Box box{20, 20, true, 0};
  // A row of 5 grains (every neighbourhood collinear) and one isolated grain.
  std::vector<Vec2> r;
  for (int i = 0; i < 5; ++i) r.push_back(Vec2(3 + i, 5));
  r.push_back(Vec2(15, 15));
  const std::vector<Vec2> u(r.size(), Vec2(0.01, 0.02));
  const D2min d = compute_d2min(r, box, u, 0.0, 2.5);
  const std::vector<int> expected_neighbours = {2, 3, 4, 3, 2, 0};
  for (std::size_t i = 0; i < r.size(); ++i) {
    SCOPED_TRACE("grain " + std::to_string(i));
    EXPECT_EQ(d.neighbours[i], expected_neighbours[i]);
    EXPECT_EQ(d.valid[i], 0);
    EXPECT_TRUE(std::isnan(d.value[i]));
    EXPECT_TRUE(std::isnan(d.per_neighbour[i]));
    EXPECT_TRUE(d.F[i].array().isNaN().all());
  }
  // Bending the row by 0.01 makes the neighbourhoods of the inner grains regular again.
  r[1].y() += 0.01;
  r[3].y() -= 0.01;
  const D2min bent = compute_d2min(r, box, u, 0.0, 2.5);
  EXPECT_EQ(bent.valid[2], 1);
  EXPECT_NEAR(bent.value[2], 0.0, 1e-20);
}

// Lees–Edwards: grains moved exactly affinely by the shear of the box (plus a translation
// in y that carries a third of them through the sheared boundary), stored wrapped in 16
// frames: D²min = 0 for every grain, F = the shear, whether the offset wraps past lx/2, past
// lx or backwards, and with the shear centred anywhere in y.
TEST(D2minLeesEdwards, AffineShearGivesZeroThroughWrappedFrames) {
  Rng rng(77);
  const Box box0{12, 10, true, 0.3 * 12};
  const std::vector<Vec2> r0 = jittered_lattice(rng, 0, 0, 12, 10);
  const double cutoff = 2.0;
  const ReferenceBonds bonds = reference_bonds(r0, box0, cutoff);
  std::vector<bool> straddles(r0.size(), false);
  for (std::size_t i = 0; i < r0.size(); ++i)
    for (auto b = bonds.start[i]; b < bonds.start[i + 1]; ++b) straddles[i] = straddles[i] || bonds.row[b] != 0;
  ASSERT_GT(std::count(straddles.begin(), straddles.end(), true), 20);

  for (double strain : {0.05, 0.5, 1.3, -0.05})
    for (double y0 : {0.0, 3.7})
      for (double lift : {0.35, -0.35}) {
        SCOPED_TRACE(::testing::Message() << "strain " << strain << ", y0 " << y0 << ", lift " << lift);
        Motion motion{strain, y0, Vec2(0.4, lift * box0.ly), {}};
        const StoredRun run = store(r0, box0, motion, 16);
        const std::vector<StoredFrame> frames = run.frames();
        const Unwrapped u = unwrap_displacements(frames, run.rate);
        EXPECT_NEAR(u.offset_change, strain * box0.ly, 1e-12);
        int crossed = 0;
        for (std::size_t i = 0; i < r0.size(); ++i) {
          EXPECT_LT((u.displacement[i] - (run.truth.back()[i] - r0[i])).norm(), 1e-12) << "grain " << i;
          crossed += std::abs(run.truth.back()[i].y() - run.position.back()[i].y()) > 1;
        }
        EXPECT_GT(crossed, int(r0.size()) / 5);

        const D2min d = compute_d2min(r0, box0, u.displacement, u.offset_change, cutoff);
        const Mat2 shear = (Mat2() << 1, strain, 0, 1).finished();
        std::ostringstream bad;
        int n_bad = 0, n_bad_inside = 0;  // inside: no bond through the sheared boundary
        for (std::size_t i = 0; i < r0.size(); ++i)
          if (!(d.valid[i] == 1 && std::abs(d.value[i]) < 1e-20 && (d.F[i] - shear).cwiseAbs().maxCoeff() < 1e-12)) {
            n_bad_inside += !straddles[i];
            if (++n_bad <= 5)
              bad << " grain " << i << " (y " << r0[i].y() << (straddles[i] ? ", straddling" : "") << "): D2min "
                  << d.value[i] << ";";
          }
        EXPECT_EQ(n_bad, 0) << n_bad_inside << " of them inside;" << bad.str();
      }
}

// The all-images definition against the library on a non-affine field, through wrapped
// frames at strains whose offset wraps forwards and backwards.
TEST(D2minLeesEdwards, AgreesWithAllImagesBruteForce) {
  Rng rng(2024);
  const Box box0{9, 8, true, 0.8 * 9};
  const std::vector<Vec2> r0 = jittered_lattice(rng, 0, 0, 9, 8);
  for (double strain : {0.3, -0.7, 1.3}) {
    SCOPED_TRACE(::testing::Message() << "strain " << strain);
    Motion motion{strain, 2.0, Vec2(-0.3, -0.4 * box0.ly), {}};
    for (std::size_t i = 0; i < r0.size(); ++i)
      motion.noise.push_back(Vec2(rng.uniform(-0.15, 0.15), rng.uniform(-0.15, 0.15)));
    const StoredRun run = store(r0, box0, motion, 12);
    const std::vector<StoredFrame> frames = run.frames();
    const Unwrapped u = unwrap_displacements(frames, run.rate);
    const D2min d = compute_d2min(r0, box0, u.displacement, u.offset_change, 1.7);
    const std::vector<Brute> brute = brute_d2min(r0, run.truth.back(), box0, strain * box0.ly, 1.7);
    double largest = 0;
    for (std::size_t i = 0; i < r0.size(); ++i) {
      ASSERT_EQ(d.neighbours[i], brute[i].neighbours) << "grain " << i;
      ASSERT_EQ(d.valid[i], 1) << "grain " << i;
      EXPECT_NEAR(d.value[i], brute[i].value, 1e-10 * brute[i].value) << "grain " << i;
      EXPECT_LT((d.F[i] - brute[i].F).cwiseAbs().maxCoeff(), 1e-10) << "grain " << i;
      EXPECT_NEAR(d.per_neighbour[i], brute[i].value / brute[i].neighbours, 1e-10 * brute[i].value);
      largest = std::max(largest, brute[i].value);
    }
    EXPECT_GT(largest, 1e-3);  // the field is non-affine: the comparison is not 0 against 0
  }
}

TEST(D2minBadInput, RaggedArraysAreRefused) {
  const Box box{10, 10, true, 0};
  const std::vector<Vec2> r = {{1, 1}, {2, 1}, {1, 2}};
  EXPECT_THROW(compute_d2min(r, box, std::vector<Vec2>(2, Vec2::Zero()), 0.0, 1.5), std::invalid_argument);
  const ReferenceBonds bonds = reference_bonds(r, box, 1.5);
  EXPECT_THROW(compute_d2min(bonds, std::vector<Vec2>(4, Vec2::Zero()), 0.0), std::invalid_argument);

  const std::vector<Vec2> fewer = {{1, 1}, {2, 1}};
  const std::vector<StoredFrame> frames = {{r, box, 0.0}, {fewer, box, 1.0}};
  try {
    unwrap_displacements(frames, 0.0);
    FAIL() << "ragged frames accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("frame 1"), std::string::npos) << e.what();
  }
}

TEST(D2minBadInput, JumpOfHalfACellIsRefusedNamingTheGrain) {
  const Box box{10, 10, true, 0};
  const std::vector<Vec2> a = {{1, 1}, {2, 1}, {1, 2}, {5, 5}};
  std::vector<Vec2> b = a;
  b[3] += Vec2(4, 4);  // 5.66 from its old place, and its nearest image as far
  const std::vector<StoredFrame> frames = {{a, box, 0.0}, {a, box, 1.0}, {b, box, 2.0}};
  try {
    unwrap_displacements(frames, 0.0);
    FAIL() << "a jump of more than half a cell was accepted";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("grain 3"), std::string::npos) << what;
    EXPECT_NE(what.find("frame 2"), std::string::npos) << what;
  }
  b[3] = a[3] + Vec2(3, 3);  // 4.24: still below half the cell
  const std::vector<StoredFrame> near = {{a, box, 0.0}, {b, box, 1.0}};
  EXPECT_NEAR(unwrap_displacements(near, 0.0).displacement[3].x(), 3.0, 1e-12);
}

TEST(D2minBadInput, InconsistentBoxesAndParametersAreRefused) {
  const Box box{10, 10, true, 2.0};
  const std::vector<Vec2> r = {{1, 1}, {2, 1}, {1, 2}};
  // The offset after Δt = 1 at γ̇ = 0.1 must be 2 + 0.1·10·1 = 3.
  Box next = box;
  next.offset = 3.0;
  EXPECT_NO_THROW(unwrap_displacements(std::vector<StoredFrame>{{r, box, 0.0}, {r, next, 1.0}}, 0.1));
  EXPECT_THROW(unwrap_displacements(std::vector<StoredFrame>{{r, box, 0.0}, {r, next, 1.0}}, -0.1),
               std::invalid_argument);
  EXPECT_THROW(unwrap_displacements(std::vector<StoredFrame>{{r, next, 1.0}, {r, box, 0.0}}, 0.1),
               std::invalid_argument);  // time decreases
  Box wider = box;
  wider.lx = 11;
  EXPECT_THROW(unwrap_displacements(std::vector<StoredFrame>{{r, box, 0.0}, {r, wider, 0.0}}, 0.0),
               std::invalid_argument);
  Box open = box;
  open.periodic_y = false;
  EXPECT_THROW(reference_bonds(r, open, 1.5), std::invalid_argument);
  EXPECT_THROW(reference_bonds(r, box, 5.0), std::invalid_argument);  // two images in range
  EXPECT_THROW(reference_bonds(r, box, 0.0), std::invalid_argument);
  EXPECT_THROW(reference_bonds({{1, 1}, {2, 10.5}}, box, 1.5), std::invalid_argument);  // not wrapped
  EXPECT_THROW(compute_d2min(r, box, {{0, 0}, {NAN, 0}, {0, 0}}, 0.0, 1.5), std::invalid_argument);
}
