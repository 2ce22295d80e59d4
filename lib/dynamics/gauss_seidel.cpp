#include "dynamics/gauss_seidel.hpp"

#include <algorithm>
#include <cmath>

#include "dynamics/branch_free.hpp"
#include "dynamics/capacity.hpp"
#include "dynamics/contact_law.hpp"
#include "dynamics/parallel.hpp"

namespace granflow {

// The rows the sweeps visit: contacts carrying a warm-start impulse and pairs whose normal
// constraint, at the free velocities, is violated or within v_rel (the bound on relative
// velocities) of binding. Any other row keeps P = 0 unless the impulses of the step change
// its u_n by more than that; check() then finds it and lets it join.
void GaussSeidel::select_working_set(const ContactRows& contacts, const Tiling& tiling, double vrel, int threads) {
  const std::ptrdiff_t count = std::ptrdiff_t(contacts.size());
  in_work_.resize(count);
  row_flags_.resize(count);
  moved_.assign(std::size_t(tiling.tiles()), 1);
  revisit_all_ = true;
  touched_.assign(std::size_t(tiling.tiles()), 1);  // the first check of a step is everywhere
  tile_residual_.resize(touched_.size());
  parallel_for(threads, count, [&](std::ptrdiff_t c) {
    const Row& r = contacts.rows()[c];
    const Body &a = contacts.bodies()[r.i], &b = contacts.bodies()[r.j];
    const double un = (a.vx - b.vx) * r.nx + (a.vy - b.vy) * r.ny;
    // Bitwise, not short-circuit: both tests are near random, and a jump would mispredict.
    in_work_[c] = (r.pn > 0) | (un - r.bn < vrel);
    row_flags_[c] = std::uint8_t(kHot | (r.pn > 0) * kBearing);
  });
  group_working_set(tiling);
}

// Lists the working set tile by tile, rows ascending within each: the order of the sweeps
// (rows are stored tile by tile, so that is ascending row order).
void GaussSeidel::group_working_set(const Tiling& tiling) {
  const int tiles = tiling.tiles();
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
    for (int c = tiling.first_row(t); c < tiling.first_row(t + 1); ++c) {
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
double GaussSeidel::sweep(ContactRows& contacts, const Tiling& tiling, double mu, bool forward, double upsilon,
                          int threads, std::int64_t& updates) {
  const int* start = work_start_.data();
  std::uint8_t* moved = moved_.data();
  std::uint8_t* touched = touched_.data();
  const int strips = tiling.strips(), tiles = tiling.blocks();
  const int dir = forward ? 1 : -1;
  double worst = 0;
  int changes = 0, active = 0;
  std::int64_t visits = 0;
  // With friction a row is skipped if its last visit left it below Υ (not hot) and no row
  // sharing one of its grains has corrected it by Υ or more since: in the previous sweep
  // (kick_prev) or in this one so far (kick_now). Its local solve would then change it by
  // less than Υ (apart from the build-up of smaller corrections, which the residual check
  // finds). A sweep after anything else changed impulses (a check, a cluster or region
  // solve, a new step) visits every row of its tiles. Frictionless sweeps visit every row:
  // their trajectories stay those of before, bit for bit.
  const bool skip_settled = Friction && skip_settled_rows_ && !revisit_all_;
  if constexpr (Friction) {
    const std::size_t bodies = contacts.bodies().size();
    for (auto& k : kicked_) k.resize(bodies);
    std::fill(kicked_[kick_now_].begin(), kicked_[kick_now_].end(), std::uint8_t(0));
  }
  const std::uint8_t* const kick_prev = Friction ? kicked_[1 - kick_now_].data() : nullptr;
  std::uint8_t* const kick_now = Friction ? kicked_[kick_now_].data() : nullptr;
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
    const Tiling::EdgeFlags edges = tiling.edge_flags(moved_);
#pragma omp parallel for num_threads(threads) if (threads > 1) schedule(dynamic, 1) \
    reduction(max : worst) reduction(+ : changes, active, visits)
    for (int t = 0; t < (count + 1) / 2; ++t) {
      // Pointers are locals, and so are the counters in the loops below: the byte stores to
      // the flags may alias anything, and would otherwise send them through memory on every row.
      const int* const work_rows = work_.data();
      Row* const row_data = contacts.rows().data();
      Tangent* const tangent_data = contacts.tangents().data();
      Body* const body_data = contacts.bodies().data();
      std::uint8_t* const row_flags = row_flags_.data();
      // The local solve of row work_rows[q]; folds its correction and counts into a tile's.
      auto update = [&](int q, double& tile_worst, int& tile_changes, int& tile_active) {
        const int c = work_rows[q];
        Row& r = row_data[c];
        if constexpr (Friction) {
          if (skip_settled && !(row_flags[c] & kHot) &&
              !(kick_prev[r.i] | kick_prev[r.j] | kick_now[r.i] | kick_now[r.j])) {
            tile_active += (row_flags[c] & kBearing) != 0;
            --visits;  // not a local solve
            return;
          }
        }
        Body& a = body_data[r.i];
        Body& b = body_data[r.j];
        if constexpr (Friction) {
          Tangent& g = tangent_data[c];
          const auto [pn, pt] = local_solve(r, g, a, b, mu);
          const double dpn = pn - r.pn, dpt = pt - g.pt;
          // Compare before dividing: the division is only needed for a new maximum.
          const double d = std::max(std::fabs(dpn), 3 * std::fabs(dpt));
          if (d > tile_worst * r.inv_w) tile_worst = d / r.inv_w;
          // The state of the row for the cluster solves: bearing, and sliding on either facet
          // of the cone (a local solve clamps P_t to ±μP_n exactly).
          const int bears = bearing(pn), bore = bearing(r.pn);
          const int slides = bears & (std::fabs(pt) == mu * pn), slid = bore & (std::fabs(g.pt) == mu * r.pn);
          tile_changes += (bears ^ bore) | (slides ^ slid) | (slides & slid & ((pt > 0) ^ (g.pt > 0)));
          tile_active += bears;
          const bool hot = d >= upsilon * r.inv_w;
          row_flags[c] = std::uint8_t(hot * kHot | bears * kBearing);
          if (hot) kick_now[r.i] = kick_now[r.j] = 1;
          r.pn = pn;
          g.pt = pt;
          add_impulse(r, a, b, dpn, dpt);
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
          if (!tiling.near_flagged(moved_, k.strip, block, edges)) continue;
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
  updates += visits;
  if constexpr (Friction) {
    kick_now_ = 1 - kick_now_;
    revisit_all_ = false;
  }
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
double GaussSeidel::check(const ContactRows& contacts, const Tiling& tiling, double mu, double upsilon, bool everywhere,
                          bool full_checks, int threads, std::int64_t& updates) {
  revisit_all_ = true;  // rows found off or joining are swept next, settled or not
  const Row* const rows = contacts.rows().data();
  const Tangent* const tangents = contacts.tangents().data();
  const Body* const bodies = contacts.bodies().data();
  std::uint8_t* moved = moved_.data();
  const int strips = tiling.strips(), tiles = tiling.blocks();
  const Tiling::EdgeFlags edges = tiling.edge_flags(touched_);
  double worst = 0;
  std::int64_t visited = 0;
  bool joined = false;
#pragma omp parallel for num_threads(threads) if (threads > 1) schedule(dynamic, 16) \
    reduction(max : worst) reduction(+ : visited) reduction(|| : joined)
  for (int tile = 0; tile < strips * tiles; ++tile) {
    const int strip = tile / tiles, block = tile % tiles;
    if (!tiling.near_flagged(touched_, strip, block, edges)) {
      if (everywhere) worst = std::max(worst, tile_residual_[tile]);  // unchanged since found
      continue;
    }
    double tile_worst = 0;
    bool tile_moved = false;
    for (int c = tiling.first_row(tile); c < tiling.first_row(tile + 1); ++c) {
      const bool in = in_work_[c];
      if (!everywhere && in) continue;
      const Row& r = rows[c];
      const Body &a = bodies[r.i], &b = bodies[r.j];
      const double corr =
          mu > 0 ? correction(r, tangents[c], local_solve(r, tangents[c], a, b, mu)) : normal_correction(r, a, b);
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
  if (everywhere && !full_checks) std::fill(touched_.begin(), touched_.end(), 0);
  updates += visited;
  if (joined) group_working_set(tiling);
  return worst;
}

double GaussSeidel::sweep(ContactRows& contacts, const Tiling& tiling, double mu, bool forward, double upsilon,
                          int threads, std::int64_t& updates) {
  return mu > 0 ? sweep<true>(contacts, tiling, mu, forward, upsilon, threads, updates)
                : sweep<false>(contacts, tiling, mu, forward, upsilon, threads, updates);
}

std::size_t GaussSeidel::bytes() const {
  return heap_bytes(work_) + heap_bytes(work_start_) + heap_bytes(in_work_) + heap_bytes(row_flags_) +
         heap_bytes(moved_) + heap_bytes(touched_) + heap_bytes(tile_residual_) + heap_bytes(kicked_[0]) +
         heap_bytes(kicked_[1]);
}

}  // namespace granflow
