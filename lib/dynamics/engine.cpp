#include "dynamics/engine.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "core/error.hpp"

namespace granflow {

namespace {

std::uint64_t pair_key(int i, int j) { return (std::uint64_t(std::uint32_t(i)) << 32) | std::uint32_t(j); }

void require(bool ok, const std::string& what) {
  if (!ok) throw UsageError(what);
}

void validate(const GrainState& s, const Box& box, double rate, const Material& m,
              const SolverSettings& set, double dt, const Vec2& gravity) {
  const std::size_t n = s.size();
  require(n > 0, "no grains");
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

void ContactRecords::clear() {
  pair.clear();
  normal_force.clear();
  tangential_force.clear();
  branch.clear();
  binary_force.clear();
  pre_normal_velocity.clear();
  age.clear();
}

Engine::Engine(GrainState state, Box box, double rate, Material material, SolverSettings settings,
               double dt, Vec2 gravity)
    : state_(std::move(state)), box_(box), rate_(rate), dt_(dt), material_(material),
      settings_(settings), gravity_(gravity) {
  validate(state_, box_, rate_, material_, settings_, dt_, gravity_);
  const std::size_t n = state_.size();
  double diameter_sum = 0;
  for (std::size_t i = 0; i < n; ++i) {
    max_radius_ = std::max(max_radius_, state_.radius[i]);
    diameter_sum += 2 * state_.radius[i];
  }
  alert_min_ = settings_.alert_distance > 0 ? settings_.alert_distance : 0.1 * diameter_sum / double(n);
  const double cutoff = 2 * max_radius_ + alert_min_;
  require(box_.lx >= 2 * cutoff && (!box_.periodic_y || box_.ly >= 2 * cutoff),
          "box smaller than two contact-search cutoffs (2·R_max + alert distance)");
  for (std::size_t i = 0; i < n; ++i) box_.wrap(state_.position[i], state_.velocity[i], rate_);
  bodies_.resize(n);
  detect();
}

// Candidate pairs of the current state, sorted by (i, j); also measures the largest overlap.
void Engine::detect() {
  const std::size_t n = state_.size();
  double vmax = 0;
  for (std::size_t i = 0; i < n; ++i)
    vmax = std::max(vmax, fluctuating_velocity(state_, box_, rate_, i).norm());
  // Relative velocity of two grains within the cutoff: fluctuations plus the shear across
  // at most one cutoff (and gravity against a fixed grain); factor 2 for safety, since
  // the post-step velocities are not known yet.
  const double vrel = 2 * vmax + std::fabs(rate_) * (2 * max_radius_ + alert_min_) + dt_ * gravity_.norm();
  alert_ = std::max(alert_min_, 2 * dt_ * vrel);
  const double cutoff = 2 * max_radius_ + alert_;
  if (box_.lx < 2 * cutoff || (box_.periodic_y && box_.ly < 2 * cutoff))
    throw RuntimeFailure("grains move too fast for the box: contact-search cutoff " + std::to_string(cutoff) +
                         " exceeds half the box");

  cells_.build(state_.position, box_, cutoff);
  found_.clear();
  double overlap = 0;
  cells_.for_each_pair(state_.position, [&](int i, int j, const Vec2& d) {
    if (state_.fixed[i] && state_.fixed[j]) return;
    const double gap = d.norm() - state_.radius[i] - state_.radius[j];
    if (gap >= alert_) return;
    overlap = std::max(overlap, -gap);
    int k = box_.periodic_y ? int(std::round((state_.position[i].y() - state_.position[j].y()) / box_.ly)) : 0;
    if (i < j)
      found_.push_back({i, j, k, d.x(), d.y()});
    else
      found_.push_back({j, i, -k, -d.x(), -d.y()});
  });
  overlap_ = overlap;

  // Counting sort by i, then by j within each (short) bucket: O(candidates).
  bucket_.assign(n + 1, 0);
  for (const Candidate& c : found_) ++bucket_[c.i + 1];
  for (std::size_t i = 0; i < n; ++i) bucket_[i + 1] += bucket_[i];
  candidates_.resize(found_.size());
  for (const Candidate& c : found_) candidates_[bucket_[c.i]++] = c;
  // bucket_[i] now holds the end of bucket i, the start of bucket i + 1.
  int begin = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const int end = bucket_[i];
    for (int a = begin + 1; a < end; ++a)
      for (int b = a; b > begin && candidates_[b - 1].j > candidates_[b].j; --b)
        std::swap(candidates_[b - 1], candidates_[b]);
    begin = end;
  }
}

// Local problems of every candidate: normals, bounds, reduced masses, warm start.
void Engine::build_rows() {
  const double e = material_.restitution, et = material_.tangential_restitution;
  const std::size_t count = candidates_.size();
  rows_.resize(count);
  row_age_.resize(count);
  std::size_t p = 0;  // cursor into the previous step's memory (same sort order)
  for (std::size_t c = 0; c < count; ++c) {
    const Candidate& k = candidates_[c];
    const int i = k.i, j = k.j;
    const double dist = std::sqrt(k.dx * k.dx + k.dy * k.dy);
    const double nx = k.dx / dist, ny = k.dy / dist;
    const double ri = state_.radius[i], rj = state_.radius[j];
    const double gap = dist - ri - rj;
    const double shift = k.image * rate_ * box_.ly;  // x-velocity of j's image relative to j
    const double dvx = state_.velocity[i].x() - state_.velocity[j].x() - shift;
    const double dvy = state_.velocity[i].y() - state_.velocity[j].y();
    const double un = dvx * nx + dvy * ny;
    const double ut = -dvx * ny + dvy * nx - (ri * state_.angular_velocity[i] + rj * state_.angular_velocity[j]);
    double bn;
    if (gap <= 0 || gap + dt_ * un <= 0)
      bn = un < 0 ? -e * un : 0.0;
    else
      bn = -gap / dt_;
    const double wi = state_.fixed[i] ? 0.0 : 1.0 / state_.mass[i];
    const double wj = state_.fixed[j] ? 0.0 : 1.0 / state_.mass[j];

    Row& r = rows_[c];
    r.i = i;
    r.j = j;
    r.nx = nx;
    r.ny = ny;
    // The solver works on raw velocity differences: move the image shift into the bounds.
    r.bn = bn + shift * nx;
    r.bt = et * ut - shift * ny;
    r.inv_w = 1.0 / (wi + wj);
    r.pn = 0;
    r.pt = 0;
    row_age_[c] = 0;
    const std::uint64_t key = pair_key(i, j);
    while (p < prev_key_.size() && prev_key_[p] < key) ++p;
    if (p < prev_key_.size() && prev_key_[p] == key) {
      // Warm start from the recorded forces, so that a run restarted from a stored
      // frame (forces, not impulses, are on file) starts from the very same numbers.
      r.pn = prev_fn_[p] * dt_;
      r.pt = prev_ft_[p] * dt_;
      row_age_[c] = prev_age_[p];
    }
  }
}

// Free velocities, plus the warm-start impulses.
void Engine::load_bodies() {
  const std::size_t n = state_.size();
  for (std::size_t i = 0; i < n; ++i) {
    Body& b = bodies_[i];
    const bool mobile = !state_.fixed[i];
    b.vx = state_.velocity[i].x() + (mobile ? dt_ * gravity_.x() : 0.0);
    b.vy = state_.velocity[i].y() + (mobile ? dt_ * gravity_.y() : 0.0);
    b.spin = state_.radius[i] * state_.angular_velocity[i];
    b.inv_mass = mobile ? 1.0 / state_.mass[i] : 0.0;
  }
  for (const Row& r : rows_) {
    if (r.pn == 0 && r.pt == 0) continue;
    Body& a = bodies_[r.i];
    Body& b = bodies_[r.j];
    const double px = r.pn * r.nx - r.pt * r.ny, py = r.pn * r.ny + r.pt * r.nx;
    a.vx += a.inv_mass * px;
    a.vy += a.inv_mass * py;
    a.spin -= 2 * a.inv_mass * r.pt;
    b.vx -= b.inv_mass * px;
    b.vy -= b.inv_mass * py;
    b.spin -= 2 * b.inv_mass * r.pt;
  }
}

namespace {

// Exact solution of one contact's local problem given the other impulses: the normal
// impulse does not change u_t (W_nt = 0 for disks), so normal then tangential is exact.
// Templates only so that these helpers can take the engine's private Row and Body.
struct Local {
  double pn, pt;
};

template <class Row, class Body>
inline Local local_solve(const Row& r, const Body& a, const Body& b, double mu) {
  const double dvx = a.vx - b.vx, dvy = a.vy - b.vy;
  const double un = dvx * r.nx + dvy * r.ny;
  const double ut = dvy * r.nx - dvx * r.ny - (a.spin + b.spin);
  const double pn = std::max(0.0, r.pn + (r.bn - un) * r.inv_w);
  const double limit = mu * pn;
  const double pt = std::clamp(r.pt + (r.bt - ut) * (r.inv_w * (1.0 / 3.0)), -limit, limit);
  return {pn, pt};
}

// Velocity correction made by a local solve: |ΔP_n|·W_nn and |ΔP_t|·W_tt.
template <class Row>
inline double correction(const Row& r, const Local& l) {
  return std::max(std::fabs(l.pn - r.pn), 3 * std::fabs(l.pt - r.pt)) / r.inv_w;
}

}  // namespace

double Engine::sweep(bool forward) {
  const double mu = material_.friction;
  const std::ptrdiff_t count = std::ptrdiff_t(rows_.size());
  const std::ptrdiff_t first = forward ? 0 : count - 1, stride = forward ? 1 : -1;
  Body* bodies = bodies_.data();
  Row* rows = rows_.data();
  double worst = 0;
  for (std::ptrdiff_t c = first; c >= 0 && c < count; c += stride) {
    Row& r = rows[c];
    Body& a = bodies[r.i];
    Body& b = bodies[r.j];
    const Local l = local_solve(r, a, b, mu);
    const double dpn = l.pn - r.pn, dpt = l.pt - r.pt;
    // Compare before dividing: the division is only needed for a new maximum.
    const double d = std::max(std::fabs(dpn), 3 * std::fabs(dpt));
    if (d > worst * r.inv_w) worst = d / r.inv_w;
    r.pn = l.pn;
    r.pt = l.pt;
    const double px = dpn * r.nx - dpt * r.ny, py = dpn * r.ny + dpt * r.nx;
    a.vx += a.inv_mass * px;
    a.vy += a.inv_mass * py;
    a.spin -= 2 * a.inv_mass * dpt;
    b.vx -= b.inv_mass * px;
    b.vy -= b.inv_mass * py;
    b.spin -= 2 * b.inv_mass * dpt;
  }
  return worst;
}

// Largest correction any contact would still make, without changing anything.
double Engine::residual() const {
  const double mu = material_.friction;
  double worst = 0;
  for (const Row& r : rows_)
    worst = std::max(worst, correction(r, local_solve(r, bodies_[r.i], bodies_[r.j], mu)));
  return worst;
}

void Engine::solve() {
  StepReport& rep = report_;
  rep.iterations = 0;
  rep.contact_updates = 0;
  rep.residual = 0;
  rep.converged = true;
  if (rows_.empty()) return;
  const double upsilon = settings_.tolerance / dt_;
  for (int it = 1; it <= settings_.max_iterations; ++it) {
    const double worst = sweep(it % 2 == 1);  // alternate directions: symmetric Gauss–Seidel
    rep.iterations = it;
    rep.contact_updates += std::int64_t(rows_.size());
    // A sweep's own corrections only bound the residual; confirm on the final velocities.
    if (worst < upsilon) {
      const double res = residual();
      if (res < upsilon) {
        rep.residual = res * dt_;
        return;
      }
    }
  }
  rep.residual = residual() * dt_;
  rep.converged = false;
  ++unconverged_;
}

// Contacts of this step, from the impulses and the (still unchanged) pre-step state.
void Engine::record_contacts() {
  records_.clear();
  prev_key_.clear();
  prev_fn_.clear();
  prev_ft_.clear();
  prev_age_.clear();
  const double e = material_.restitution;
  for (std::size_t c = 0; c < rows_.size(); ++c) {
    const Row& r = rows_[c];
    if (!(r.pn > 0)) continue;
    const Candidate& k = candidates_[c];
    const int age = row_age_[c] + 1;
    const Vec2 n(r.nx, r.ny);
    const Vec2 vi = fluctuating_velocity(state_, box_, rate_, r.i);
    const Vec2 vj = fluctuating_velocity(state_, box_, rate_, r.j);
    const double shift = k.image * rate_ * box_.ly;
    const double un = (state_.velocity[r.i] - state_.velocity[r.j]).dot(n) - shift * r.nx;
    records_.pair.push_back({r.i, r.j});
    const double fn = r.pn / dt_, ft = r.pt / dt_;
    records_.normal_force.push_back(fn);
    records_.tangential_force.push_back(ft);
    records_.branch.emplace_back(k.dx, k.dy);
    records_.binary_force.push_back((1 + e) * r.inv_w * std::max(0.0, -un) / dt_);
    records_.pre_normal_velocity.push_back({vi.dot(n), vj.dot(n)});
    records_.age.push_back(age);
    prev_key_.push_back(pair_key(r.i, r.j));
    prev_fn_.push_back(fn);
    prev_ft_.push_back(ft);
    prev_age_.push_back(age);
  }
  report_.candidates = int(rows_.size());
  report_.contacts = int(records_.size());
}

void Engine::store_bodies() {
  for (std::size_t i = 0; i < state_.size(); ++i) {
    const Body& b = bodies_[i];
    state_.velocity[i] = Vec2(b.vx, b.vy);
    // Only grains that felt a tangential impulse change ω: s/R would otherwise perturb ω in the last bit.
    if (b.spin != state_.radius[i] * state_.angular_velocity[i]) state_.angular_velocity[i] = b.spin / state_.radius[i];
  }
}

void Engine::advance() {
  if (box_.periodic_y) box_.shift_offset(rate_ * box_.ly * dt_);
  for (std::size_t i = 0; i < state_.size(); ++i) {
    state_.position[i] += dt_ * state_.velocity[i];
    state_.orientation[i] += dt_ * state_.angular_velocity[i];
    if (!(state_.position[i].allFinite() && state_.velocity[i].allFinite() && std::isfinite(state_.angular_velocity[i])))
      throw RuntimeFailure("non-finite state of grain " + std::to_string(i) + " at step " +
                           std::to_string(steps_ + 1));
    // Wrapped with the offset at the end of the step: the image the grain moved into.
    box_.wrap(state_.position[i], state_.velocity[i], rate_);
  }
  ++steps_;
}

const StepReport& Engine::step() {
  build_rows();
  load_bodies();
  solve();
  record_contacts();
  store_bodies();
  advance();
  detect();
  report_.step = steps_;
  report_.max_overlap = overlap_;
  return report_;
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
