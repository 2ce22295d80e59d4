#include "dynamics/engine.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>
#include <utility>

#include <omp.h>

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>

#include "core/error.hpp"
#include "dynamics/branch_free.hpp"
#include "dynamics/capacity.hpp"
#include "dynamics/contact_law.hpp"
#include "neighbours/cell_list.hpp"

namespace granflow {

namespace {

// Width of the sweep tiles in cell columns (≈ 8 largest diameters): narrow enough that a
// few unsettled contacts keep little else busy, wide enough to hold a few dozen contacts.
constexpr int kTileColumns = 8;

// Row flags of the frictionless sweeps: still corrected by Υ or more; carrying P_n > 0.
constexpr std::uint8_t kHot = 1, kBearing = 2;

std::uint64_t pair_key(int i, int j) { return (std::uint64_t(std::uint32_t(i)) << 32) | std::uint32_t(j); }

template <class T>
std::size_t bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

// resize() under fit_capacity(); the contents are refilled by the caller.
template <class T>
void refill(std::vector<T>& v, std::size_t n) {
  fit_capacity(v, n);
  v.resize(n);
}

void require(bool ok, const std::string& what) {
  if (!ok) throw UsageError(what);
}

void validate(const GrainState& s, const Box& box, double rate, const Material& m, const SolverSettings& set, double dt,
              const Vec2& gravity) {
  const std::size_t n = s.size();
  require(n > 0, "no grains");
  require(n < (std::size_t(1) << 30), "more than 2^30 grains");
  require(s.velocity.size() == n && s.orientation.size() == n && s.angular_velocity.size() == n &&
              s.radius.size() == n && s.mass.size() == n && s.fixed.size() == n,
          "grain arrays have inconsistent lengths");
  require(std::isfinite(box.lx) && box.lx > 0 && std::isfinite(box.offset), "box width must be positive");
  require(!box.periodic_y || (std::isfinite(box.ly) && box.ly > 0), "box height must be positive");
  require(std::isfinite(rate), "shear rate must be finite");
  require(box.periodic_y || rate == 0, "shear needs a box periodic in y (Lees–Edwards)");
  require(std::isfinite(dt) && dt > 0, "time step must be positive");
  require(std::fabs(rate) * dt < 0.5, "strain step |rate·dt| must be below 0.5");
  require(m.restitution >= 0 && m.restitution <= 1, "restitution must lie in [0, 1]");
  require(m.tangential_restitution >= -1 && m.tangential_restitution <= 1,
          "tangential restitution must lie in [-1, 1]");
  require(m.friction >= 0 && std::isfinite(m.friction), "friction must be finite and >= 0");
  require(set.tolerance > 0 && std::isfinite(set.tolerance), "solver tolerance must be positive");
  require(set.max_iterations > 0, "solver max_iterations must be positive");
  require(set.alert_distance >= 0 && std::isfinite(set.alert_distance), "alert distance must be >= 0");
  require(set.skin >= 0 && std::isfinite(set.skin), "pair-list skin must be >= 0");
  require(set.threads >= 1, "solver threads must be >= 1");
  require(gravity.allFinite(), "gravity must be finite");
  for (std::size_t i = 0; i < n; ++i) {
    const std::string at = " (grain " + std::to_string(i) + ")";
    require(s.position[i].allFinite() && s.velocity[i].allFinite() && std::isfinite(s.orientation[i]) &&
                std::isfinite(s.angular_velocity[i]),
            "non-finite grain state" + at);
    require(std::isfinite(s.radius[i]) && s.radius[i] > 0, "radius must be positive" + at);
    require(std::isfinite(s.mass[i]) && s.mass[i] > 0, "mass must be positive" + at);
  }
}

}  // namespace

Engine::Engine(GrainState state, Box box, double rate, Material material, SolverSettings settings, double dt,
               Vec2 gravity)
    : state_(std::move(state)), box_(box), rate_(rate), dt_(dt), material_(material), settings_(settings),
      gravity_(gravity) {
  validate(state_, box_, rate_, material_, settings_, dt_, gravity_);
  const std::size_t n = state_.size();
  double diameter_sum = 0;
  for (std::size_t i = 0; i < n; ++i) {
    max_radius_ = std::max(max_radius_, state_.radius[i]);
    diameter_sum += 2 * state_.radius[i];
  }
  const double mean_diameter = diameter_sum / double(n);
  alert_min_ = settings_.alert_distance > 0 ? settings_.alert_distance : 0.01 * mean_diameter;
  skin_ = settings_.skin > 0 ? settings_.skin : 0.3 * mean_diameter;
  tile_margin_ = 0.1 * mean_diameter;
  const double cutoff = 2 * max_radius_ + alert_min_;
  require(box_.lx >= 2 * cutoff && (!box_.periodic_y || box_.ly >= 2 * cutoff),
          "box smaller than two contact-search cutoffs (2·R_max + alert distance)");
  for (std::size_t i = 0; i < n; ++i) box_.wrap(state_.position[i], state_.velocity[i], rate_);
  bodies_.resize(n);
  body_of_.resize(n);
  detect(false);
}

// Candidate pairs of the current state, sorted by (i, j), from the pair list (rebuilt
// if it might miss one); also measures the largest overlap. moved: the grains have
// moved since the last call.
void Engine::detect(bool moved) {
  const std::size_t n = state_.size();
  // max |ṽ| = √(max |ṽ|²), as fluctuating_velocity() computes ṽ.
  double vmax2 = 0;
#pragma omp parallel for num_threads(settings_.threads) if (settings_.threads > 1) schedule(static) reduction(max \
                                                                                                              : vmax2)
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& v = state_.velocity[i];
    const double vx = v.x() - rate_ * (state_.position[i].y() - 0.5 * box_.ly);
    vmax2 = std::max(vmax2, vx * vx + v.y() * v.y());
  }
  const double vmax = std::sqrt(vmax2);
  // Relative velocity of two grains within the cutoff: fluctuations plus the shear across
  // at most one cutoff (and gravity against a fixed grain); factor 2 for safety, since
  // the post-step velocities are not known yet.
  vrel_ = 2 * vmax + std::fabs(rate_) * (2 * max_radius_ + alert_min_) + dt_ * gravity_.norm();
  alert_ = std::max(alert_min_, 2 * dt_ * vrel_);
  const double cutoff = 2 * max_radius_ + alert_;
  if (box_.lx < 2 * cutoff || (box_.periodic_y && box_.ly < 2 * cutoff))
    throw RuntimeFailure("grains move too fast for the box: contact-search cutoff " + std::to_string(cutoff) +
                         " exceeds half the box");

  if (moved) {
    // The step moved grain i by dt·v_i = dt·(ṽ_i + γ̇(y_i − Ly/2)x̂), y_i before the move,
    // so the separation d of a pair changed by dt·(ṽ_i − ṽ_j + γ̇·d_y·x̂). vmax is measured
    // after the move: before it |ṽ| ≤ vmax·(1 + |γ̇|dt). While a pair closes in from the
    // list's reach to the alert distance, |d_y| ≤ 2R_max + reach + 2·dt·v.
    const double v = vmax * (1 + std::fabs(rate_) * dt_);
    drift_ += dt_ * (2 * v + std::fabs(rate_) * (2 * max_radius_ + reach_ + 2 * dt_ * v));
  }
  // Relative margin: gaps are compared with round-off.
  report_.pairs_rebuilt = !(drift_ < reach_ - alert_ - 1e-9 * reach_);
  if (report_.pairs_rebuilt) rebuild_pairs();

  // Candidates change little from step to step: room for an eighth more than last time.
  const std::size_t last = candidates_.size();
  candidates_.clear();
  fit_capacity(candidates_, last + last / 8);
  double overlap = 0;
  const int threads = settings_.threads;
  constexpr std::size_t block = 8192;
  if (threads == 1 || pairs_.size() <= block) {
    overlap = select_candidates(0, pairs_.size(), candidates_);
  } else {
    // Blocks of pairs filtered in parallel, each into its thread's buffer, and appended in
    // order as soon as the blocks before it are: only one block per thread is held twice.
    const std::ptrdiff_t blocks = std::ptrdiff_t((pairs_.size() + block - 1) / block);
    candidate_blocks_.resize(threads);
#pragma omp parallel num_threads(threads) reduction(max : overlap)
    {
      std::vector<Candidate>& found = candidate_blocks_[omp_get_thread_num()];
#pragma omp for ordered schedule(static, 1)
      for (std::ptrdiff_t b = 0; b < blocks; ++b) {
        found.clear();
        overlap = std::max(overlap, select_candidates(b * block, std::min(pairs_.size(), (b + 1) * block), found));
#pragma omp ordered
        candidates_.insert(candidates_.end(), found.begin(), found.end());
      }
    }
  }
  // Growth by doubling (past last + last/8) leaves up to half unused.
  if (candidates_.capacity() > candidates_.size() + candidates_.size() / 2 + 64) candidates_.shrink_to_fit();
  overlap_ = overlap;
}

// Appends the pairs first … last − 1 of the list whose gap is below the alert distance;
// returns their largest overlap.
double Engine::select_candidates(std::size_t first, std::size_t last, std::vector<Candidate>& out) const {
  const Vec2* position = state_.position.data();
  const double* radius = state_.radius.data();
  const double lx = box_.lx, ly = box_.ly, offset = box_.offset;
  // Box::minimum_image and the image index k, by reciprocals instead of divisions: the
  // rounded quotients differ only for separations within an ulp of half the box, where
  // no pair is ever a candidate.
  const double to_x = 1 / lx, to_y = 1 / ly;
  const double alert = alert_;
  double overlap = 0;
  // Whether a listed pair is a candidate is as good as random (about half are): each pair
  // is written to a small buffer and kept by advancing its end or not, without a jump.
  // Non-candidates have gap ≥ alert ≥ 0, so taking max(overlap, −gap) over all is the same.
  constexpr std::size_t kChunk = 256;
  Candidate found[kChunk];
  for (std::size_t chunk = first; chunk < last; chunk += kChunk) {
    const std::size_t end = std::min(last, chunk + kChunk);
    std::size_t kept = 0;
    for (std::size_t p = chunk; p < end; ++p) {
      const auto [i, j] = pairs_[p];
      double dx = position[i].x() - position[j].x(), dy = position[i].y() - position[j].y();
      int k = 0;
      if (box_.periodic_y) {
        k = round_to_int(dy * to_y);
        dy -= k * ly;
        dx -= k * offset;
      }
      dx -= lx * round_to_int(dx * to_x);
      const double gap = std::sqrt(dx * dx + dy * dy) - radius[i] - radius[j];
      overlap = std::max(overlap, -gap);
      found[kept] = Candidate(i, j, k, dx, dy);
      kept += gap < alert;
    }
    out.insert(out.end(), found, found + kept);
  }
  return overlap;
}

// Pairs whose gap is below alert + skin (as far as the box allows), sorted by (i, j).
void Engine::rebuild_pairs() {
  const std::size_t n = state_.size();
  const double half = 0.5 * (box_.periodic_y ? std::min(box_.lx, box_.ly) : box_.lx);
  reach_ = std::max(alert_, std::min(alert_ + skin_, half - 2 * max_radius_));
  drift_ = 0;
  CellList cells;
  cells.build(state_.position, box_, 2 * max_radius_ + reach_);
  // Threads search bands of cell rows, each into its own list; the order in which the
  // pairs are found does not matter, since they are sorted below.
  const int threads = cells.rows() >= 4 * settings_.threads ? settings_.threads : 1;
  std::vector<std::vector<std::array<int, 2>>> found(threads);
#pragma omp parallel num_threads(threads) if (threads > 1)
  {
    const int t = omp_get_thread_num();
    cells.for_each_pair_in_rows(cells.rows() * t / threads, cells.rows() * (t + 1) / threads, state_.position,
                                [&](int i, int j, const Vec2& d) {
                                  if (state_.fixed[i] && state_.fixed[j]) return;
                                  if (d.norm() - state_.radius[i] - state_.radius[j] >= reach_) return;
                                  found[t].push_back({std::min(i, j), std::max(i, j)});
                                });
  }
  // Counting sort by i, then by j within each (short) bucket: O(pairs).
  bucket_.assign(n + 1, 0);
  std::size_t total = 0;
  for (const auto& band : found) {
    total += band.size();
    for (const auto& p : band) ++bucket_[p[0] + 1];
  }
  for (std::size_t i = 0; i < n; ++i) bucket_[i + 1] += bucket_[i];
  pairs_.resize(total);
  for (const auto& band : found)
    for (const auto& p : band) pairs_[bucket_[p[0]]++] = p;
  // bucket_[i] now holds the end of bucket i, the start of bucket i + 1.
  int begin = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const int end = bucket_[i];
    std::sort(pairs_.begin() + begin, pairs_.begin() + end);
    begin = end;
  }
}

// Internal numbering of the grains by cells of a grid, tile by tile (see below) and row by
// row within a tile, so that the bodies of neighbouring grains, and the contacts between
// them, lie close together in memory, and each tile's rows are swept in one stretch.
void Engine::order_bodies() {
  const int n = int(state_.size());
  double y0 = 0, height = box_.ly;
  if (!box_.periodic_y) {
    const auto [lo, hi] = std::minmax_element(state_.position.begin(), state_.position.end(),
                                              [](const Vec2& a, const Vec2& b) { return a.y() < b.y(); });
    y0 = lo->y();
    height = hi->y() - lo->y();
  }
  const double h = 2 * max_radius_;
  const int columns = std::max(1, int(box_.lx / h));
  const int rows = std::clamp(int(height / h), 1, std::max(1, 2 * n / columns));  // at most ~2n cells
  const double to_column = columns / box_.lx, to_row = height > 0 ? rows / height : 0.0;

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
  const double reach = 2 * max_radius_ + std::max(alert_, tile_margin_);
  const double row_height = height > 0 ? height / rows : h;
  const int per_strip = std::max(1, int(std::ceil(reach / row_height)));
  strips_ = rows / per_strip;
  strips_ = strips_ > 1 ? strips_ - strips_ % 2 : 1;
  const int per_tile = std::max(kTileColumns, int(std::ceil(reach / (box_.lx / columns))));
  tiles_ = strips_ > 1 ? columns / per_tile : 1;
  if (tiles_ < 3) tiles_ = 1;
  auto strip_of_row = [&](int row) { return std::min(row / per_strip, strips_ - 1); };
  auto block_of_column = [&](int column) { return std::min(column / per_tile, tiles_ - 1); };
  // Cells ranked tile by tile, row by row within a tile: counted per cell, then summed in
  // that order.
  bucket_.assign(std::size_t(columns) * rows, 0);
  scratch_.resize(n);
  const int threads = settings_.threads;
#pragma omp parallel for num_threads(threads) if (threads > 1) schedule(static)
  for (int g = 0; g < n; ++g) {
    const Vec2& r = state_.position[g];
    const int column = std::clamp(int(r.x() * to_column), 0, columns - 1);
    const int row = std::clamp(int((r.y() - y0) * to_row), 0, rows - 1);
    scratch_[g] = row * columns + column;
  }
  for (int g = 0; g < n; ++g) ++bucket_[scratch_[g]];
  int next = 0;
  for (int strip = 0; strip < strips_; ++strip)
    for (int block = 0; block < tiles_; ++block)
      for (int row = strip * per_strip; row < rows && strip_of_row(row) == strip; ++row)
        for (int column = block * per_tile; column < columns && block_of_column(column) == block; ++column) {
          int& cell = bucket_[std::size_t(row) * columns + column];
          const int count = cell;
          cell = next;
          next += count;
        }
  strip_of_.resize(n);
  block_of_.resize(n);
  for (int g = 0; g < n; ++g) body_of_[g] = bucket_[scratch_[g]]++;
#pragma omp parallel for num_threads(threads) if (threads > 1) schedule(static)
  for (int g = 0; g < n; ++g) {
    const int b = body_of_[g];
    strip_of_[b] = strip_of_row(scratch_[g] / columns);
    block_of_[b] = block_of_column(scratch_[g] % columns);
  }
}

// The tile of a contact between bodies a and b: the strip of the lower one and the column
// block of the left one (across the periodic x boundary, the last). A contact thus moves only
// bodies of its own tile and of the tiles above and to the right of it, and a body is moved
// only by contacts of its own tile and of the tiles below and to the left, so a tile needs
// a sweep only if it or one of its eight neighbours moved. Across the periodic y boundary
// (a contact through the image k ≠ 0), where the Lees–Edwards offset breaks the columns'
// alignment, the tile of the upper body (see sweep()).
int Engine::row_tile(int a, int b, int image) const {
  if (image != 0) {
    const int upper = image > 0 ? a : b;
    return strip_of_[upper] * tiles_ + block_of_[upper];
  }
  const int ba = block_of_[a], bb = block_of_[b];
  const int block = std::abs(ba - bb) <= 1 ? std::min(ba, bb) : std::max(ba, bb);
  return std::min(strip_of_[a], strip_of_[b]) * tiles_ + block;
}

// Local problems of every candidate: normals, bounds, reduced masses, warm start. Rows are
// stored in sweep order: by tile, ties in candidate order.
void Engine::build_rows() {
  const std::size_t count = candidates_.size();
  auto tile = [&](const Candidate& k) { return row_tile(body_of_[k.i], body_of_[k.j()], k.image()); };
  const int tiles = strips_ * tiles_;
  // Each candidate's tile (in parallel: it reads scattered bodies), then its row: counting
  // sort by tile, ties in candidate order.
  refill(row_of_, count);
#pragma omp parallel for num_threads(settings_.threads) if (settings_.threads > 1) schedule(static)
  for (std::size_t c = 0; c < count; ++c) row_of_[c] = tile(candidates_[c]);
  bucket_.assign(tiles + 1, 0);
  for (std::size_t c = 0; c < count; ++c) ++bucket_[row_of_[c] + 1];
  for (int t = 0; t < tiles; ++t) bucket_[t + 1] += bucket_[t];
  tile_rows_.assign(bucket_.begin(), bucket_.end());
  for (std::size_t c = 0; c < count; ++c) row_of_[c] = bucket_[row_of_[c]]++;
  refill(rows_, count);
  refill(tangent_, material_.friction > 0 ? count : 0);
  refill(row_bodies_, count);
  refill(row_age_, count);
  // Chunks of candidates, each with its own cursor into the previous step's memory (same
  // sort order), so that threads can share them.
  constexpr std::ptrdiff_t chunk = 4096;
  const std::ptrdiff_t chunks = (std::ptrdiff_t(count) + chunk - 1) / chunk;
#pragma omp parallel for num_threads(settings_.threads) if (settings_.threads > 1) schedule(static)
  for (std::ptrdiff_t h = 0; h < chunks; ++h) {
    const std::size_t first = h * chunk, last = std::min(count, std::size_t(first + chunk));
    std::size_t p =
        std::lower_bound(prev_key_.begin(), prev_key_.end(), pair_key(candidates_[first].i, candidates_[first].j())) -
        prev_key_.begin();
    for (std::size_t c = first; c < last; ++c) build_row(c, p);
  }
}

// Row of candidate c, warm-started from the previous step's memory found at or after p.
void Engine::build_row(std::size_t c, std::size_t& p) {
  const double e = material_.restitution, et = material_.tangential_restitution;
  const Candidate& k = candidates_[c];
  const int i = k.i, j = k.j();
  const double dist = std::sqrt(k.dx * k.dx + k.dy * k.dy);
  const double nx = k.dx / dist, ny = k.dy / dist;
  const double ri = state_.radius[i], rj = state_.radius[j];
  const double gap = dist - ri - rj;
  const double shift = k.image() * rate_ * box_.ly;  // x-velocity of j's image relative to j
  const double dvx = state_.velocity[i].x() - state_.velocity[j].x() - shift;
  const double dvy = state_.velocity[i].y() - state_.velocity[j].y();
  const double un = dvx * nx + dvy * ny;
  const double ut = -dvx * ny + dvy * nx - (ri * state_.angular_velocity[i] + rj * state_.angular_velocity[j]);
  // Touching or predicted to touch, or not, is as good as random: both bounds are computed
  // and one is picked without a jump. e·max(0, −u_n) is −e·u_n for u_n < 0, else +0.
  const bool touching = (gap <= 0) | (gap + dt_ * un <= 0);
  const double bn = pick(touching, e * positive_part(-un), -gap / dt_);
  const double wi = state_.fixed[i] ? 0.0 : 1.0 / state_.mass[i];
  const double wj = state_.fixed[j] ? 0.0 : 1.0 / state_.mass[j];

  Row& r = rows_[row_of_[c]];
  r.i = body_of_[i];
  r.j = body_of_[j];
  row_bodies_[row_of_[c]] = {state_.fixed[i] ? -1 : r.i, state_.fixed[j] ? -1 : r.j};
  r.nx = nx;
  r.ny = ny;
  // The solver works on raw velocity differences: move the image shift into the bounds.
  r.bn = bn + shift * nx;
  r.inv_w = 1.0 / (wi + wj);
  r.pn = 0;
  double pt = 0;
  row_age_[c] = 0;
  const std::uint64_t key = pair_key(i, j);
  while (p < prev_key_.size() && prev_key_[p] < key) ++p;
  if (p < prev_key_.size() && prev_key_[p] == key) {
    // Warm start from the recorded forces, so that a run restarted from a stored
    // frame (forces, not impulses, are on file) starts from the very same numbers.
    // Without friction no P_t is kept: a frictional state's tangential forces are dropped
    // (the frictionless sweep never changes P_t, and would apply a kept one every step).
    r.pn = prev_fn_[p] * dt_;
    pt = prev_ft_[p] * dt_;
    row_age_[c] = prev_age_[p];
  }
  if (material_.friction > 0) tangent_[row_of_[c]] = {et * ut - shift * ny, pt};
}

// Free velocities, plus the warm-start impulses.
void Engine::load_bodies() {
  const std::size_t n = state_.size();
#pragma omp parallel for num_threads(settings_.threads) if (settings_.threads > 1) schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    Body& b = bodies_[body_of_[i]];
    const bool mobile = !state_.fixed[i];
    b.vx = state_.velocity[i].x() + (mobile ? dt_ * gravity_.x() : 0.0);
    b.vy = state_.velocity[i].y() + (mobile ? dt_ * gravity_.y() : 0.0);
    b.spin = state_.radius[i] * state_.angular_velocity[i];
    b.inv_mass = mobile ? 1.0 / state_.mass[i] : 0.0;
  }
  const bool friction = material_.friction > 0;
  for (std::size_t c = 0; c < rows_.size(); ++c) {
    const Row& r = rows_[c];
    const double pt = friction ? tangent_[c].pt : 0.0;
    if (r.pn == 0 && pt == 0) continue;
    Body& a = bodies_[r.i];
    Body& b = bodies_[r.j];
    const double px = r.pn * r.nx - pt * r.ny, py = r.pn * r.ny + pt * r.nx;
    a.vx += a.inv_mass * px;
    a.vy += a.inv_mass * py;
    a.spin -= 2 * a.inv_mass * pt;
    b.vx -= b.inv_mass * px;
    b.vy -= b.inv_mass * py;
    b.spin -= 2 * b.inv_mass * pt;
  }
}

namespace {

// See solve_cluster(). 10 also stops the blow-up but undoes most solves in a pile coming to
// rest (5° incline: 899 sweeps per step instead of 63, steps at the sweep cap); 100 and 1000
// undo none there.
constexpr double kClusterSolveGrowth = 100;

// Clusters of at least this many active rows are factorised by all threads together.
constexpr int kSharedClusterRows = 2000;

// The items q of [0, count) for which keep(q) holds, gathered in order by threads: counted
// by chunks, then, after resize(kept), place(q, k) for each with its rank k among the kept.
// The ranks, hence the result, do not depend on the number of threads.
template <class Keep, class Resize, class Place>
void gather(std::ptrdiff_t count, int threads, std::vector<std::size_t>& chunk_start, Keep keep, Resize resize,
            Place place) {
  constexpr std::ptrdiff_t chunk = 4096;
  const std::ptrdiff_t chunks = (count + chunk - 1) / chunk;
  chunk_start.assign(chunks + 1, 0);
  // One chunk is not worth waking the threads for (twice).
  const bool parallel = threads > 1 && chunks > 1;
#pragma omp parallel for num_threads(threads) if (parallel) schedule(static)
  for (std::ptrdiff_t h = 0; h < chunks; ++h) {
    std::size_t kept = 0;
    for (std::ptrdiff_t q = h * chunk; q < std::min(count, (h + 1) * chunk); ++q) kept += keep(q);
    chunk_start[h + 1] = kept;
  }
  for (std::ptrdiff_t h = 0; h < chunks; ++h) chunk_start[h + 1] += chunk_start[h];
  resize(chunk_start[chunks]);
  // The items kept are listed first, by advancing the list's end or not: a jump on keep(q),
  // which is as good as random (which rows bear, say), would mispredict.
#pragma omp parallel for num_threads(threads) if (parallel) schedule(static)
  for (std::ptrdiff_t h = 0; h < chunks; ++h) {
    std::ptrdiff_t kept[chunk];
    std::ptrdiff_t n = 0;
    for (std::ptrdiff_t q = h * chunk; q < std::min(count, (h + 1) * chunk); ++q) {
      kept[n] = q;
      n += keep(q);
    }
    for (std::ptrdiff_t t = 0; t < n; ++t) place(kept[t], chunk_start[h] + std::size_t(t));
  }
}

}  // namespace

// The rows the sweeps visit: contacts carrying a warm-start impulse and pairs whose normal
// constraint, at the free velocities, is violated or within v_rel (the bound on relative
// velocities) of binding. Any other row keeps P = 0 unless the impulses of the step change
// its u_n by more than that; check() then finds it and lets it join.
void Engine::select_working_set() {
  const std::ptrdiff_t count = std::ptrdiff_t(rows_.size());
  in_work_.resize(count);
  row_flags_.resize(count);
  unknown_.assign(count, -1);
  moved_.assign(std::size_t(strips_) * tiles_, 1);
  touched_.assign(std::size_t(strips_) * tiles_, 1);  // the first check of a step is everywhere
  tile_residual_.resize(touched_.size());
#pragma omp parallel for num_threads(settings_.threads) if (settings_.threads > 1) schedule(static)
  for (std::ptrdiff_t c = 0; c < count; ++c) {
    const Row& r = rows_[c];
    const Body &a = bodies_[r.i], &b = bodies_[r.j];
    const double un = (a.vx - b.vx) * r.nx + (a.vy - b.vy) * r.ny;
    // Bitwise, not short-circuit: both tests are near random, and a jump would mispredict.
    in_work_[c] = (r.pn > 0) | (un - r.bn < vrel_);
    row_flags_[c] = std::uint8_t(kHot | (r.pn > 0) * kBearing);
  }
  group_working_set();
}

// Lists the working set tile by tile, rows ascending within each: the order of the sweeps
// (rows are stored tile by tile, so that is ascending row order).
void Engine::group_working_set() {
  const int tiles = strips_ * tiles_;
  const std::size_t size = std::count(in_work_.begin(), in_work_.end(), std::uint8_t(1));
  // Every row is written and kept by advancing the end or not (membership is near random):
  // one slot more for the last row written.
  work_.resize(size + 1);
  work_start_.resize(tiles + 1);
  int* const work = work_.data();
  const std::uint8_t* const in_work = in_work_.data();
  int q = 0;
  for (int t = 0; t < tiles; ++t) {
    work_start_[t] = q;
    for (int c = tile_rows_[t]; c < tile_rows_[t + 1]; ++c) {
      work[q] = c;
      q += in_work[c];
    }
  }
  work_start_[tiles] = q;
  work_.resize(size);
}

// Which of the two strips next to each other across the periodic y boundary, the first and
// the last, have a flagged tile (none without that boundary or with a single strip).
Engine::EdgeFlags Engine::edge_flags(const std::vector<std::uint8_t>& flags) const {
  if (!box_.periodic_y || strips_ < 2) return {};
  auto strip_flagged = [&](int strip) {
    const auto first = flags.begin() + std::ptrdiff_t(strip) * tiles_;
    return std::find(first, first + tiles_, std::uint8_t(1)) != first + tiles_;
  };
  return {strip_flagged(0), strip_flagged(strips_ - 1)};
}

// Whether tile (strip, block) or one of its eight neighbours is flagged. Across the periodic
// y boundary the Lees–Edwards offset shifts the columns: the tiles of the first strip count
// any flagged tile of the last strip as a neighbour, and those of the last strip, whose
// contacts across it reach grains of the first strip anywhere, any flagged tile of either
// (edges: edge_flags(flags), taken once by the caller).
bool Engine::near_flagged(const std::vector<std::uint8_t>& flags, int strip, int block, EdgeFlags edges) const {
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

// One Gauss–Seidel sweep over the working set, strips of one parity (in parallel), then of
// the other, tile by tile along each strip; backwards, the exact reverse. Returns the
// largest correction made. The frictionless sweep also counts status changes (P_n > 0 or
// not) and active rows, and marks the rows still corrected by Υ or more, for the cluster
// solves.
//
// Each task sweeps two strips of the same parity, a row of one then a row of the other.
// They share no grain, so the result is that of sweeping them one after the other, bit for
// bit; but a row's update waits for the previous row's (they usually share a grain), and
// the other strip's row fills that wait.
template <bool Friction>
double Engine::sweep(bool forward, double upsilon) {
  const double mu = material_.friction;
  const int* start = work_start_.data();
  std::uint8_t* moved = moved_.data();
  std::uint8_t* touched = touched_.data();
  const int threads = settings_.threads, strips = strips_, tiles = tiles_;
  const int dir = forward ? 1 : -1;
  double worst = 0;
  int changes = 0, active = 0;
  std::int64_t visits = 0;
  // Where a strip's sweep stands: its next tile (step), the rows left in the current tile
  // (q up to end, by dir) and that tile's largest correction and counts so far.
  struct Cursor {
    int strip, step = 0, tile = 0, q = 0, end = 0;
    double worst = 0;
    int changes = 0, active = 0;
  };
  for (int half = 0; half < 2; ++half) {
    const int parity = forward ? half : 1 - half;
    const int count = (strips - parity + 1) / 2;  // strips of this parity
    // The edge strips as of the start of this half: the same for any number of threads.
    const EdgeFlags edges = edge_flags(moved_);
#pragma omp parallel for num_threads(threads) if (threads > 1) schedule(dynamic, 1) \
    reduction(max : worst) reduction(+ : changes, active, visits)
    for (int t = 0; t < (count + 1) / 2; ++t) {
      // Pointers are locals, and so are the counters in the loops below: the byte stores to
      // the flags may alias anything, and would otherwise send them through memory on every row.
      const int* const work_rows = work_.data();
      Row* const row_data = rows_.data();
      Tangent* const tangent_data = tangent_.data();
      Body* const body_data = bodies_.data();
      std::uint8_t* const row_flags = row_flags_.data();
      // The local solve of row work_rows[q]; folds its correction and counts into a tile's.
      auto update = [&](int q, double& tile_worst, int& tile_changes, int& tile_active) {
        const int c = work_rows[q];
        Row& r = row_data[c];
        Body& a = body_data[r.i];
        Body& b = body_data[r.j];
        if constexpr (Friction) {
          Tangent& g = tangent_data[c];
          const auto [pn, pt] = local_solve(r, g, a, b, mu);
          const double dpn = pn - r.pn, dpt = pt - g.pt;
          // Compare before dividing: the division is only needed for a new maximum.
          const double d = std::max(std::fabs(dpn), 3 * std::fabs(dpt));
          if (d > tile_worst * r.inv_w) tile_worst = d / r.inv_w;
          r.pn = pn;
          g.pt = pt;
          const double px = dpn * r.nx - dpt * r.ny, py = dpn * r.ny + dpt * r.nx;
          a.vx += a.inv_mass * px;
          a.vy += a.inv_mass * py;
          a.spin -= 2 * a.inv_mass * dpt;
          b.vx -= b.inv_mass * px;
          b.vy -= b.inv_mass * py;
          b.spin -= 2 * b.inv_mass * dpt;
        } else {
          // μ = 0: P_t stays 0 and the spins never change.
          const double pn = normal_impulse(r, a, b);
          const double dpn = pn - r.pn;
          const double d = std::fabs(dpn);
          if (d > tile_worst * r.inv_w) tile_worst = d / r.inv_w;
          // Whether a row bears flips about as often as not: integer arithmetic on the bits
          // of P_n ≥ +0 (never −0: max(0, x) gives +0) instead of branches that mispredict.
          const int bears = bearing(pn), bore = bearing(r.pn);
          tile_changes += bears ^ bore;
          tile_active += bears;
          row_flags[c] = std::uint8_t((d >= upsilon * r.inv_w) * kHot | bears * kBearing);
          r.pn = pn;
          const double px = dpn * r.nx, py = dpn * r.ny;
          a.vx += a.inv_mass * px;
          a.vy += a.inv_mass * py;
          b.vx -= b.inv_mass * px;
          b.vy -= b.inv_mass * py;
        }
      };
      // Moves the cursor to the next tile with rows to sweep, settling the empty ones on the
      // way; false at the end of the strip. A tile whose corrections and whose neighbours'
      // (the last time each was swept) all stayed below Υ has settled; check() confirms it
      // at the end.
      auto next_tile = [&](Cursor& k) {
        while (k.step < tiles) {
          const int block = forward ? k.step : tiles - 1 - k.step;
          ++k.step;
          if (!near_flagged(moved_, k.strip, block, edges)) continue;
          k.tile = k.strip * tiles + block;
          touched[k.tile] = 1;
          const int first = start[k.tile], last = start[k.tile + 1];
          if (first == last) {
            moved[k.tile] = 0;
            continue;
          }
          k.q = forward ? first : last - 1;
          k.end = forward ? last : first - 1;
          k.worst = 0;
          k.changes = k.active = 0;
          visits += last - first;
          return true;
        }
        return false;
      };
      auto finish_tile = [&](const Cursor& k) {
        moved[k.tile] = k.worst >= upsilon;
        worst = std::max(worst, k.worst);
        changes += k.changes;
        active += k.active;
      };
      Cursor a{parity + 4 * t}, b{parity + 4 * t + 2};
      bool more_a = next_tile(a), more_b = b.strip < strips && next_tile(b);
      while (more_a && more_b) {
        const int n = std::min(dir * (a.end - a.q), dir * (b.end - b.q));
        int qa = a.q, qb = b.q;
        double worst_a = a.worst, worst_b = b.worst;
        int changes_a = a.changes, changes_b = b.changes, active_a = a.active, active_b = b.active;
        for (int k = 0; k < n; ++k, qa += dir, qb += dir) {
          update(qa, worst_a, changes_a, active_a);
          update(qb, worst_b, changes_b, active_b);
        }
        a.q = qa;
        a.worst = worst_a;
        a.changes = changes_a;
        a.active = active_a;
        b.q = qb;
        b.worst = worst_b;
        b.changes = changes_b;
        b.active = active_b;
        if (a.q == a.end) {
          finish_tile(a);
          more_a = next_tile(a);
        }
        if (b.q == b.end) {
          finish_tile(b);
          more_b = next_tile(b);
        }
      }
      // The strip left alone.
      for (Cursor* k : {&a, &b}) {
        for (bool more = k == &a ? more_a : more_b; more; more = next_tile(*k)) {
          double tile_worst = k->worst;
          int tile_changes = k->changes, tile_active = k->active;
          for (int q = k->q; q != k->end; q += dir) update(q, tile_worst, tile_changes, tile_active);
          k->worst = tile_worst;
          k->changes = tile_changes;
          k->active = tile_active;
          finish_tile(*k);
        }
      }
    }
  }
  status_changes_ = changes;
  active_rows_ = active;
  report_.contact_updates += visits;
  return worst;
}

// Largest correction a local solve would still make on the current velocities, over every
// row (everywhere) or over the rows outside the working set; rows outside it that would
// change join it. The tiles of rows found off by Υ or more, or joining, are swept next.
// Everywhere means every row whose residual may have changed since the last such check:
// a row's residual depends on its impulse and its bodies' velocities only, which only the
// rows of its own or the eight neighbouring tiles change (see row_tile()), so tiles away
// from any tile swept or solved since then keep the residuals found then (all below Υ,
// or their tiles would have been swept), and the largest of those counts as found again.
// The rows outside the working set there all had a zero correction (else they would have
// joined), and still have: the check outside it skips those tiles as well.
double Engine::check(bool everywhere) {
  const double mu = material_.friction, upsilon = settings_.tolerance / dt_;
  std::uint8_t* moved = moved_.data();
  const int strips = strips_, tiles = tiles_;
  const EdgeFlags edges = edge_flags(touched_);
  double worst = 0;
  std::int64_t visited = 0;
  bool joined = false;
#pragma omp parallel for num_threads(settings_.threads) if (settings_.threads > 1) schedule(dynamic, 16) \
    reduction(max : worst) reduction(+ : visited) reduction(|| : joined)
  for (int tile = 0; tile < strips * tiles; ++tile) {
    const int strip = tile / tiles, block = tile % tiles;
    if (!near_flagged(touched_, strip, block, edges)) {
      if (everywhere) worst = std::max(worst, tile_residual_[tile]);  // unchanged since found
      continue;
    }
    double tile_worst = 0;
    bool tile_moved = false;
    for (int c = tile_rows_[tile]; c < tile_rows_[tile + 1]; ++c) {
      const bool in = in_work_[c];
      if (!everywhere && in) continue;
      const Row& r = rows_[c];
      const Body &a = bodies_[r.i], &b = bodies_[r.j];
      const double corr =
          mu > 0 ? correction(r, tangent_[c], local_solve(r, tangent_[c], a, b, mu)) : normal_correction(r, a, b);
      tile_worst = std::max(tile_worst, corr);
      ++visited;
      // Bitwise, not short-circuit: corr > 0 is as good as random, joining is rare.
      const bool joins = (corr > 0) & !in;
      if (joins) {
        in_work_[c] = 1;
        row_flags_[c] = kHot;  // P_n = 0 outside the working set
        joined = true;
      }
      tile_moved |= joins | (corr >= upsilon);
    }
    if (tile_moved) moved[tile] = 1;
    if (everywhere) tile_residual_[tile] = tile_worst;
    worst = std::max(worst, tile_worst);
  }
  if (everywhere && !settings_.full_checks) std::fill(touched_.begin(), touched_.end(), 0);
  report_.contact_updates += visited;
  if (joined) group_working_set();
  return worst;
}

// One exact solve, for the current active set, of each cluster of active contacts (joined
// through mobile grains) in which some contact was still corrected by Υ or more in the last
// sweep: W_AA·ΔP_A = b_A − u_A on its normal rows (μ = 0), then P_A ← max(0, P_A + ΔP_A).
// Clusters share no mobile grain, so threads take them in any order.
void Engine::solve_clusters() {
  const int n = int(bodies_.size());
  // The active rows (all in the working set) with their mobile bodies (−1 for a fixed one,
  // which couples nothing), read once: the passes below touch only this compact copy.
  const int threads = settings_.threads;
  gather(
      std::ptrdiff_t(work_.size()), threads, chunk_start_,
      [&](std::ptrdiff_t q) { return (row_flags_[work_[q]] & kBearing) != 0; },
      [&](std::size_t kept) {
        fit_capacity(active_, kept);
        active_.resize(kept);
      },
      [&](std::ptrdiff_t q, std::size_t k) {
        const int c = work_[q];
        active_[k] = {c, row_bodies_[c][0], row_bodies_[c][1], 0};
      });
  // Clusters by union–find over bodies; a row's cluster is that of one of its mobile bodies.
  // Links always go from the larger root to the smaller, so every cluster's root ends as its
  // smallest body whatever the order of the unions: the threads unite rows concurrently
  // (a link is a compare-and-swap that fails if its root was linked meanwhile; path halving
  // only ever points a body at one of its ancestors) and the result is the same for any N.
  const std::ptrdiff_t rows = std::ptrdiff_t(active_.size());
  cluster_.resize(n);
  cluster_id_.resize(n);
#pragma omp parallel for num_threads(threads) if (threads > 1) schedule(static)
  for (int b = 0; b < n; ++b) {
    cluster_[b] = b;
    cluster_id_[b] = -2;
  }
  // Relaxed atomics (plain moves on x86) and the compare-and-swap only with threads: a
  // locked instruction per link would cost one thread a quarter of the union–find.
  const bool shared = threads > 1;
  auto parent = [&](int b) { return std::atomic_ref<int>(cluster_[b]); };
  auto root = [&](int b) {
    for (int p; (p = parent(b).load(std::memory_order_relaxed)) != b;) {
      const int grandparent = parent(p).load(std::memory_order_relaxed);
      parent(b).store(grandparent, std::memory_order_relaxed);
      b = grandparent;
    }
    return b;
  };
  auto link = [&](int x, int y) {  // x > y; false if x is no longer a root
    if (!shared) return cluster_[x] = y, true;
    return parent(x).compare_exchange_strong(x, y, std::memory_order_relaxed);
  };
#pragma omp parallel for num_threads(threads) if (shared) schedule(static)
  for (std::ptrdiff_t q = 0; q < rows; ++q) {
    const ActiveRow& a = active_[q];
    if (a.i < 0 || a.j < 0) continue;
    for (;;) {
      const int x = root(a.i), y = root(a.j);
      if (x == y || link(std::max(x, y), std::min(x, y))) break;
    }
  }
  // Hot clusters are numbered in order of appearance; cluster_id_ per root: −2 cold, −1 hot.
#pragma omp parallel for num_threads(threads) if (threads > 1) schedule(static)
  for (std::ptrdiff_t q = 0; q < rows; ++q) {
    ActiveRow& a = active_[q];
    a.cluster = root(a.i >= 0 ? a.i : a.j);
    if (row_flags_[a.c] & kHot) std::atomic_ref<int>(cluster_id_[a.cluster]).store(-1, std::memory_order_relaxed);
  }
  int clusters = 0;
  std::size_t kept = 0;
  for (ActiveRow a : active_) {
    int& id = cluster_id_[a.cluster];
    if (id == -2) continue;
    if (id == -1) id = clusters++;
    a.cluster = id;
    active_[kept++] = a;
  }
  active_.resize(kept);

  // The rows of each cluster (in sweep order), and of each mobile body.
  cluster_start_.assign(clusters + 1, 0);
  body_start_.assign(n + 1, 0);
  for (const ActiveRow& a : active_) {
    ++cluster_start_[a.cluster + 1];
    if (a.i >= 0) ++body_start_[a.i + 1];
    if (a.j >= 0) ++body_start_[a.j + 1];
  }
  for (int k = 0; k < clusters; ++k) cluster_start_[k + 1] += cluster_start_[k];
  for (int b = 0; b < n; ++b) body_start_[b + 1] += body_start_[b];
  refill(cluster_rows_, active_.size());
  refill(body_rows_, body_start_[n]);
  bucket_.assign(cluster_start_.begin(), cluster_start_.end() - 1);
  degree_.assign(n, 0);  // ends as the number of rows at each body
  for (const ActiveRow& a : active_) {
    cluster_rows_[bucket_[a.cluster]++] = a.c;
    if (a.i >= 0) body_rows_[body_start_[a.i] + degree_[a.i]++] = a.c;
    if (a.j >= 0) body_rows_[body_start_[a.j] + degree_[a.j]++] = a.c;
  }

  // Clusters go to the threads whole, largest first; one that holds more than a thread's
  // share of all the rows (and at least kSharedClusterRows: the percolating cluster) would
  // keep one thread busy while the others wait, so it is factorised by all threads together
  // instead, after the others. The clusters are independent: the same result either way.
  cluster_scratch_.resize(threads);
  large_.clear();
  cluster_order_.clear();
  const int shared_at = std::max(kSharedClusterRows, int(active_.size()) / threads);
  auto size = [&](int k) { return cluster_start_[k + 1] - cluster_start_[k]; };
  for (int k = 0; k < clusters; ++k) {
    report_.largest_cluster = std::max(report_.largest_cluster, size(k));
    (threads > 1 && size(k) >= shared_at ? large_ : cluster_order_).push_back(k);
  }
  if (threads > 1)
    std::stable_sort(cluster_order_.begin(), cluster_order_.end(), [&](int a, int b) { return size(a) > size(b); });
#pragma omp parallel for num_threads(threads) if (threads > 1) schedule(dynamic)
  for (std::size_t q = 0; q < cluster_order_.size(); ++q)
    solve_cluster(cluster_order_[q], cluster_scratch_[omp_get_thread_num()], 1);
  for (int k : large_) solve_cluster(k, cluster_scratch_[0], threads);
  // Velocities changed only at the bodies of these rows: their tiles are swept next (the
  // rows are in ascending order, as in the working set, and rows are stored tile by tile).
  int tile = 0;
  for (const ActiveRow& a : active_) {
    while (tile_rows_[tile + 1] <= a.c) ++tile;
    moved_[tile] = touched_[tile] = 1;
  }
}

// The solve of cluster k (see solve_clusters()). Returns false when its factor would be too
// large to pay off (nothing changed) or its result was undone (impulses restored exactly,
// velocities up to round-off).
bool Engine::solve_cluster(int k, ClusterScratch& w, int threads) {
  const int* members = cluster_rows_.data() + cluster_start_[k];
  const int m = cluster_start_[k + 1] - cluster_start_[k];
  // Numbering (w.order[u] = row of unknown u): first peel leaves, bodies left with a single
  // unnumbered row, since such a row eliminates without fill-in (clusters are mostly trees);
  // then the loops that remain, in sweep order.
  w.order.clear();
  auto number = [&](int c) {
    unknown_[c] = int(w.order.size());
    w.order.push_back(c);
  };
  // (Bodies from the compact row_bodies_, −1 for a fixed one.)
  w.peel.clear();
  for (int q = 0; q < m; ++q)
    for (int b : row_bodies_[members[q]])
      if (b >= 0 && degree_[b] == 1) w.peel.push_back(b);
  for (std::size_t q = 0; q < w.peel.size(); ++q) {
    const int b = w.peel[q];
    for (int p = body_start_[b]; p < body_start_[b + 1]; ++p) {
      const int c = body_rows_[p];
      if (unknown_[c] >= 0) continue;
      number(c);
      const auto [i, j] = row_bodies_[c];
      const int other = i == b ? j : i;
      if (other >= 0 && --degree_[other] == 1) w.peel.push_back(other);
    }
  }
  const int peeled = int(w.order.size());
  for (int q = 0; q < m; ++q)
    if (unknown_[members[q]] < 0) number(members[q]);

  // Pivots below 1e-9 of their diagonal: a redundant contact (pinned). If the loops in sweep
  // order fill the factor in beyond 4 nonzeros per matrix entry, they are reordered by
  // approximate minimum degree; beyond 8 even then, Gauss–Seidel alone is cheaper.
  auto factor = [&](std::size_t fill) {
    assemble_cluster(w, threads);
    return w.ldl.factor(m, w.start, w.row, w.value, 1e-9, fill * w.row.size() + 64, threads);
  };
  bool factored = factor(4);
  if (!factored && peeled < m) {
    order_loops(w, peeled);
    factored = factor(8);
  }
  bool accepted = false;
  if (factored) {
    w.ldl.solve(w.rhs);
    // The step is undone if it multiplies the cluster's largest local correction by more
    // than kClusterSolveGrowth. When the active set is hyperstatic (jammed, ν near ν_c)
    // its equations can be inconsistent and near-singular: the solve then returns huge
    // self-stresses whose clamping at P_n = 0 would throw the velocities off by orders of
    // magnitude. (A good step may raise the correction a little: the clamping.)
    const double before = cluster_residual(w, threads);
    auto set_normal_impulse = [&](int c, double pn) {
      Row& r = rows_[c];
      apply_normal_impulse(r, pn - r.pn);
      r.pn = pn;
      row_flags_[c] = std::uint8_t((row_flags_[c] & kHot) | bearing(pn) * kBearing);
    };
    for (int u = 0; u < m; ++u) {
      const double pn = rows_[w.order[u]].pn, solved = positive_part(pn + w.rhs[u]);
      w.rhs[u] = pn;  // kept for an undo
      set_normal_impulse(w.order[u], solved);
    }
    accepted = cluster_residual(w, threads) <= kClusterSolveGrowth * before;  // false for NaN too
    if (!accepted)
      for (int u = m - 1; u >= 0; --u) set_normal_impulse(w.order[u], w.rhs[u]);
  }
  for (int c : w.order) unknown_[c] = -1;
  return accepted;
}

// Adds the normal impulse dpn of row r to its bodies' velocities. Fixed bodies (shared
// between clusters) are left alone: they would not move anyway.
void Engine::apply_normal_impulse(const Row& r, double dpn) {
  for (const auto& [body, sign] : {std::pair(r.i, 1.0), std::pair(r.j, -1.0)}) {
    Body& b = bodies_[body];
    if (b.inv_mass == 0) continue;
    b.vx += sign * b.inv_mass * dpn * r.nx;
    b.vy += sign * b.inv_mass * dpn * r.ny;
  }
}

// Largest velocity correction a local solve would make on the cluster's rows (μ = 0).
double Engine::cluster_residual(const ClusterScratch& w, int threads) const {
  const std::ptrdiff_t m = std::ptrdiff_t(w.order.size());
  auto row = [&](std::ptrdiff_t u) {
    const Row& r = rows_[w.order[u]];
    return normal_correction(r, bodies_[r.i], bodies_[r.j]);
  };
  double worst = 0;
  // Most clusters are small and solved by one thread: there, even a parallel region that
  // runs on one thread (≈ 0.2 µs) would cost more than the rows.
  if (threads <= 1) {
    for (std::ptrdiff_t u = 0; u < m; ++u) worst = std::max(worst, row(u));
    return worst;
  }
#pragma omp parallel for num_threads(threads) schedule(static) reduction(max : worst)
  for (std::ptrdiff_t u = 0; u < m; ++u) worst = std::max(worst, row(u));
  return worst;
}

// The cluster's matrix, upper triangle by columns in unknown order, and right-hand side:
// W_ab = Σ over the mobile bodies shared by rows a and b of s_a·s_b·(n̂_a·n̂_b)/m, with
// s = +1 for the body of grain i, −1 for that of grain j; b_a − u_a at the current velocities.
// With threads, columns are counted, then filled in parallel (same entries, same order).
void Engine::assemble_cluster(ClusterScratch& w, int threads) const {
  const int m = int(w.order.size());
  w.start.assign(m + 1, 0);
  w.rhs.resize(m);
  // Calls emit(row, value) for each entry of column u and below (the upper triangle holds
  // those with row ≤ u), top to bottom as found; sets rhs[u].
  auto column = [&](int u, auto&& emit) {
    const Row& a = rows_[w.order[u]];
    const Body &bi = bodies_[a.i], &bj = bodies_[a.j];
    w.rhs[u] = a.bn - ((bi.vx - bj.vx) * a.nx + (bi.vy - bj.vy) * a.ny);
    for (int body : {a.i, a.j}) {
      const double inv_mass = bodies_[body].inv_mass;
      if (inv_mass == 0) continue;
      const double sa = body == a.i ? 1.0 : -1.0;
      for (int p = body_start_[body]; p < body_start_[body + 1]; ++p) {
        const int other = unknown_[body_rows_[p]];
        const Row& b = rows_[body_rows_[p]];
        const double sb = body == b.i ? 1.0 : -1.0;
        emit(other, sa * sb * (a.nx * b.nx + a.ny * b.ny) * inv_mass);  // kept for other ≤ u
      }
    }
  };
  if (threads <= 1) {
    // Every entry found is written, and kept by advancing the end or not: whether a
    // neighbour's unknown comes before u is as good as random, and a jump would mispredict.
    std::size_t bound = 0;
    for (int u = 0; u < m; ++u)
      for (int body : row_bodies_[w.order[u]])
        if (body >= 0) bound += std::size_t(body_start_[body + 1] - body_start_[body]);
    fit_capacity(w.row, bound);
    fit_capacity(w.value, bound);
    w.row.resize(bound);
    w.value.resize(bound);
    int* const row = w.row.data();
    double* const value = w.value.data();
    std::size_t q = 0;
    for (int u = 0; u < m; ++u) {
      column(u, [&](int other, double v) {
        row[q] = other;
        value[q] = v;
        q += other <= u;
      });
      w.start[u + 1] = int(q);
    }
    w.row.resize(q);
    w.value.resize(q);
    return;
  }
#pragma omp parallel for num_threads(threads) schedule(static)
  for (int u = 0; u < m; ++u) column(u, [&](int other, double) { w.start[u + 1] += other <= u; });
  for (int u = 0; u < m; ++u) w.start[u + 1] += w.start[u];
  fit_capacity(w.row, w.start[m]);
  fit_capacity(w.value, w.start[m]);
  w.row.resize(w.start[m]);
  w.value.resize(w.start[m]);
#pragma omp parallel for num_threads(threads) schedule(static)
  for (int u = 0; u < m; ++u) {
    int q = w.start[u];
    column(u, [&](int other, double value) {
      if (other > u) return;
      w.row[q] = other;
      w.value[q++] = value;
    });
  }
}

// Reorders the cluster's unknowns from `first` on (the loops left after peeling) by
// approximate minimum degree (Eigen's AMD) on their coupling pattern.
void Engine::order_loops(ClusterScratch& w, int first) {
  const int q = int(w.order.size()) - first;
  std::vector<Eigen::Triplet<double>> pattern;
  for (int t = 0; t < q; ++t) {
    const Row& a = rows_[w.order[first + t]];
    for (int body : {a.i, a.j}) {
      if (bodies_[body].inv_mass == 0) continue;
      for (int p = body_start_[body]; p < body_start_[body + 1]; ++p) {
        const int u = unknown_[body_rows_[p]] - first;
        if (u >= 0 && u <= t) pattern.emplace_back(t, u, 1.0);
      }
    }
  }
  Eigen::SparseMatrix<double> loops(q, q);
  loops.setFromTriplets(pattern.begin(), pattern.end());
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> order;
  Eigen::AMDOrdering<int>()(loops, order);  // order.indices()[k]: the k-th to eliminate
  w.peel.assign(w.order.begin() + first, w.order.end());
  for (int k = 0; k < q; ++k) {
    const int c = w.peel[order.indices()[k]];
    w.order[first + k] = c;
    unknown_[c] = first + k;
  }
}

void Engine::solve() {
  StepReport& rep = report_;
  rep.iterations = 0;
  rep.contact_updates = 0;
  rep.cluster_solves = 0;
  rep.largest_cluster = 0;
  rep.residual = 0;
  rep.converged = true;
  if (rows_.empty()) return;
  const double upsilon = settings_.tolerance / dt_;
  const bool friction = material_.friction > 0;
  const bool clusters = settings_.cluster_solves && !friction;
  int next_cluster_solve = 2, cluster_wait = 1;
  select_working_set();
  for (int it = 1; it <= settings_.max_iterations; ++it) {
    const bool forward = it % 2 == 1;  // alternate directions: symmetric Gauss–Seidel
    const double worst = friction ? sweep<true>(forward, upsilon) : sweep<false>(forward, upsilon);
    rep.iterations = it;
    if (worst < upsilon) {
      // A sweep's own corrections only bound the residual; confirm on the final velocities,
      // on every candidate.
      const double res = check(true);  // marks the tiles still off
      if (res < upsilon) {
        rep.residual = res * dt_;
        return;
      }
    } else if (clusters && it >= next_cluster_solve && 100 * status_changes_ <= active_rows_) {
      // The active set has (nearly) settled: solve its clusters exactly. While it keeps
      // changing, each solve waits twice as many sweeps as the one before, so that their
      // number stays logarithmic in the sweeps of the step.
      solve_clusters();  // marks the tiles of the rows it solved
      ++rep.cluster_solves;
      next_cluster_solve = it + cluster_wait;
      cluster_wait *= 2;
    } else if (it % 16 == 0) {
      // Rows outside the working set join early, not only when it has converged without them.
      check(false);
    }
  }
  // Out of sweeps; a cluster solve after the last one may still have converged.
  const double res = check(true);
  rep.residual = res * dt_;
  if (res < upsilon) return;
  rep.converged = false;
  ++unconverged_;
}

// Contacts of this step, from the impulses and the (still unchanged) pre-step state, in
// candidate order, written in parallel at their places.
void Engine::record_contacts() {
  const double e = material_.restitution;
  auto resize = [&](std::size_t contacts) {
    auto fit = [&](auto& v) {
      fit_capacity(v, contacts);
      v.resize(contacts);
    };
    fit(records_.pair);
    fit(records_.normal_force);
    fit(records_.tangential_force);
    fit(records_.branch);
    fit(records_.binary_force);
    fit(records_.pre_normal_velocity);
    fit(records_.age);
    fit(prev_key_);
    fit(prev_fn_);
    fit(prev_ft_);
    fit(prev_age_);
    fit(dissipated_);
  };
  auto record = [&](std::ptrdiff_t c, std::size_t q) {
    const Row& r = rows_[row_of_[c]];
    const Candidate& k = candidates_[c];
    const int i = k.i, j = k.j();
    const int age = row_age_[c] + 1;
    const Vec2 n(r.nx, r.ny);
    const Vec2 vi = fluctuating_velocity(state_, box_, rate_, i);
    const Vec2 vj = fluctuating_velocity(state_, box_, rate_, j);
    const double shift = k.image() * rate_ * box_.ly;
    const double un = (state_.velocity[i] - state_.velocity[j]).dot(n) - shift * r.nx;
    const double fn = r.pn / dt_, ft = tangent_.empty() ? 0.0 : tangent_[row_of_[c]].pt / dt_;
    records_.pair[q] = {i, j};
    records_.normal_force[q] = fn;
    records_.tangential_force[q] = ft;
    records_.branch[q] = Vec2(k.dx, k.dy);
    records_.binary_force[q] = (1 + e) * r.inv_w * std::max(0.0, -un) / dt_;
    records_.pre_normal_velocity[q] = {vi.dot(n), vj.dot(n)};
    records_.age[q] = age;
    dissipated_[q] = dissipated(r, c, i, j, shift);
    prev_key_[q] = pair_key(i, j);
    prev_fn_[q] = fn;
    prev_ft_[q] = ft;
    prev_age_[q] = age;
  };
  // Without friction the flags say which rows bear (kBearing exactly when P_n > 0), and
  // they take a byte per row where the rows take a cache line: reading them keeps this
  // pass, in candidate order and not in row order, out of the large rows.
  const bool flagged = material_.friction == 0;
  gather(
      std::ptrdiff_t(candidates_.size()), settings_.threads, chunk_start_,
      [&](std::ptrdiff_t c) { return flagged ? (row_flags_[row_of_[c]] & kBearing) != 0 : rows_[row_of_[c]].pn > 0; },
      resize, record);
  report_.candidates = int(rows_.size());
  report_.contacts = int(records_.size());
  // Summed in candidate order: the same number for any thread count.
  int born = 0;
  double product = 0, lost = 0;
  for (std::size_t q = 0; q < records_.size(); ++q) {
    if (records_.age[q] == 1) {
      ++born;
      product += records_.pre_normal_velocity[q][0] * records_.pre_normal_velocity[q][1];
    }
    lost += dissipated_[q];
  }
  report_.collisions = born;
  report_.collision_velocity_product = product;
  report_.dissipated_energy = lost;
}

// −P·ū of row r (candidate c, grains i and j): ū at the mean of the free velocities (the
// pre-step state, still in state_, plus gravity) and the post-step ones (in bodies_).
double Engine::dissipated(const Row& r, std::size_t c, int i, int j, double shift) const {
  const Body& a = bodies_[r.i];
  const Body& b = bodies_[r.j];
  auto free_v = [&](int g) { return state_.fixed[g] ? state_.velocity[g] : Vec2(state_.velocity[g] + dt_ * gravity_); };
  const Vec2 va = 0.5 * (free_v(i) + Vec2(a.vx, a.vy));
  const Vec2 vb = 0.5 * (free_v(j) + Vec2(b.vx, b.vy));
  const double sa = 0.5 * (state_.radius[i] * state_.angular_velocity[i] + a.spin);
  const double sb = 0.5 * (state_.radius[j] * state_.angular_velocity[j] + b.spin);
  const double ux = va.x() - vb.x() - shift, uy = va.y() - vb.y();
  const double un = ux * r.nx + uy * r.ny;
  const double ut = -ux * r.ny + uy * r.nx - sa - sb;
  const double pt = tangent_.empty() ? 0.0 : tangent_[row_of_[c]].pt;
  return -(r.pn * un + pt * ut);
}

void Engine::store_bodies() {
#pragma omp parallel for num_threads(settings_.threads) if (settings_.threads > 1) schedule(static)
  for (std::size_t i = 0; i < state_.size(); ++i) {
    const Body& b = bodies_[body_of_[i]];
    state_.velocity[i] = Vec2(b.vx, b.vy);
    // Only grains that felt a tangential impulse change ω: s/R would otherwise perturb ω in the last bit.
    if (b.spin != state_.radius[i] * state_.angular_velocity[i]) state_.angular_velocity[i] = b.spin / state_.radius[i];
  }
}

void Engine::advance() {
  if (box_.periodic_y) box_.shift_offset(rate_ * box_.ly * dt_);
  const std::ptrdiff_t n = std::ptrdiff_t(state_.size());
  std::ptrdiff_t bad = n;  // first grain with a non-finite state
#pragma omp parallel for num_threads(settings_.threads) if (settings_.threads > 1) schedule(static) reduction(min : bad)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    state_.position[i] += dt_ * state_.velocity[i];
    state_.orientation[i] += dt_ * state_.angular_velocity[i];
    if (!(state_.position[i].allFinite() && state_.velocity[i].allFinite() &&
          std::isfinite(state_.angular_velocity[i])))
      bad = std::min(bad, i);
    else  // wrapped with the offset at the end of the step: the image the grain moved into
      box_.wrap(state_.position[i], state_.velocity[i], rate_);
  }
  if (bad < n)
    throw RuntimeFailure("non-finite state of grain " + std::to_string(bad) + " at step " + std::to_string(steps_ + 1));
  ++steps_;
}

const StepReport& Engine::step() {
  order_bodies();
  build_rows();
  load_bodies();
  solve();
  record_contacts();
  store_bodies();
  advance();
  detect(true);
  report_.step = steps_;
  report_.max_overlap = overlap_;
  return report_;
}

void Engine::set_threads(int threads) {
  if (threads < 1) throw UsageError("threads must be at least 1");
  settings_.threads = threads;
}

std::size_t Engine::allocated_bytes() const {
  const GrainState& s = state_;
  const ContactRecords& r = records_;
  std::size_t blocks = bytes(candidate_blocks_) + bytes(cluster_scratch_);
  for (const auto& b : candidate_blocks_) blocks += bytes(b);
  for (const ClusterScratch& w : cluster_scratch_)
    blocks += bytes(w.order) + bytes(w.peel) + bytes(w.start) + bytes(w.row) + bytes(w.value) + bytes(w.rhs) +
              w.ldl.allocated_bytes();
  return blocks + bytes(s.position) + bytes(s.velocity) + bytes(s.orientation) + bytes(s.angular_velocity) +
         bytes(s.radius) + bytes(s.mass) + bytes(s.fixed) + bytes(pairs_) + bytes(candidates_) + bytes(bucket_) +
         bytes(scratch_) + bytes(body_of_) + bytes(strip_of_) + bytes(block_of_) + bytes(row_of_) + bytes(bodies_) +
         bytes(rows_) + bytes(tangent_) + bytes(row_bodies_) + bytes(row_age_) + bytes(work_) + bytes(work_start_) +
         bytes(in_work_) + bytes(row_flags_) + bytes(moved_) + bytes(touched_) + bytes(tile_residual_) +
         bytes(tile_rows_) + bytes(active_) + bytes(large_) + bytes(cluster_order_) + bytes(chunk_start_) +
         bytes(cluster_) + bytes(cluster_id_) + bytes(cluster_start_) + bytes(cluster_rows_) + bytes(body_start_) +
         bytes(body_rows_) + bytes(degree_) + bytes(unknown_) + bytes(prev_key_) + bytes(prev_fn_) + bytes(prev_ft_) +
         bytes(prev_age_) + bytes(r.pair) + bytes(r.normal_force) + bytes(r.tangential_force) + bytes(r.branch) +
         bytes(r.binary_force) + bytes(r.pre_normal_velocity) + bytes(r.age) + bytes(dissipated_);
}

ContactMemory Engine::memory() const {
  ContactMemory m;
  for (std::size_t c = 0; c < prev_key_.size(); ++c)
    m.pair.push_back({int(prev_key_[c] >> 32), int(prev_key_[c] & 0xffffffffu)});
  m.normal_force = prev_fn_;
  m.tangential_force = prev_ft_;
  m.age = prev_age_;
  return m;
}

void Engine::restore(std::int64_t step, const ContactMemory& memory) {
  const std::size_t c = memory.pair.size();
  require(step >= 0, "restored step counter must be >= 0");
  require(memory.normal_force.size() == c && memory.tangential_force.size() == c && memory.age.size() == c,
          "contact memory arrays have inconsistent lengths");
  std::vector<std::uint64_t> keys(c);
  for (std::size_t k = 0; k < c; ++k) {
    const auto [i, j] = memory.pair[k];
    require(i >= 0 && i < j && std::size_t(j) < state_.size(), "contact memory: bad pair");
    require(std::isfinite(memory.normal_force[k]) && memory.normal_force[k] >= 0 &&
                std::isfinite(memory.tangential_force[k]) && memory.age[k] >= 1,
            "contact memory: bad force or age");
    keys[k] = pair_key(i, j);
    require(k == 0 || keys[k - 1] < keys[k], "contact memory: pairs not sorted or repeated");
  }
  steps_ = step;
  prev_key_ = std::move(keys);
  prev_fn_ = memory.normal_force;
  prev_ft_ = memory.tangential_force;
  prev_age_ = memory.age;
}

}  // namespace granflow
