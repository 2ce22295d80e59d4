#include "dynamics/engine.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "dynamics/branch_free.hpp"
#include "dynamics/capacity.hpp"
#include "dynamics/contact_law.hpp"
#include "dynamics/parallel.hpp"

namespace granflow {

namespace {

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
  tiling_ = Tiling(0.1 * mean_diameter);
  const double cutoff = 2 * max_radius_ + alert_min_;
  require(box_.lx >= 2 * cutoff && (!box_.periodic_y || box_.ly >= 2 * cutoff),
          "box smaller than two contact-search cutoffs (2·R_max + alert distance)");
  broad_ = BroadPhase(settings_.skin > 0 ? settings_.skin : 0.3 * mean_diameter, max_radius_);
  for (std::size_t i = 0; i < n; ++i) box_.wrap(state_.position[i], state_.velocity[i], rate_);
  contacts_ = ContactRows(n);
  detect(false);
}

// Candidate pairs of the current state (see BroadPhase), at an alert distance set from the
// largest relative velocity. moved: the grains have moved since the last call.
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

  if (moved) broad_.moved(vmax, rate_, dt_);
  report_.pairs_rebuilt = broad_.find(state_, box_, alert_, settings_.threads);
}

// The rows the sweeps visit: contacts carrying a warm-start impulse and pairs whose normal
// constraint, at the free velocities, is violated or within v_rel (the bound on relative
// velocities) of binding. Any other row keeps P = 0 unless the impulses of the step change
// its u_n by more than that; check() then finds it and lets it join.
void Engine::select_working_set() {
  const std::ptrdiff_t count = std::ptrdiff_t(contacts_.rows().size());
  in_work_.resize(count);
  row_flags_.resize(count);
  moved_.assign(std::size_t(tiling_.tiles()), 1);
  touched_.assign(std::size_t(tiling_.tiles()), 1);  // the first check of a step is everywhere
  tile_residual_.resize(touched_.size());
  parallel_for(settings_.threads, count, [&](std::ptrdiff_t c) {
    const Row& r = contacts_.rows()[c];
    const Body &a = contacts_.bodies()[r.i], &b = contacts_.bodies()[r.j];
    const double un = (a.vx - b.vx) * r.nx + (a.vy - b.vy) * r.ny;
    // Bitwise, not short-circuit: both tests are near random, and a jump would mispredict.
    in_work_[c] = (r.pn > 0) | (un - r.bn < vrel_);
    row_flags_[c] = std::uint8_t(kHot | (r.pn > 0) * kBearing);
  });
  group_working_set();
}

// Lists the working set tile by tile, rows ascending within each: the order of the sweeps
// (rows are stored tile by tile, so that is ascending row order).
void Engine::group_working_set() {
  const int tiles = tiling_.tiles();
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
    for (int c = tiling_.first_row(t); c < tiling_.first_row(t + 1); ++c) {
      work[q] = c;
      q += in_work[c];
    }
  }
  work_start_[tiles] = q;
  work_.resize(size);
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
  const int threads = settings_.threads, strips = tiling_.strips(), tiles = tiling_.blocks();
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
    const Tiling::EdgeFlags edges = tiling_.edge_flags(moved_);
#pragma omp parallel for num_threads(threads) if (threads > 1) schedule(dynamic, 1) \
    reduction(max : worst) reduction(+ : changes, active, visits)
    for (int t = 0; t < (count + 1) / 2; ++t) {
      // Pointers are locals, and so are the counters in the loops below: the byte stores to
      // the flags may alias anything, and would otherwise send them through memory on every row.
      const int* const work_rows = work_.data();
      Row* const row_data = contacts_.rows().data();
      Tangent* const tangent_data = contacts_.tangents().data();
      Body* const body_data = contacts_.bodies().data();
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
          if (!tiling_.near_flagged(moved_, k.strip, block, edges)) continue;
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
// rows of its own or the eight neighbouring tiles change (see Tiling::tile()), so tiles away
// from any tile swept or solved since then keep the residuals found then (all below Υ,
// or their tiles would have been swept), and the largest of those counts as found again.
// The rows outside the working set there all had a zero correction (else they would have
// joined), and still have: the check outside it skips those tiles as well.
double Engine::check(bool everywhere) {
  const double mu = material_.friction, upsilon = settings_.tolerance / dt_;
  std::uint8_t* moved = moved_.data();
  const int strips = tiling_.strips(), tiles = tiling_.blocks();
  const Tiling::EdgeFlags edges = tiling_.edge_flags(touched_);
  double worst = 0;
  std::int64_t visited = 0;
  bool joined = false;
#pragma omp parallel for num_threads(settings_.threads) if (settings_.threads > 1) schedule(dynamic, 16) \
    reduction(max : worst) reduction(+ : visited) reduction(|| : joined)
  for (int tile = 0; tile < strips * tiles; ++tile) {
    const int strip = tile / tiles, block = tile % tiles;
    if (!tiling_.near_flagged(touched_, strip, block, edges)) {
      if (everywhere) worst = std::max(worst, tile_residual_[tile]);  // unchanged since found
      continue;
    }
    double tile_worst = 0;
    bool tile_moved = false;
    for (int c = tiling_.first_row(tile); c < tiling_.first_row(tile + 1); ++c) {
      const bool in = in_work_[c];
      if (!everywhere && in) continue;
      const Row& r = contacts_.rows()[c];
      const Body &a = contacts_.bodies()[r.i], &b = contacts_.bodies()[r.j];
      const double corr =
          mu > 0 ? correction(r, contacts_.tangents()[c], local_solve(r, contacts_.tangents()[c], a, b, mu))
                 : normal_correction(r, a, b);
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

void Engine::solve() {
  StepReport& rep = report_;
  rep.iterations = 0;
  rep.contact_updates = 0;
  rep.cluster_solves = 0;
  rep.largest_cluster = 0;
  rep.residual = 0;
  rep.converged = true;
  if (contacts_.rows().empty()) return;
  const double upsilon = settings_.tolerance / dt_;
  const bool friction = material_.friction > 0;
  const bool clusters = settings_.cluster_solves && !friction;
  int next_cluster_solve = 2, cluster_wait = 1;
  select_working_set();
  clusters_.reset(contacts_.size());
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
      // Marks the tiles of the rows it solved.
      const int largest = clusters_.solve(contacts_, tiling_, work_, row_flags_.data(), moved_.data(), touched_.data(),
                                          settings_.threads);
      rep.largest_cluster = std::max(rep.largest_cluster, largest);
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
  const StepInput in{state_, box_, rate_, dt_, material_, gravity_, settings_.threads};
  tiling_.order(state_, box_, max_radius_, alert_, settings_.threads);
  contacts_.build(in, broad_.candidates(), tiling_);
  contacts_.load_bodies(in, tiling_);
  solve();
  // Without friction the flags say which rows bear (kBearing exactly when P_n > 0).
  const bool flagged = material_.friction == 0;
  const ContactRows::Tally tally =
      contacts_.record(in, broad_.candidates(), flagged ? row_flags_.data() : nullptr, kBearing);
  report_.candidates = int(contacts_.size());
  report_.contacts = int(contacts_.records().size());
  report_.collisions = tally.collisions;
  report_.collision_velocity_product = tally.collision_velocity_product;
  report_.dissipated_energy = tally.dissipated_energy;
  contacts_.store_bodies(state_, tiling_, settings_.threads);
  advance();
  detect(true);
  report_.step = steps_;
  report_.max_overlap = broad_.overlap();
  return report_;
}

void Engine::set_threads(int threads) {
  if (threads < 1) throw UsageError("threads must be at least 1");
  settings_.threads = threads;
}

std::size_t Engine::allocated_bytes() const {
  const GrainState& s = state_;
  return broad_.bytes() + tiling_.bytes() + contacts_.bytes() + clusters_.bytes() + heap_bytes(s.position) +
         heap_bytes(s.velocity) + heap_bytes(s.orientation) + heap_bytes(s.angular_velocity) + heap_bytes(s.radius) +
         heap_bytes(s.mass) + heap_bytes(s.fixed) + heap_bytes(work_) + heap_bytes(work_start_) + heap_bytes(in_work_) +
         heap_bytes(row_flags_) + heap_bytes(moved_) + heap_bytes(touched_) + heap_bytes(tile_residual_);
}

ContactMemory Engine::memory() const {
  ContactMemory m;
  const std::vector<std::uint64_t>& keys = contacts_.memory_keys();
  for (std::size_t c = 0; c < keys.size(); ++c) m.pair.push_back({int(keys[c] >> 32), int(keys[c] & 0xffffffffu)});
  m.normal_force = contacts_.memory_normal_force();
  m.tangential_force = contacts_.memory_tangential_force();
  m.age = contacts_.memory_age();
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
  contacts_.set_memory(std::move(keys), memory.normal_force, memory.tangential_force, memory.age);
}

}  // namespace granflow
