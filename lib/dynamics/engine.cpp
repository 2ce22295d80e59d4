#include "dynamics/engine.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "core/format.hpp"
#include "dynamics/branch_free.hpp"
#include "dynamics/capacity.hpp"
#include "dynamics/parallel.hpp"

namespace granflow {

namespace {

// Region solves (see solve()): after SolverSettings::region_solve_after sweeps of a step,
// then one every kRegionSolveEvery sweeps, each over a region one grain wider, seeded by the
// rows still corrected by kRegionSeedFraction of the largest correction or more. A dense
// solve costs O(rows³) (0.03 s at 100 rows, 0.6 s at 300: thousands of sweeps of a
// 10³-grain layer), so the k-th attempt may have k·kRegionRowsStep rows, kRegionRows at most.
// Measured on the quick 20° μ = 0.4 incline branch (docs/performance.md): seeds at every row
// above Υ, or 300 rows from the first attempt, solved fewer regions or cost 60 % more time.
constexpr int kRegionSolveEvery = 500;
constexpr double kRegionSeedFraction = 0.1;
constexpr int kRegionRowsStep = 100;
constexpr int kRegionRows = 300;

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
  require(set.region_solve_after >= 0, "solver region_solve_after must be >= 0");
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
  gauss_seidel_.skip_settled_rows(settings_.skip_settled_rows);
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
    throw RuntimeFailure("grains move too fast for the box: contact-search cutoff " + format_number(cutoff) +
                         " exceeds half the box (largest velocity fluctuation " + format_number(vmax) +
                         " about the mean flow, " + format_number(vmax * dt_) + " per time step of " +
                         format_number(dt_) + "; a smaller time step shortens the search)");

  if (moved) broad_.moved(vmax, rate_, dt_);
  report_.pairs_rebuilt = broad_.find(state_, box_, alert_, settings_.threads);
}

void Engine::solve() {
  StepReport& rep = report_;
  rep.iterations = 0;
  rep.contact_updates = 0;
  rep.cluster_solves = 0;
  rep.largest_cluster = 0;
  rep.region_solves = 0;
  rep.residual = 0;
  rep.converged = true;
  if (contacts_.rows().empty()) return;
  const double upsilon = settings_.tolerance / dt_, mu = material_.friction;
  const int threads = settings_.threads;
  const bool clusters = settings_.cluster_solves;
  const int region_after = settings_.region_solve_after;
  int next_cluster_solve = 2, cluster_wait = 1;
  // The residual check (see GaussSeidel::check()), counted in contact_updates.
  auto check = [&](bool everywhere) {
    return gauss_seidel_.check(contacts_, tiling_, mu, upsilon, everywhere, settings_.full_checks, threads,
                               rep.contact_updates);
  };
  gauss_seidel_.select_working_set(contacts_, tiling_, vrel_, threads);
  clusters_.reset(contacts_.size());
  for (int it = 1; it <= settings_.max_iterations; ++it) {
    const bool forward = it % 2 == 1;  // alternate directions: symmetric Gauss–Seidel
    const double worst = gauss_seidel_.sweep(contacts_, tiling_, mu, forward, upsilon, threads, rep.contact_updates);
    rep.iterations = it;
    if (worst < upsilon) {
      // A sweep's own corrections only bound the residual; confirm on the final velocities,
      // on every candidate.
      const double res = check(true);  // marks the tiles still off
      if (res < upsilon) {
        rep.residual = res * dt_;
        return;
      }
    } else if (mu > 0 && region_after > 0 && it >= region_after && (it - region_after) % kRegionSolveEvery == 0) {
      // Still unconverged after many sweeps: solve the places that hold the step up exactly,
      // each time over a region one grain wider and allowed to be larger.
      const int attempt = (it - region_after) / kRegionSolveEvery;
      const RegionSolver::Outcome o = regions_.solve(
          contacts_, tiling_, gauss_seidel_.work(), gauss_seidel_.row_flags(), gauss_seidel_.moved(),
          gauss_seidel_.touched(), mu, upsilon, kRegionSeedFraction, 1 + attempt,
          std::min(kRegionRows, kRegionRowsStep * (1 + attempt)));
      rep.region_solves += o.solved;
      gauss_seidel_.revisit_all();
    } else if (clusters && it >= next_cluster_solve &&
               100 * gauss_seidel_.status_changes() <= gauss_seidel_.active_rows()) {
      // The active set has (nearly) settled: solve its clusters exactly. While it keeps
      // changing, each solve waits twice as many sweeps as the one before, so that their
      // number stays logarithmic in the sweeps of the step. The pass marks the tiles of the
      // rows it solved, to be swept next.
      gauss_seidel_.revisit_all();
      const int largest = clusters_.solve(contacts_, tiling_, gauss_seidel_.work(), gauss_seidel_.row_flags(),
                                          gauss_seidel_.moved(), gauss_seidel_.touched(), mu, upsilon, threads);
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
  const StepInput in{state_, box_, rate_, dt_, material_, gravity_, settings_.threads, settings_.activation};
  tiling_.order(state_, box_, max_radius_, alert_, settings_.threads);
  contacts_.build(in, broad_.candidates(), tiling_);
  contacts_.load_bodies(in, tiling_);
  solve();
  // Without friction the flags say which rows bear (kBearing exactly when P_n > 0).
  const bool flagged = material_.friction == 0;
  const ContactRows::Tally tally =
      contacts_.record(in, broad_.candidates(), flagged ? gauss_seidel_.row_flags() : nullptr, kBearing);
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
  return broad_.bytes() + tiling_.bytes() + contacts_.bytes() + gauss_seidel_.bytes() + clusters_.bytes() +
         regions_.bytes() +
         heap_bytes(s.position) + heap_bytes(s.velocity) + heap_bytes(s.orientation) + heap_bytes(s.angular_velocity) +
         heap_bytes(s.radius) + heap_bytes(s.mass) + heap_bytes(s.fixed);
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
