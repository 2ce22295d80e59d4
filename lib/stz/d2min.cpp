#include "stz/d2min.hpp"
#include "core/format.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "neighbours/cell_list.hpp"

namespace granflow::stz {

namespace {

void check_box(const Box& box, const std::string& what) {
  if (!box.periodic_y) throw std::invalid_argument(what + ": the box is not periodic in y (D²min needs simple shear)");
  if (!(std::isfinite(box.lx) && box.lx > 0 && std::isfinite(box.ly) && box.ly > 0))
    throw std::invalid_argument(what + ": the box size must be positive and finite");
  if (!(std::isfinite(box.offset) && box.offset >= 0 && box.offset < box.lx))
    throw std::invalid_argument(what + ": the Lees–Edwards offset " + format_number(box.offset, 17) +
                                " is not in [0, lx)");
}

}  // namespace

ReferenceBonds reference_bonds(const std::vector<Vec2>& positions, const Box& box, double cutoff) {
  check_box(box, "reference frame");
  if (!(std::isfinite(cutoff) && cutoff > 0 && cutoff < 0.5 * std::min(box.lx, box.ly)))
    throw std::invalid_argument("cutoff " + format_number(cutoff, 17) +
                                " must be positive and below half the smaller box side (" +
                                format_number(0.5 * std::min(box.lx, box.ly), 17) + ")");
  if (positions.size() > std::size_t(std::numeric_limits<std::int32_t>::max()))
    throw std::invalid_argument("too many grains");
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const Vec2& r = positions[i];
    if (!(r.allFinite() && r.x() >= 0 && r.x() < box.lx && r.y() >= 0 && r.y() < box.ly))
      throw std::invalid_argument("reference frame: grain " + std::to_string(i) + " is not in the primary cell");
  }

  struct Pair {
    std::int32_t i, j, row;
    Vec2 d;  // r_i − (image of j in row `row` relative to i)
  };
  std::vector<Pair> pairs;
  pairs.reserve(8 * positions.size());
  CellList cells;
  cells.build(positions, box, cutoff);
  cells.for_each_pair(positions, [&](int i, int j, const Vec2& d) {
    // minimum_image(r_i − r_j) subtracted k·(offset, ly) and a multiple of lx: recover k.
    const int row = int(std::lround((positions[i].y() - positions[j].y() - d.y()) / box.ly));
    pairs.push_back({std::int32_t(i), std::int32_t(j), std::int32_t(row), d});
  });

  ReferenceBonds bonds;
  const std::size_t n = positions.size();
  bonds.start.assign(n + 1, 0);
  for (const Pair& p : pairs) {
    ++bonds.start[std::size_t(p.i) + 1];
    ++bonds.start[std::size_t(p.j) + 1];
  }
  for (std::size_t i = 0; i < n; ++i) bonds.start[i + 1] += bonds.start[i];
  const std::size_t total = std::size_t(bonds.start[n]);
  bonds.neighbour.resize(total);
  bonds.row.resize(total);
  bonds.bond.resize(total);
  std::vector<std::int64_t> fill(bonds.start.begin(), bonds.start.end() - 1);
  auto add = [&](std::int32_t from, std::int32_t to, std::int32_t row, const Vec2& d0) {
    const std::size_t b = std::size_t(fill[std::size_t(from)]++);
    bonds.neighbour[b] = to;
    bonds.row[b] = row;
    bonds.bond[b] = d0;
  };
  for (const Pair& p : pairs) {
    add(p.i, p.j, p.row, -p.d);  // from i to j's image in row k
    add(p.j, p.i, -p.row, p.d);  // from j to i's image in row −k
  }
  return bonds;
}

D2min compute_d2min(const ReferenceBonds& bonds, const std::vector<Vec2>& displacement, double offset_change) {
  if (bonds.start.empty() || bonds.start.size() != displacement.size() + 1)
    throw std::invalid_argument("displacements: " + std::to_string(displacement.size()) + " grains, reference frame: " +
                                std::to_string(bonds.start.empty() ? 0 : bonds.start.size() - 1));
  if (!std::isfinite(offset_change)) throw std::invalid_argument("the offset change is not finite");
  for (std::size_t i = 0; i < displacement.size(); ++i)
    if (!displacement[i].allFinite())
      throw std::invalid_argument("displacement of grain " + std::to_string(i) + " is not finite");

  const std::size_t n = displacement.size();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  D2min out;
  out.value.assign(n, nan);
  out.per_neighbour.assign(n, nan);
  out.neighbours.assign(n, 0);
  out.valid.assign(n, 0);
  out.F.assign(n, Mat2::Constant(nan));

  for (std::size_t i = 0; i < n; ++i) {
    const std::int64_t b0 = bonds.start[i], b1 = bonds.start[i + 1];
    out.neighbours[i] = std::int32_t(b1 - b0);
    if (b1 - b0 < 2) continue;
    auto current = [&](std::int64_t b) {
      Vec2 d = bonds.bond[b] + displacement[std::size_t(bonds.neighbour[b])] - displacement[i];
      d.x() += bonds.row[b] * offset_change;
      return d;
    };
    Mat2 X = Mat2::Zero(), Y = Mat2::Zero();
    for (std::int64_t b = b0; b < b1; ++b) {
      const Vec2& d0 = bonds.bond[b];
      X += current(b) * d0.transpose();
      Y += d0 * d0.transpose();
    }
    // Y is symmetric positive semi-definite: λ_max from the trace and λ_min = det/λ_max.
    const double half_trace = 0.5 * (Y(0, 0) + Y(1, 1));
    const double spread = std::hypot(0.5 * (Y(0, 0) - Y(1, 1)), Y(0, 1));
    const double lmax = half_trace + spread;
    const double det = Y(0, 0) * Y(1, 1) - Y(0, 1) * Y(1, 0);
    if (!(lmax > 0) || !(det / lmax > kSingularRatio * lmax)) continue;
    const Mat2 F = X * Y.inverse();
    // Second pass over the residuals: tr Z − tr(X Y⁻¹ Xᵀ) would cancel badly.
    double sum = 0;
    for (std::int64_t b = b0; b < b1; ++b) sum += (current(b) - F * bonds.bond[b]).squaredNorm();
    out.value[i] = sum;
    out.per_neighbour[i] = sum / double(b1 - b0);
    out.valid[i] = 1;
    out.F[i] = F;
  }
  return out;
}

D2min compute_d2min(const std::vector<Vec2>& reference, const Box& box, const std::vector<Vec2>& displacement,
                    double offset_change, double cutoff) {
  if (reference.size() != displacement.size())
    throw std::invalid_argument("reference frame has " + std::to_string(reference.size()) + " grains, displacements " +
                                std::to_string(displacement.size()));
  return compute_d2min(reference_bonds(reference, box, cutoff), displacement, offset_change);
}

Unwrapper::Unwrapper(const StoredFrame& first, double rate, std::string name)
    : first_(first.position.begin(), first.position.end()), unwrapped_(first_), first_box_(first.box),
      last_box_(first.box), rate_(rate), first_time_(first.time), last_time_(first.time), last_name_(std::move(name)) {
  if (!std::isfinite(rate)) throw std::invalid_argument("the shear rate is not finite");
  check_box(first.box, last_name_);
  if (!std::isfinite(first.time)) throw std::invalid_argument(last_name_ + ": the time is not finite");
  for (std::size_t i = 0; i < first_.size(); ++i)
    if (!first_[i].allFinite())
      throw std::invalid_argument(last_name_ + ": the position of grain " + std::to_string(i) + " is not finite");
}

void Unwrapper::add(const StoredFrame& frame, std::string name) {
  const std::size_t n = first_.size();
  const double lx = first_box_.lx, ly = first_box_.ly;
  check_box(frame.box, name);
  if (frame.position.size() != n)
    throw std::invalid_argument(name + " has " + std::to_string(frame.position.size()) +
                                " grains, the first frame has " + std::to_string(n));
  if (frame.box.lx != lx || frame.box.ly != ly)
    throw std::invalid_argument(name + ": the box size differs from the first frame's");
  if (!std::isfinite(frame.time)) throw std::invalid_argument(name + ": the time is not finite");
  if (frame.time < last_time_) throw std::invalid_argument(name + ": the time decreases");
  // The stored offset must be the previous one advanced by γ̇·ly·Δt, modulo lx.
  const double expected = last_box_.offset + rate_ * ly * (frame.time - last_time_);
  const double miss = std::remainder(frame.box.offset - expected, lx);
  if (!(std::abs(miss) <= 1e-6 * lx))
    throw std::invalid_argument(name + ": the Lees–Edwards offset " + format_number(frame.box.offset, 17) +
                                " does not follow from the shear rate " + format_number(rate_, 17) + " (expected " +
                                format_number(expected - lx * std::floor(expected / lx), 17) + ")");
  for (std::size_t i = 0; i < n; ++i)
    if (!frame.position[i].allFinite())
      throw std::invalid_argument(name + ": the position of grain " + std::to_string(i) + " is not finite");

  // Unwrapped positions R: a stored r is R − c·(offset, ly) − m·lx for the grain's image
  // counters (c, m); from frame to frame the nearest such image of the new r continues R.
  // It is the true one whenever the grain moved by less than half of min(lx, ly), since
  // two images differ by at least min(lx, ly). All grains are checked before any moves, so
  // that a refused frame leaves the state as it was.
  const double half_cell = 0.5 * std::min(lx, ly);
  std::vector<Vec2> next(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& r = frame.position[i];
    const Vec2& R = unwrapped_[i];
    const double c = std::round((R.y() - r.y()) / ly);
    const double x = r.x() + c * frame.box.offset;
    next[i] = Vec2(x + lx * std::round((R.x() - x) / lx), r.y() + c * ly);
    if (!((next[i] - R).norm() < half_cell))
      throw std::invalid_argument(name + ": grain " + std::to_string(i) + " moved by " +
                                  format_number((next[i] - R).norm(), 17) + " or more since " + last_name_ +
                                  ", not less than half the cell (" + format_number(half_cell, 17) +
                                  "): its image is ambiguous; store frames more often");
  }
  unwrapped_.swap(next);
  last_box_ = frame.box;
  last_time_ = frame.time;
  last_name_ = std::move(name);
  ++frames_;
}

Unwrapped Unwrapper::result() const {
  Unwrapped out;
  out.displacement.resize(first_.size());
  for (std::size_t i = 0; i < first_.size(); ++i) out.displacement[i] = unwrapped_[i] - first_[i];
  // The images of the last frame were placed with its stored offset: Δδ must agree with the
  // stored offsets modulo lx exactly, and the rate fixes the number of whole turns.
  const double lx = first_box_.lx;
  const double stored = last_box_.offset - first_box_.offset;
  const double drift = rate_ * first_box_.ly * (last_time_ - first_time_);
  out.offset_change = stored + lx * std::round((drift - stored) / lx);
  return out;
}

Unwrapped unwrap_displacements(std::span<const StoredFrame> frames, double rate) {
  if (frames.empty()) throw std::invalid_argument("no frames to unwrap");
  Unwrapper unwrapper(frames.front(), rate);
  for (std::size_t f = 1; f < frames.size(); ++f) unwrapper.add(frames[f], "frame " + std::to_string(f));
  return unwrapper.result();
}

}  // namespace granflow::stz
