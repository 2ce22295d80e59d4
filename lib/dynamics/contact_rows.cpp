#include "dynamics/contact_rows.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "dynamics/branch_free.hpp"
#include "dynamics/capacity.hpp"
#include "dynamics/contact_law.hpp"
#include "dynamics/parallel.hpp"

namespace granflow {

// Local problems of every candidate: normals, bounds, reduced masses, warm start. Rows are
// stored in sweep order: by tile, ties in candidate order.
void ContactRows::build(const StepInput& in, const std::vector<Candidate>& candidates, Tiling& tiling) {
  const std::size_t count = candidates.size();
  refill(row_of_, count);
  tiling.sort_rows(candidates, row_of_, in.threads);
  refill(rows_, count);
  refill(tangents_, in.material.friction > 0 ? count : 0);
  refill(row_bodies_, count);
  refill(row_age_, count);
  // Chunks of candidates, each with its own cursor into the previous step's memory (same
  // sort order), so that threads can share them.
  constexpr std::ptrdiff_t chunk = 4096;
  const std::ptrdiff_t chunks = (std::ptrdiff_t(count) + chunk - 1) / chunk;
  parallel_for(in.threads, chunks, [&](std::ptrdiff_t h) {
    const std::size_t first = h * chunk, last = std::min(count, std::size_t(first + chunk));
    std::size_t p =
        std::lower_bound(prev_key_.begin(), prev_key_.end(), pair_key(candidates[first].i, candidates[first].j())) -
        prev_key_.begin();
    for (std::size_t c = first; c < last; ++c) build_row(in, candidates, tiling, c, p);
  });
}

// Row of candidate c, warm-started from the previous step's memory found at or after p.
void ContactRows::build_row(const StepInput& in, const std::vector<Candidate>& candidates, const Tiling& tiling,
                            std::size_t c, std::size_t& p) {
  const GrainState& s = in.state;
  const double e = in.material.restitution, et = in.material.tangential_restitution;
  const Candidate& k = candidates[c];
  const int i = k.i, j = k.j();
  const double dist = std::sqrt(k.dx * k.dx + k.dy * k.dy);
  const double nx = k.dx / dist, ny = k.dy / dist;
  const double ri = s.radius[i], rj = s.radius[j];
  const double gap = dist - ri - rj;
  const double shift = k.image() * in.rate * in.box.ly;  // x-velocity of j's image relative to j
  const double dvx = s.velocity[i].x() - s.velocity[j].x() - shift;
  const double dvy = s.velocity[i].y() - s.velocity[j].y();
  const double un = dvx * nx + dvy * ny;
  const double ut = -dvx * ny + dvy * nx - (ri * s.angular_velocity[i] + rj * s.angular_velocity[j]);
  // Touching or predicted to touch, or not, is as good as random: both bounds are computed
  // and one is picked without a jump. e·max(0, −u_n) is −e·u_n for u_n < 0, else +0.
  const bool touching = (gap <= 0) | (gap + in.dt * un <= 0);
  double bn = pick(touching, e * positive_part(-un), -gap / in.dt);
  // The thesis' activation: a pair apart at the start of the step is unconstrained.
  if (in.activation == Activation::overlap && gap > 0) bn = -std::numeric_limits<double>::infinity();
  const double wi = s.fixed[i] ? 0.0 : 1.0 / s.mass[i];
  const double wj = s.fixed[j] ? 0.0 : 1.0 / s.mass[j];

  Row& r = rows_[row_of_[c]];
  r.i = tiling.body(i);
  r.j = tiling.body(j);
  row_bodies_[row_of_[c]] = {s.fixed[i] ? -1 : r.i, s.fixed[j] ? -1 : r.j};
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
    r.pn = prev_fn_[p] * in.dt;
    pt = prev_ft_[p] * in.dt;
    row_age_[c] = prev_age_[p];
  }
  if (in.material.friction > 0) tangents_[row_of_[c]] = {et * ut - shift * ny, pt};
}

// Free velocities, plus the warm-start impulses.
void ContactRows::load_bodies(const StepInput& in, const Tiling& tiling) {
  const GrainState& s = in.state;
  const std::size_t n = s.size();
  parallel_for(in.threads, n, [&](std::size_t i) {
    Body& b = bodies_[tiling.body(i)];
    const bool mobile = !s.fixed[i];
    b.vx = s.velocity[i].x() + (mobile ? in.dt * in.gravity.x() : 0.0);
    b.vy = s.velocity[i].y() + (mobile ? in.dt * in.gravity.y() : 0.0);
    b.spin = s.radius[i] * s.angular_velocity[i];
    b.inv_mass = mobile ? 1.0 / s.mass[i] : 0.0;
  });
  const bool friction = in.material.friction > 0;
  for (std::size_t c = 0; c < rows_.size(); ++c) {
    const Row& r = rows_[c];
    const double pt = friction ? tangents_[c].pt : 0.0;
    if (r.pn == 0 && pt == 0) continue;
    add_impulse(r, bodies_[r.i], bodies_[r.j], r.pn, pt);
  }
}

// Contacts of this step, from the impulses and the (still unchanged) pre-step state, in
// candidate order, written in parallel at their places.
ContactRows::Tally ContactRows::record(const StepInput& in, const std::vector<Candidate>& candidates,
                                       const std::uint8_t* flags, std::uint8_t bearing) {
  const GrainState& s = in.state;
  const double e = in.material.restitution;
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
    const Candidate& k = candidates[c];
    const int i = k.i, j = k.j();
    const int age = row_age_[c] + 1;
    const Vec2 n(r.nx, r.ny);
    const Vec2 vi = fluctuating_velocity(s, in.box, in.rate, i);
    const Vec2 vj = fluctuating_velocity(s, in.box, in.rate, j);
    const double shift = k.image() * in.rate * in.box.ly;
    const double un = (s.velocity[i] - s.velocity[j]).dot(n) - shift * r.nx;
    const double fn = r.pn / in.dt, ft = tangents_.empty() ? 0.0 : tangents_[row_of_[c]].pt / in.dt;
    records_.pair[q] = {i, j};
    records_.normal_force[q] = fn;
    records_.tangential_force[q] = ft;
    records_.branch[q] = Vec2(k.dx, k.dy);
    records_.binary_force[q] = (1 + e) * r.inv_w * std::max(0.0, -un) / in.dt;
    records_.pre_normal_velocity[q] = {vi.dot(n), vj.dot(n)};
    records_.age[q] = age;
    dissipated_[q] = dissipated(in, r, c, i, j, shift);
    prev_key_[q] = pair_key(i, j);
    prev_fn_[q] = fn;
    prev_ft_[q] = ft;
    prev_age_[q] = age;
  };
  // Where given, the flags say which rows bear, and they take a byte per row where the rows
  // take a cache line: reading them keeps this pass, in candidate order and not in row order,
  // out of the large rows.
  gather(
      std::ptrdiff_t(candidates.size()), in.threads, chunk_start_,
      [&](std::ptrdiff_t c) { return flags ? (flags[row_of_[c]] & bearing) != 0 : rows_[row_of_[c]].pn > 0; }, resize,
      record);
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
  return {born, product, lost};
}

// −P·ū of row r (candidate c, grains i and j): ū at the mean of the free velocities (the
// pre-step state, still in in.state, plus gravity) and the post-step ones (in bodies_).
double ContactRows::dissipated(const StepInput& in, const Row& r, std::size_t c, int i, int j, double shift) const {
  const GrainState& s = in.state;
  const Body& a = bodies_[r.i];
  const Body& b = bodies_[r.j];
  auto free_v = [&](int g) { return s.fixed[g] ? s.velocity[g] : Vec2(s.velocity[g] + in.dt * in.gravity); };
  const Vec2 va = 0.5 * (free_v(i) + Vec2(a.vx, a.vy));
  const Vec2 vb = 0.5 * (free_v(j) + Vec2(b.vx, b.vy));
  const double sa = 0.5 * (s.radius[i] * s.angular_velocity[i] + a.spin);
  const double sb = 0.5 * (s.radius[j] * s.angular_velocity[j] + b.spin);
  const double ux = va.x() - vb.x() - shift, uy = va.y() - vb.y();
  const double un = ux * r.nx + uy * r.ny;
  const double ut = -ux * r.ny + uy * r.nx - sa - sb;
  const double pt = tangents_.empty() ? 0.0 : tangents_[row_of_[c]].pt;
  return -(r.pn * un + pt * ut);
}

void ContactRows::store_bodies(GrainState& s, const Tiling& tiling, int threads) const {
  parallel_for(threads, s.size(), [&](std::size_t i) {
    const Body& b = bodies_[tiling.body(i)];
    s.velocity[i] = Vec2(b.vx, b.vy);
    // Only grains that felt a tangential impulse change ω: s/R would otherwise perturb ω in the last bit.
    if (b.spin != s.radius[i] * s.angular_velocity[i]) s.angular_velocity[i] = b.spin / s.radius[i];
  });
}

void ContactRows::set_memory(std::vector<std::uint64_t> keys, std::vector<double> normal_force,
                             std::vector<double> tangential_force, std::vector<int> age) {
  prev_key_ = std::move(keys);
  prev_fn_ = std::move(normal_force);
  prev_ft_ = std::move(tangential_force);
  prev_age_ = std::move(age);
}

std::size_t ContactRows::bytes() const {
  const ContactRecords& r = records_;
  return heap_bytes(row_of_) + heap_bytes(bodies_) + heap_bytes(rows_) + heap_bytes(tangents_) +
         heap_bytes(row_bodies_) + heap_bytes(row_age_) + heap_bytes(prev_key_) + heap_bytes(prev_fn_) +
         heap_bytes(prev_ft_) + heap_bytes(prev_age_) + heap_bytes(r.pair) + heap_bytes(r.normal_force) +
         heap_bytes(r.tangential_force) + heap_bytes(r.branch) + heap_bytes(r.binary_force) +
         heap_bytes(r.pre_normal_velocity) + heap_bytes(r.age) + heap_bytes(dissipated_) + heap_bytes(chunk_start_);
}

}  // namespace granflow
