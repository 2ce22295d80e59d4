#include "dynamics/cluster_solver.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <utility>

#include <omp.h>

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>

#include "dynamics/branch_free.hpp"
#include "dynamics/capacity.hpp"
#include "dynamics/contact_law.hpp"
#include "dynamics/parallel.hpp"

namespace granflow {

namespace {

// See solve_cluster(). 10 also stops the blow-up but undoes most solves in a pile coming to
// rest (5° incline: 899 sweeps per step instead of 63, steps at the sweep cap); 100 and 1000
// undo none there.
constexpr double kClusterSolveGrowth = 100;

// A frictional cluster with at least this many rows left after peeling is ordered by minimum
// degree at once, without first trying the sweep order: where the sweep order passes the fill
// test it still makes more arithmetic than the minimum-degree order (its fill lies in wide
// fronts), and where it fails the attempt is wasted. Measured (docs/performance.md): ν = 0.78,
// N = 10³, 4.1 → 2.9 s per unit strain with this threshold anywhere from 25 to 400, the same
// sweeps and passes; at 25 and 50, ν = 0.76 ran slower than before (small clusters cost more
// to order than they save), at 200, N = 10⁴ gained less than at 100.
constexpr int kOrderedLoops = 100;

// Clusters of at least this many active rows are factorised by all threads together.
constexpr int kSharedClusterRows = 2000;

// A row that a step along a self-stress opens (P_n reaches 0); see step_along_self_stress().
constexpr std::int8_t kOpened = 2;

// Self-stresses solved for in one cluster solve at most: each costs a solve and two passes
// over the matrix, and a jammed, hyperstatic cluster pins hundreds of unknowns.
constexpr int kSelfStressesPerSolve = 8;

}  // namespace

// One exact solve, for the current active set, of each cluster of active contacts (joined
// through mobile grains) in which some contact was still corrected by Υ or more in the last
// sweep: W_AA·ΔP_A = b_A − u_A on its normal rows (μ = 0), then P_A ← max(0, P_A + ΔP_A).
// Clusters share no mobile grain, so threads take them in any order.
int ClusterSolver::solve(ContactRows& contacts, const Tiling& tiling, const std::vector<int>& work,
                         std::uint8_t* row_flags, std::uint8_t* moved, std::uint8_t* touched, double mu, double upsilon,
                         int threads) {
  mu_ = mu;
  upsilon_ = upsilon;
  tangents_ = mu > 0 ? contacts.tangents().data() : nullptr;
  const int n = int(contacts.bodies().size());
  rows_ = contacts.rows().data();
  bodies_ = contacts.bodies().data();
  row_bodies_ = contacts.row_bodies().data();
  row_flags_ = row_flags;
  int largest = 0;
  // The active rows (all in the working set) with their mobile bodies (−1 for a fixed one,
  // which couples nothing), read once: the passes below touch only this compact copy.
  gather(
      std::ptrdiff_t(work.size()), threads, chunk_start_,
      [&](std::ptrdiff_t q) { return (row_flags_[work[q]] & kBearing) != 0; },
      [&](std::size_t kept) {
        fit_capacity(active_, kept);
        active_.resize(kept);
      },
      [&](std::ptrdiff_t q, std::size_t k) {
        const int c = work[q];
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
  parallel_for(threads, n, [&](int b) {
    cluster_[b] = b;
    cluster_id_[b] = -2;
  });
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
  parallel_for(threads, rows, [&](std::ptrdiff_t q) {
    const ActiveRow& a = active_[q];
    if (a.i < 0 || a.j < 0) return;
    for (;;) {
      const int x = root(a.i), y = root(a.j);
      if (x == y || link(std::max(x, y), std::min(x, y))) break;
    }
  });
  // Hot clusters are numbered in order of appearance; cluster_id_ per root: −2 cold, −1 hot.
  parallel_for(threads, rows, [&](std::ptrdiff_t q) {
    ActiveRow& a = active_[q];
    a.cluster = root(a.i >= 0 ? a.i : a.j);
    if (row_flags_[a.c] & kHot) std::atomic_ref<int>(cluster_id_[a.cluster]).store(-1, std::memory_order_relaxed);
  });
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
  counting_sort(
      clusters, cluster_start_,
      [&](auto emit) {
        for (const ActiveRow& a : active_) emit(a.cluster, a.c);
      },
      [&](std::size_t total) { refill(cluster_rows_, total); }, [&](int c, int slot) { cluster_rows_[slot] = c; });
  counting_sort(
      n, body_start_,
      [&](auto emit) {
        for (const ActiveRow& a : active_) {
          if (a.i >= 0) emit(a.i, a.c);
          if (a.j >= 0) emit(a.j, a.c);
        }
      },
      [&](std::size_t total) { refill(body_rows_, total); }, [&](int c, int slot) { body_rows_[slot] = c; });
  degree_.resize(n);  // the number of rows at each body
  for (int b = 0; b < n; ++b) degree_[b] = body_start_[b + 1] - body_start_[b];

  // Clusters go to the threads whole, largest first; one that holds more than a thread's
  // share of all the rows (and at least kSharedClusterRows: the percolating cluster) would
  // keep one thread busy while the others wait, so it is factorised by all threads together
  // instead, after the others. The clusters are independent: the same result either way.
  scratch_.resize(threads);
  large_.clear();
  cluster_order_.clear();
  const int shared_at = std::max(kSharedClusterRows, int(active_.size()) / threads);
  auto size = [&](int k) { return cluster_start_[k + 1] - cluster_start_[k]; };
  for (int k = 0; k < clusters; ++k) {
    largest = std::max(largest, size(k));
    (threads > 1 && size(k) >= shared_at ? large_ : cluster_order_).push_back(k);
  }
  if (threads > 1)
    std::stable_sort(cluster_order_.begin(), cluster_order_.end(), [&](int a, int b) { return size(a) > size(b); });
#pragma omp parallel for num_threads(threads) if (threads > 1) schedule(dynamic)
  for (std::size_t q = 0; q < cluster_order_.size(); ++q)
    solve_cluster(cluster_order_[q], scratch_[omp_get_thread_num()], 1);
  for (int k : large_) solve_cluster(k, scratch_[0], threads);
  // Velocities changed only at the bodies of these rows: their tiles are swept next (the
  // rows are in ascending order, as in the working set, and rows are stored tile by tile).
  int tile = 0;
  for (const ActiveRow& a : active_) {
    while (tiling.first_row(tile + 1) <= a.c) ++tile;
    moved[tile] = touched[tile] = 1;
  }
  return largest;
}

// The solve of cluster k (see solve()). Returns false when its factor would be too
// large to pay off (nothing changed) or its result was undone (impulses and velocities
// restored exactly).
bool ClusterSolver::solve_cluster(int k, Scratch& w, int threads) {
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
  // (Bodies from the compact row_bodies, −1 for a fixed one.)
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
  // approximate minimum degree; beyond 8 even then, Gauss–Seidel alone is cheaper. Frictional
  // clusters with kOrderedLoops loop rows or more are reordered at once (frictionless ones
  // keep the sweep order where it passes, and with it their trajectories bit for bit).
  auto factor = [&](std::size_t fill) {
    if (tangents_) {
      assemble_frictional_cluster(w);
      return w.ldl.factor(w.first[m], w.start, w.row, w.value, w.lower, 1e-9, fill * w.row.size() + 64, threads);
    }
    assemble_cluster(w, threads);
    return w.ldl.factor(m, w.start, w.row, w.value, 1e-9, fill * w.row.size() + 64, threads);
  };
  const bool ordered_at_once = tangents_ && m - peeled >= kOrderedLoops;
  bool factored = !ordered_at_once && factor(4);
  if (!factored && peeled < m) {
    order_loops(w, peeled);
    factored = factor(8);
  }
  bool accepted = false;
  if (factored) {
    const bool self_stress = tangents_ && w.ldl.pinned() > 0;
    if (self_stress) w.b = w.rhs;
    w.ldl.solve(w.rhs);
    if (self_stress) step_along_self_stress(w);
    accepted = tangents_ ? apply_frictional_solution(w, threads) : apply_normal_solution(w, threads);
  }
  for (int c : w.order) unknown_[c] = -1;
  return accepted;
}

// Applies the solved ΔP_n (in w.rhs), clamped at P_n ≥ 0. The step is undone if it multiplies
// the cluster's largest local correction by more than kClusterSolveGrowth. When the active set
// is hyperstatic (jammed, ν near ν_c) its equations can be inconsistent and near-singular: the
// solve then returns huge self-stresses whose clamping at P_n = 0 would throw the velocities
// off by orders of magnitude. (A good step may raise the correction a little: the clamping.)
bool ClusterSolver::apply_normal_solution(Scratch& w, int threads) {
  const int m = int(w.order.size());
  const double before = cluster_residual(w, threads);
  auto set_normal_impulse = [&](int c, double pn) {
    Row& r = rows_[c];
    apply_normal_impulse(r, pn - r.pn);
    r.pn = pn;
    row_flags_[c] = std::uint8_t((row_flags_[c] & kHot) | bearing(pn) * kBearing);
  };
  save_bodies(w);
  for (int u = 0; u < m; ++u) {
    const double pn = rows_[w.order[u]].pn, solved = positive_part(pn + w.rhs[u]);
    w.rhs[u] = pn;  // kept for an undo
    set_normal_impulse(w.order[u], solved);
  }
  const bool accepted = cluster_residual(w, threads) <= kClusterSolveGrowth * before;  // false for NaN too
  if (!accepted) {
    for (int u = 0; u < m; ++u) {
      const int c = w.order[u];
      rows_[c].pn = w.rhs[u];
      row_flags_[c] = std::uint8_t((row_flags_[c] & kHot) | bearing(w.rhs[u]) * kBearing);
    }
    restore_bodies(w);
  }
  return accepted;
}

// The same with friction: ΔP_n and, for a sticking row, ΔP_t (see assemble_frictional_cluster())
// projected on the cone, P_n ≥ 0 then |P_t| ≤ μP_n (a sliding row's P_t on its facet), and
// undone on the same test.
bool ClusterSolver::apply_frictional_solution(Scratch& w, int threads) {
  const int m = int(w.order.size());
  const double mu = mu_;
  const double before = cluster_residual(w, threads);
  auto set_impulse = [&](int c, double pn, double pt) {
    Row& r = rows_[c];
    Tangent& g = tangents_[c];
    apply_impulse(r, pn - r.pn, pt - g.pt);
    r.pn = pn;
    g.pt = pt;
    row_flags_[c] = std::uint8_t((row_flags_[c] & kHot) | bearing(pn) * kBearing);
  };
  w.old.resize(2 * std::size_t(m));  // kept for an undo
  save_bodies(w);
  for (int u = 0; u < m; ++u) {
    const int c = w.order[u];
    const double pn = rows_[c].pn, pt = tangents_[c].pt;
    const double solved_pn = positive_part(pn + w.rhs[w.first[u]]);
    const double limit = mu * solved_pn;
    const double solved_pt =
        w.facet[u] != 0 ? w.facet[u] * limit : std::clamp(pt + w.rhs[w.first[u] + 1], -limit, limit);
    w.old[2 * u] = pn;
    w.old[2 * u + 1] = pt;
    set_impulse(c, solved_pn, solved_pt);
  }
  const bool accepted = cluster_residual(w, threads) <= kClusterSolveGrowth * before;  // false for NaN too
  if (!accepted) {
    for (int u = 0; u < m; ++u) {
      const int c = w.order[u];
      rows_[c].pn = w.old[2 * u];
      tangents_[c].pt = w.old[2 * u + 1];
      row_flags_[c] = std::uint8_t((row_flags_[c] & kHot) | bearing(w.old[2 * u]) * kBearing);
    }
    restore_bodies(w);
  }
  return accepted;
}

// A pinned unknown k leaves its equation out of the frictional cluster's solve: A is singular,
// with a self-stress z (A·z = 0, z_k = 1: impulses that move no grain) and a left null vector
// y (yᵀ·A = 0, y_k = 1: a combination of the equations that no impulse changes), and the solve
// is one of the line of solutions ΔP + λz. Where the cone's bounds on the contacts that z
// touches leave an interval of λ, the solution moves into it:
// - if equation k is met (|r_k| < Υ, r = b − A·ΔP), to the point of the interval nearest to
//   λ = 0: without this, the projection of a self-stress far outside a cone undoes the solve;
// - if it is not, no impulses in the current states meet every equation: b has a part β·y,
//   β of the sign of r_k, that no impulse reaches, and some contact must change state where
//   that part lets it: a sticking contact may slide on facet s if the unreachable part of its
//   tangential equation pushes towards s (s·β·y_t > 0: the side a local solve would clamp it
//   on), and a contact may open if that part of its normal equation pulls it apart
//   (β·y_n < 0). The solution moves to the nearer end of the interval where such a change
//   is, and that contact takes it (on its facet, or open) for the next pass. If the bounds
//   leave no interval, only those that hold at λ = 0 count. Gauss–Seidel alone drifts along
//   z by a step per sweep as small as r_k: a grain wedged between two fixed ones of an
//   incline's base took over 10⁴ sweeps in one step.
// At most kSelfStressesPerSolve self-stresses are solved for, those of unmet equations first;
// the others wait for the next pass.
void ClusterSolver::step_along_self_stress(Scratch& w) {
  const int m = int(w.order.size()), n = w.first[m];
  std::vector<double>& x = w.rhs;  // the solved ΔP
  w.stepped.clear();
  // out += s·A·v. Entry p of column j (row i = w.row[p] ≤ j) holds A(i, j) in value and
  // A(j, i) in lower.
  auto multiply = [&](double s, const std::vector<double>& v, std::vector<double>& out) {
    for (int j = 0; j < n; ++j)
      for (int p = w.start[j]; p < w.start[j + 1]; ++p) {
        const int i = w.row[p];
        out[i] += s * w.value[p] * v[j];
        if (i != j) out[j] += s * w.lower[p] * v[i];
      }
  };
  std::vector<double>& r = w.b;  // r = b − A·x (x_k = 0 for a pinned k)
  multiply(-1.0, x, r);
  // The unmet equations first: they are what Gauss–Seidel cannot mend. A met one can only
  // move x back into cones it leaves, so none is needed while x is inside every cone.
  w.pinned.clear();
  for (int k = 0; k < n; ++k)
    if (w.ldl.pinned(k) && std::fabs(r[k]) >= upsilon_) w.pinned.push_back(k);
  const std::size_t unmet = w.pinned.size();
  for (int k = 0; k < n; ++k)
    if (w.ldl.pinned(k) && !(std::fabs(r[k]) >= upsilon_)) w.pinned.push_back(k);
  auto inside_cones = [&] {
    for (int u = 0; u < m; ++u) {
      const int c = w.order[u], q = w.first[u];
      const double pn = rows_[c].pn + x[q];
      if (!(pn >= 0)) return false;
      if (w.facet[u] == 0 && !(std::fabs(tangents_[c].pt + x[q + 1]) <= mu_ * pn)) return false;
    }
    return true;
  };
  for (std::size_t e = 0; e < w.pinned.size() && e < std::size_t(kSelfStressesPerSolve); ++e) {
    const int k = w.pinned[e];
    const double rk = r[k];
    const bool met = e >= unmet;
    if (met && inside_cones()) break;
    // Column k of A into w.stress, row k into w.left (the storage as in multiply()).
    w.stress.assign(n, 0.0);
    w.left.assign(n, 0.0);
    for (int j = 0; j < n; ++j)
      for (int p = w.start[j]; p < w.start[j + 1]; ++p) {
        const int i = w.row[p];
        if (i == j) continue;  // the diagonal: z_k and y_k are set below
        if (i == k) {
          w.stress[j] += w.lower[p];
          w.left[j] += w.value[p];
        }
        if (j == k) {
          w.stress[i] += w.value[p];
          w.left[i] += w.lower[p];
        }
      }
    for (double& v : w.stress) v = -v;
    w.ldl.solve(w.stress);  // the other unknowns of z (pinned ones 0)
    w.stress[k] = 1;
    if (!met) {  // y only says which state change an unmet equation allows
      for (double& v : w.left) v = -v;
      w.ldl.solve_transposed(w.left);
      w.left[k] = 1;
    }
    // A row that an earlier step put on its facet or opened no longer has the freedom that
    // z uses: a self-stress through it waits for the next pass, solved in the new states.
    double size = 0;
    for (double v : w.stress) size = std::max(size, std::fabs(v));
    auto through = [&](int u) {
      for (int q = w.first[u]; q < w.first[u + 1]; ++q)
        if (std::fabs(w.stress[q]) > 1e-9 * size) return true;
      return false;
    };
    if (std::any_of(w.stepped.begin(), w.stepped.end(), through)) continue;
    // The interval [low, high] of λ over which ΔP + λz keeps every bound g0 + λ·g1 ≥ 0 of the
    // contacts z touches, with the row and state at each end; in held, those that hold at 0.
    struct End {
      double lambda;
      int row = -1;
      std::int8_t state = 0;
    };
    struct Interval {
      End high{std::numeric_limits<double>::infinity()}, low{-std::numeric_limits<double>::infinity()};
      bool empty() const { return !(low.lambda <= high.lambda); }
    } all, held;
    auto bound = [&](int u, double g0, double g1, std::int8_t state) {
      if (!(std::fabs(g1) > 1e-9 * size)) return;  // a contact that z does not touch
      const double lambda = -g0 / g1;
      for (Interval* in : {&all, &held}) {
        if (in == &held && !(g0 >= 0)) continue;
        End& end = g1 < 0 ? in->high : in->low;
        if (g1 < 0 ? lambda < end.lambda : lambda > end.lambda) end = {lambda, u, state};
      }
    };
    for (int u = 0; u < m; ++u) {
      const int c = w.order[u], q = w.first[u];
      const double pn = rows_[c].pn + x[q], dn = w.stress[q];
      bound(u, pn, dn, kOpened);
      if (w.facet[u] != 0) continue;  // a sliding row stays on its facet
      const double pt = tangents_[c].pt + x[q + 1], dt = w.stress[q + 1];
      bound(u, mu_ * pn - pt, mu_ * dn - dt, 1);
      bound(u, mu_ * pn + pt, mu_ * dn + dt, -1);
    }
    // z is a self-stress only up to the pinning threshold: a move along it must not change a
    // velocity by Υ or more (A·z is not exactly 0), or repeated moves could drive the grains.
    w.change.assign(n, 0.0);  // A·z
    multiply(1.0, w.stress, w.change);
    double drift = 0;
    for (double v : w.change) drift = std::max(drift, std::fabs(v));
    auto safe = [&](double lambda) { return std::fabs(lambda) * drift < upsilon_; };
    auto move = [&](double lambda) {
      for (int q = 0; q < n; ++q) {
        x[q] += lambda * w.stress[q];
        r[q] -= lambda * w.change[q];
      }
    };
    if (met) {
      if (all.empty()) continue;
      const double lambda = std::clamp(0.0, all.low.lambda, all.high.lambda);
      if (!safe(lambda)) continue;
      move(lambda);
      continue;
    }
    const Interval& in = all.empty() ? held : all;
    auto allowed = [&](const End& end) {
      if (end.row < 0) return false;
      const int q = w.first[end.row];
      return end.state == kOpened ? rk * w.left[q] < 0 : end.state * rk * w.left[q + 1] > 0;
    };
    const bool up = allowed(in.high) && safe(in.high.lambda), down = allowed(in.low) && safe(in.low.lambda);
    if (!up && !down) continue;
    const End& end = up && (!down || std::fabs(in.high.lambda) <= std::fabs(in.low.lambda)) ? in.high : in.low;
    move(end.lambda);
    w.stepped.push_back(end.row);
    // Exactly on the boundary, which round-off in x may have missed by an ulp.
    if (end.state == kOpened) x[w.first[end.row]] = -rows_[w.order[end.row]].pn;
    else w.facet[end.row] = end.state;
  }
}

// An undone solve restores the impulses and the velocities exactly. Undoing by applying the
// opposite impulses would leave round-off of the solve's impulses in the velocities, and a
// near-singular frictional cluster's solve can be 10¹³ times the step's impulses: a kick to
// every grain of the cluster that breaks momentum conservation. Only mobile bodies are saved
// and restored, each once: a fixed one may be shared with a cluster another thread is solving.
void ClusterSolver::save_bodies(Scratch& w) const {
  w.saved.clear();
  w.saved_index.clear();
  const int m = int(w.order.size());
  for (int u = 0; u < m; ++u) {
    const int c = w.order[u];
    const Row& r = rows_[c];
    for (int side = 0; side < 2; ++side) {
      const int b = row_bodies_[c][side];  // compact, −1 for a fixed body
      if (b < 0) continue;
      // Once per body: at the first of its rows in the cluster's numbering.
      bool first = true;
      for (int p = body_start_[b]; p < body_start_[b + 1] && first; ++p) {
        const int other = unknown_[body_rows_[p]];
        first = other < 0 || other >= u;
      }
      if (!first) continue;
      const int body = side == 0 ? r.i : r.j;
      w.saved.push_back(bodies_[body]);
      w.saved_index.push_back(body);
    }
  }
}

void ClusterSolver::restore_bodies(const Scratch& w) {
  for (std::size_t k = 0; k < w.saved.size(); ++k) bodies_[w.saved_index[k]] = w.saved[k];
}

// Adds the normal impulse dpn of row r to its bodies' velocities. Fixed bodies (shared
// between clusters) are left alone: they would not move anyway.
void ClusterSolver::apply_normal_impulse(const Row& r, double dpn) {
  for (const auto& [body, sign] : {std::pair(r.i, 1.0), std::pair(r.j, -1.0)}) {
    Body& b = bodies_[body];
    if (b.inv_mass == 0) continue;
    b.vx += sign * b.inv_mass * dpn * r.nx;
    b.vy += sign * b.inv_mass * dpn * r.ny;
  }
}

// Adds the impulse (dpn, dpt) of row r to its bodies' velocities and spins (see
// apply_normal_impulse()).
void ClusterSolver::apply_impulse(const Row& r, double dpn, double dpt) {
  const double px = dpn * r.nx - dpt * r.ny, py = dpn * r.ny + dpt * r.nx;
  for (const auto& [body, sign] : {std::pair(r.i, 1.0), std::pair(r.j, -1.0)}) {
    Body& b = bodies_[body];
    if (b.inv_mass == 0) continue;
    b.vx += sign * b.inv_mass * px;
    b.vy += sign * b.inv_mass * py;
    b.spin -= 2 * b.inv_mass * dpt;
  }
}

// Largest velocity correction a local solve would make on the cluster's rows.
double ClusterSolver::cluster_residual(const Scratch& w, int threads) const {
  const std::ptrdiff_t m = std::ptrdiff_t(w.order.size());
  auto row = [&](std::ptrdiff_t u) {
    const int c = w.order[u];
    const Row& r = rows_[c];
    const Body &a = bodies_[r.i], &b = bodies_[r.j];
    return tangents_ ? correction(r, tangents_[c], local_solve(r, tangents_[c], a, b, mu_))
                     : normal_correction(r, a, b);
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
void ClusterSolver::assemble_cluster(Scratch& w, int threads) const {
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
  parallel_for(threads, m, [&](int u) { column(u, [&](int other, double) { w.start[u + 1] += other <= u; }); });
  for (int u = 0; u < m; ++u) w.start[u + 1] += w.start[u];
  fit_capacity(w.row, w.start[m]);
  fit_capacity(w.value, w.start[m]);
  w.row.resize(w.start[m]);
  w.value.resize(w.start[m]);
  parallel_for(threads, m, [&](int u) {
    int q = w.start[u];
    column(u, [&](int other, double value) {
      if (other > u) return;
      w.row[q] = other;
      w.value[q++] = value;
    });
  });
}

// The frictional cluster's matrix A (see the header), by columns: for the entries of column k
// with row ≤ k, value holds A(row, k) and lower A(k, row). Row u of w.order has its normal
// unknown ΔP_n at w.first[u] and, if it sticks, its tangential one ΔP_t at w.first[u] + 1; a
// sliding row's ΔP_t = sμΔP_n is substituted (its impulse acts along n̂ + sμt̂), so it has no
// tangential unknown nor equation. Entry (x_o, y_u) is the change of row o's velocity along
// x ∈ {n̂, t̂} per unit impulse of row u along y, summed over their shared mobile bodies (mass m,
// s = ±1 as in assemble_cluster()): s_o·s_u·(x_o·y_u)/m, plus 2/m for x = y = t̂ (the spins:
// ΔS = −2·P_t/m on both grains of a contact, and u_t holds −S_i − S_j). The right-hand side:
// b − u at the current velocities (a sliding row's P_t is on its facet already: a sweep's
// clamp puts it there exactly).
void ClusterSolver::assemble_frictional_cluster(Scratch& w) const {
  const int m = int(w.order.size());
  const double mu = mu_;
  w.facet.resize(m);
  w.first.resize(m + 1);
  w.first[0] = 0;
  for (int u = 0; u < m; ++u) {
    const int c = w.order[u];
    const Tangent& g = tangents_[c];
    const int facet = std::fabs(g.pt) >= mu * rows_[c].pn ? (g.pt > 0 ? 1 : -1) : 0;
    w.facet[u] = std::int8_t(facet);
    w.first[u + 1] = w.first[u] + (facet != 0 ? 1 : 2);
  }
  const int unknowns = w.first[m];
  w.start.assign(unknowns + 1, 0);
  w.rhs.resize(unknowns);
  w.row.clear();
  w.value.clear();
  w.lower.clear();
  for (int u = 0; u < m; ++u) {
    const Row& a = rows_[w.order[u]];
    const Tangent& g = tangents_[w.order[u]];
    const Body &bi = bodies_[a.i], &bj = bodies_[a.j];
    const double dvx = bi.vx - bj.vx, dvy = bi.vy - bj.vy;
    w.rhs[w.first[u]] = a.bn - (dvx * a.nx + dvy * a.ny);
    if (w.facet[u] == 0) w.rhs[w.first[u] + 1] = g.bt - (dvy * a.nx - dvx * a.ny - (bi.spin + bj.spin));
  }
  auto emit = [&](int row, double upper, double lower) {
    w.row.push_back(row);
    w.value.push_back(upper);
    w.lower.push_back(lower);
  };
  for (int u = 0; u < m; ++u) {
    const Row& a = rows_[w.order[u]];
    const double su = w.facet[u] * mu;  // 0 for a sticking row
    // Calls f(o, nn, nt, tn, tt) for each row o ≤ u sharing a mobile body with row u, once per
    // shared body, with xy = s_o·s_u·(x_o·y_u)/m (+ 2/m in tt).
    auto neighbours = [&](auto&& f) {
      for (int body : {a.i, a.j}) {
        const double inv_mass = bodies_[body].inv_mass;
        if (inv_mass == 0) continue;
        const double side = body == a.i ? 1.0 : -1.0;
        for (int p = body_start_[body]; p < body_start_[body + 1]; ++p) {
          const int o = unknown_[body_rows_[p]];
          if (o > u) continue;
          const Row& b = rows_[body_rows_[p]];
          const double k = side * (body == b.i ? 1.0 : -1.0) * inv_mass;
          // t̂ = ẑ × n̂ = (−n_y, n_x)
          f(o, k * (b.nx * a.nx + b.ny * a.ny), k * (b.nx * -a.ny + b.ny * a.nx), k * (-b.ny * a.nx + b.nx * a.ny),
            k * (b.ny * a.ny + b.nx * a.nx) + 2 * inv_mass);
        }
      }
    };
    // Column of row u's normal unknown (impulse along n̂_u + s_uμt̂_u): rows N_o, and T_o for a
    // sticking o < u.
    neighbours([&](int o, double nn, double nt, double tn, double tt) {
      const double so = w.facet[o] * mu;
      emit(w.first[o], nn + su * nt, nn + so * tn);
      if (o < u && w.facet[o] == 0) emit(w.first[o] + 1, tn + su * tt, tn);
    });
    w.start[w.first[u] + 1] = int(w.row.size());
    if (w.facet[u] != 0) continue;
    // Column of a sticking row u's tangential unknown: rows N_o and, for a sticking o, T_o.
    neighbours([&](int o, double, double nt, double, double tt) {
      const double so = w.facet[o] * mu;
      emit(w.first[o], nt, nt + so * tt);
      if (w.facet[o] == 0) emit(w.first[o] + 1, tt, tt);
    });
    w.start[w.first[u] + 2] = int(w.row.size());
  }
}

// Reorders the cluster's unknowns from `first` on (the loops left after peeling) by
// approximate minimum degree (Eigen's AMD) on their coupling pattern. The pattern is built
// as that routine takes it, full and symmetric, diagonal included, each column's rows sorted
// and distinct: the same input, hence the same order, as Eigen's AMDOrdering makes from one
// triangle, without its triplets, transpose and sum.
void ClusterSolver::order_loops(Scratch& w, int first) {
  const int q = int(w.order.size()) - first;
  Eigen::SparseMatrix<double> graph(q, q);
  w.start.assign(q + 1, 0);
  w.row.clear();
  for (int t = 0; t < q; ++t) {
    const Row& a = rows_[w.order[first + t]];
    const std::size_t column = w.row.size();
    for (int body : {a.i, a.j}) {
      if (bodies_[body].inv_mass == 0) continue;
      for (int p = body_start_[body]; p < body_start_[body + 1]; ++p) {
        const int u = unknown_[body_rows_[p]] - first;
        if (u >= 0) w.row.push_back(u);
      }
    }
    std::sort(w.row.begin() + std::ptrdiff_t(column), w.row.end());
    w.row.erase(std::unique(w.row.begin() + std::ptrdiff_t(column), w.row.end()), w.row.end());
    w.start[t + 1] = int(w.row.size());
  }
  graph.resizeNonZeros(Eigen::Index(w.row.size()));
  std::copy(w.start.begin(), w.start.end(), graph.outerIndexPtr());
  std::copy(w.row.begin(), w.row.end(), graph.innerIndexPtr());
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> order;
  Eigen::internal::minimum_degree_ordering(graph, order);  // order.indices()[k]: the k-th to eliminate
  w.peel.assign(w.order.begin() + first, w.order.end());
  for (int k = 0; k < q; ++k) {
    const int c = w.peel[order.indices()[k]];
    w.order[first + k] = c;
    unknown_[c] = first + k;
  }
}

std::size_t ClusterSolver::bytes() const {
  std::size_t scratch = heap_bytes(scratch_);
  for (const Scratch& w : scratch_)
    scratch += heap_bytes(w.order) + heap_bytes(w.peel) + heap_bytes(w.start) + heap_bytes(w.row) +
               heap_bytes(w.value) + heap_bytes(w.rhs) + heap_bytes(w.first) + heap_bytes(w.lower) + heap_bytes(w.old) +
               heap_bytes(w.saved) + heap_bytes(w.saved_index) + heap_bytes(w.b) + heap_bytes(w.stress) +
               heap_bytes(w.left) + heap_bytes(w.change) + heap_bytes(w.facet) + heap_bytes(w.stepped) +
               heap_bytes(w.pinned) + w.ldl.allocated_bytes();
  return scratch + heap_bytes(active_) + heap_bytes(large_) + heap_bytes(cluster_order_) + heap_bytes(chunk_start_) +
         heap_bytes(cluster_) + heap_bytes(cluster_id_) + heap_bytes(cluster_start_) + heap_bytes(cluster_rows_) +
         heap_bytes(body_start_) + heap_bytes(body_rows_) + heap_bytes(degree_) + heap_bytes(unknown_);
}

}  // namespace granflow
