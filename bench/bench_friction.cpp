// Frictional simple shear (μ = 0.4, e = 0, γ̇ = 1, γ̇dt = 10⁻³, tolerance 10⁻¹⁰: gf-shear's
// defaults with --friction 0.4 --restitution 0): the work per step and the time per unit
// strain of the contact solver, Gauss–Seidel only against the default settings, on the
// same steps from the same sheared state.
//
//   build-*/bench/bench_friction                                        everything (see below)
//   build-*/bench/bench_friction --benchmark_filter='Friction/1000/'    quick: N = 1000 only
//   build-*/bench/bench_friction --benchmark_filter='Friction/.*/780/'  ν = 0.78, both sizes
//   build-*/bench/bench_friction --benchmark_filter=FrictionSpeedup     the two solvers alternating
//
// BM_Friction/N/ν·1000/solver: solver 0 = Gauss–Seidel only (SolverSettings::cluster_solves
// = false, region_solve_after = 0), 1 = the default settings (cluster_solves = true, region
// solves after 1 000 sweeps), 2 = the default without the region solves (region_solve_after
// = 0, the solver before them), 3 = the default without skipping settled rows in the sweeps
// (skip_settled_rows = false, the solver before it). Every (N, ν) is first sheared
// from gf-pack's packing at rest (the affine start) with the default settings for
// warm_steps(N, ν) steps, once (cached); each case then times timed_steps(N, ν) steps of a
// fresh engine that continues from that state (grain state, box with its Lees–Edwards
// offset, step counter and the last step's contact memory, as gf-shear resumes from a
// checkpoint), so both solvers start from the same state. The warm-up is not timed.
// Every case runs once (a run is deterministic). Counters, per step unless said:
//   s/strain     CPU time of the process per unit strain (one thread)
//   sweeps       mean Gauss–Seidel sweeps          clusters   mean StepReport::cluster_solves
//   regions      mean StepReport::region_solves
//   largest      largest cluster (active rows) solved exactly, over the timed steps
//   contacts     mean contacts (P_n > 0)           updates/s  local contact solves per second
//   unconverged  timed steps that reached max_iterations (completed anyway, counted)
//
// BM_FrictionSpeedup/N/ν·1000: both solvers from the same warmed state, alternating (0, 1,
// 0, 1, ...) kSpeedupReps times over the same timed steps; the fastest CPU time of each is
// kept, so that a busy moment of the shared machine does not decide the ratio:
//   s/strain 0, s/strain 1, speedup = s/strain 0 / s/strain 1, sweeps 0, sweeps 1,
//   clusters 1, same = 1 if both solvers ended in bit-identical grain states (true as long
//   as the default settings solve frictional contacts by Gauss–Seidel alone).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <ctime>
#include <map>
#include <utility>

#include "dynamics/engine.hpp"
#include "packing/packing.hpp"

namespace {

using namespace granflow;

constexpr double kFriction = 0.4, kRestitution = 0.0, kRate = 1.0, kStrainStep = 1e-3;
constexpr int kSpeedupReps = 3;

// Warm-up: 0.5 strain units at N = 10³; 0.3 at N = 10⁴, where today's solver takes 0.2 s
// per step at ν = 0.78 and about 1.3 s at 0.80, so that the start-up transient is not over
// there (performance.md says so beside the figures).
std::int64_t warm_steps(std::int64_t grains, double) { return grains <= 1000 ? 500 : 300; }

// Timed steps: 200 at N = 10³ (0.2 strain); at N = 10⁴, 50 below ν = 0.78 and 20 above,
// few enough that the whole default run stays near half an hour with today's solver.
std::int64_t timed_steps(std::int64_t grains, double nu) {
  if (grains <= 1000) return 200;
  return nu < 0.775 ? 50 : 20;
}

double cpu_seconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// Solver 0, 1, 2 or 3 (see the head of the file).
SolverSettings settings(int solver) {
  SolverSettings s;  // tolerance 10⁻¹⁰, one thread
  s.cluster_solves = solver != 0;
  if (solver == 0 || solver == 2) s.region_solve_after = 0;
  s.skip_settled_rows = solver != 0 && solver != 3;
  return s;
}

const Material kMaterial{kRestitution, 0.0, kFriction};

// The sheared state of each (N, ν), made once with the default settings.
const Engine& warmed(std::int64_t grains, double nu) {
  static std::map<std::pair<std::int64_t, double>, Engine> cache;
  auto it = cache.find({grains, nu});
  if (it == cache.end()) {
    PackingParams p;
    p.grains = grains;
    p.packing_fraction = nu;
    const Packing packing = make_biperiodic_packing(p);
    GrainState state = make_grains(packing.position, packing.radius);
    add_affine_flow(state, packing.box, kRate);
    Engine engine(std::move(state), packing.box, kRate, kMaterial, settings(1), kStrainStep / kRate);
    for (std::int64_t k = warm_steps(grains, nu); k > 0; --k) engine.step();
    it = cache.emplace(std::make_pair(grains, nu), std::move(engine)).first;
  }
  return it->second;
}

// A fresh engine with the given solver that continues `from` exactly as a resumed run would.
Engine continue_with(const Engine& from, int solver) {
  Engine engine(from.state(), from.box(), from.rate(), from.material(), settings(solver), from.dt());
  engine.restore(from.step_count(), from.memory());
  return engine;
}

struct Work {
  double seconds = 0, sweeps = 0, clusters = 0, regions = 0, contacts = 0, updates = 0, unconverged = 0;
  int largest = 0;
};

Work run(Engine& engine, std::int64_t steps) {
  Work w;
  const double start = cpu_seconds();
  for (std::int64_t k = 0; k < steps; ++k) {
    const StepReport& r = engine.step();
    w.sweeps += r.iterations;
    w.clusters += r.cluster_solves;
    w.regions += r.region_solves;
    w.contacts += r.contacts;
    w.updates += double(r.contact_updates);
    w.unconverged += !r.converged;
    w.largest = std::max(w.largest, r.largest_cluster);
  }
  w.seconds = cpu_seconds() - start;
  return w;
}

void BM_Friction(benchmark::State& state) {
  const std::int64_t grains = state.range(0);
  const double nu = double(state.range(1)) / 1000.0;
  const int solver = int(state.range(2));
  const std::int64_t steps = timed_steps(grains, nu);
  const Engine& start = warmed(grains, nu);
  Work w;
  for (auto _ : state) {
    Engine engine = continue_with(start, solver);
    w = run(engine, steps);
  }
  const double n = double(steps);
  state.counters["s/strain"] = w.seconds / (n * kStrainStep);
  state.counters["sweeps"] = w.sweeps / n;
  state.counters["clusters"] = w.clusters / n;
  state.counters["regions"] = w.regions / n;
  state.counters["largest"] = w.largest;
  state.counters["contacts"] = w.contacts / n;
  state.counters["updates/s"] = w.updates / w.seconds;
  state.counters["unconverged"] = w.unconverged;
  state.counters["steps"] = n;
}

void BM_FrictionSpeedup(benchmark::State& state) {
  const std::int64_t grains = state.range(0);
  const double nu = double(state.range(1)) / 1000.0;
  const std::int64_t steps = timed_steps(grains, nu);
  const Engine& start = warmed(grains, nu);
  double best[2] = {1e300, 1e300};
  Work last[2];
  bool same = true;
  for (auto _ : state)
    for (int rep = 0; rep < kSpeedupReps; ++rep) {
      Engine engine[2] = {continue_with(start, 0), continue_with(start, 1)};
      for (int solver : {0, 1}) {
        last[solver] = run(engine[solver], steps);
        best[solver] = std::min(best[solver], last[solver].seconds);
      }
      const GrainState &a = engine[0].state(), &b = engine[1].state();
      same = same && a.position == b.position && a.velocity == b.velocity && a.angular_velocity == b.angular_velocity;
    }
  const double n = double(steps);
  state.counters["s/strain 0"] = best[0] / (n * kStrainStep);
  state.counters["s/strain 1"] = best[1] / (n * kStrainStep);
  state.counters["speedup"] = best[0] / best[1];
  state.counters["sweeps 0"] = last[0].sweeps / n;
  state.counters["sweeps 1"] = last[1].sweeps / n;
  state.counters["clusters 1"] = last[1].clusters / n;
  state.counters["unconverged 0"] = last[0].unconverged;
  state.counters["unconverged 1"] = last[1].unconverged;
  state.counters["same"] = same;
}

void friction_grid(benchmark::internal::Benchmark* b) {
  for (std::int64_t grains : {1000, 10000})
    for (std::int64_t nu : {700, 760, 780, 800, 820})
      for (std::int64_t solver : {0, 1, 2, 3}) b->Args({grains, nu, solver});
}

}  // namespace

BENCHMARK(BM_Friction)->Apply(friction_grid)->Iterations(1)->Unit(benchmark::kMillisecond);
// Side by side at ν = 0.78 (the target point), both sizes.
BENCHMARK(BM_FrictionSpeedup)->Args({1000, 780})->Args({10000, 780})->Iterations(1)->Unit(benchmark::kSecond);

BENCHMARK_MAIN();
