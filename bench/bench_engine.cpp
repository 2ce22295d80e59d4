// Contact Dynamics engine: cost of simple shear (Lees–Edwards, e = 0.5) from the affine
// start in biperiodic packings, per step, per contact update and per unit strain.
//
//   build-*/bench/bench_engine                                       everything (~1 h)
//   build-*/bench/bench_engine --benchmark_filter='Shear/1000/'      quick: N = 1000 only (~1 min)
//   build-*/bench/bench_engine --benchmark_filter='Shear/2000/'      time to solution, N = 2000
//   build-*/bench/bench_engine --benchmark_filter=Tolerance          p, s, T at tolerance 1e-6 vs 1e-10
//   build-*/bench/bench_engine --benchmark_filter=Threads            1 vs 2 threads at N = 10⁵
//   build-*/bench/bench_engine --benchmark_filter=Speedup            the same, alternating, best of each
//   build-*/bench/bench_engine --benchmark_filter=SweepsOnly         Gauss–Seidel without cluster solves
//
// Arguments of BM_Shear and BM_Threads: N, ν·1000, μ·100, γ̇dt·10⁴, warm-up steps (not
// timed), timed steps, threads. Every case runs once (a run is deterministic; repetitions
// would only measure the noise of the machine). BM_Shear's counters use the CPU time of the
// process, which other work on the machine inflates least; BM_Threads' the wall time:
//   s/strain         time per unit strain            steps/s      steps per second
//   updates/s        local contact solves per second (one visit of one contact, in a sweep
//                    or a residual check)
//   sweeps           mean Gauss–Seidel sweeps per step   clusters   mean cluster solves per step
//   largest          active rows of the largest cluster solved exactly in a timed step
//   candidates, contacts   per step (mean)            rebuilds     pair-list rebuilds per step
//   ns/grain         time per grain per step        B/grain      Engine::allocated_bytes() / N
//   unconverged      steps that reached max_iterations
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <ctime>
#include <map>
#include <utility>

#include "dynamics/engine.hpp"
#include "packing/packing.hpp"
#include "shear/observables.hpp"

namespace {

using namespace granflow;

// Packings are deterministic and take a while at N = 10⁵: build each (N, ν) once.
const Packing& packing(std::int64_t grains, double nu) {
  static std::map<std::pair<std::int64_t, double>, Packing> cache;
  auto it = cache.find({grains, nu});
  if (it == cache.end()) {
    PackingParams p;
    p.grains = grains;
    p.packing_fraction = nu;
    it = cache.emplace(std::make_pair(grains, nu), make_biperiodic_packing(p)).first;
  }
  return it->second;
}

Engine sheared(std::int64_t grains, double nu, double mu, double strain_step, double tolerance, int threads = 1,
               bool cluster_solves = true) {
  const Packing& p = packing(grains, nu);
  GrainState state = make_grains(p.position, p.radius);
  const double rate = 1.0;
  add_affine_flow(state, p.box, rate);
  SolverSettings settings;
  settings.tolerance = tolerance;
  settings.threads = threads;
  settings.cluster_solves = cluster_solves;
  return Engine(std::move(state), p.box, rate, Material{0.5, 0.0, mu}, settings, strain_step / rate);
}

// CPU time of the process and wall time, in seconds.
double cpu_seconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

double wall_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// wall: time with the wall clock, else with the CPU time of the process.
void run_shear(benchmark::State& state, bool wall, bool cluster_solves = true) {
  const std::int64_t grains = state.range(0);
  const double nu = state.range(1) / 1000.0, mu = state.range(2) / 100.0, strain_step = state.range(3) * 1e-4;
  const std::int64_t warm = state.range(4), steps = state.range(5);
  const int threads = int(state.range(6));
  Engine engine = sheared(grains, nu, mu, strain_step, 1e-10, threads, cluster_solves);
  for (std::int64_t k = 0; k < warm; ++k) engine.step();
  double sweeps = 0, clusters = 0, candidates = 0, contacts = 0, updates = 0, rebuilds = 0, unconverged = 0;
  double largest = 0;
  double seconds = 0;
  for (auto _ : state) {
    const double start_cpu = cpu_seconds(), start_wall = wall_seconds();
    for (std::int64_t k = 0; k < steps; ++k) {
      const StepReport& r = engine.step();
      sweeps += r.iterations;
      clusters += r.cluster_solves;
      largest = std::max(largest, double(r.largest_cluster));
      candidates += r.candidates;
      contacts += r.contacts;
      updates += double(r.contact_updates);
      rebuilds += r.pairs_rebuilt;
      unconverged += !r.converged;
    }
    seconds = wall ? wall_seconds() - start_wall : cpu_seconds() - start_cpu;
  }
  const double n = double(steps);
  state.counters["s/strain"] = seconds / (n * strain_step);
  state.counters["steps/s"] = n / seconds;
  state.counters["updates/s"] = updates / seconds;
  state.counters["ns/grain"] = 1e9 * seconds / (n * double(grains));
  state.counters["sweeps"] = sweeps / n;
  state.counters["clusters"] = clusters / n;
  state.counters["largest"] = largest;
  state.counters["candidates"] = candidates / n;
  state.counters["contacts"] = contacts / n;
  state.counters["rebuilds"] = rebuilds / n;
  state.counters["B/grain"] = double(engine.allocated_bytes()) / double(grains);
  state.counters["unconverged"] = unconverged;
}

void BM_Shear(benchmark::State& state) { run_shear(state, false); }

void BM_Threads(benchmark::State& state) { run_shear(state, true); }

// Speed-up from 1 to 2 threads on the same warmed-up state (wall time): copies of the engine
// run the same steps with 1 and with 2 threads, alternately, `reps` times each; the fastest
// of each is kept, so that a busy moment of the machine does not decide the ratio.
// Arguments: N, ν·1000, μ·100, γ̇dt·10⁴, warm-up steps, timed steps, reps.
void BM_Speedup(benchmark::State& state) {
  const std::int64_t grains = state.range(0), warm = state.range(4), steps = state.range(5), reps = state.range(6);
  Engine warmed = sheared(grains, state.range(1) / 1000.0, state.range(2) / 100.0, state.range(3) * 1e-4, 1e-10, 2);
  for (std::int64_t k = 0; k < warm; ++k) warmed.step();
  double best[2] = {1e300, 1e300};
  std::size_t bytes[2] = {0, 0};
  for (auto _ : state)
    for (std::int64_t rep = 0; rep < reps; ++rep)
      for (int threads : {1, 2}) {
        Engine engine = warmed;
        engine.set_threads(threads);
        const double start = wall_seconds();
        for (std::int64_t k = 0; k < steps; ++k) engine.step();
        best[threads - 1] = std::min(best[threads - 1], wall_seconds() - start);
        bytes[threads - 1] = engine.allocated_bytes();
      }
  state.counters["s/step 1"] = best[0] / double(steps);
  state.counters["s/step 2"] = best[1] / double(steps);
  state.counters["speedup"] = best[0] / best[1];
  state.counters["B/grain 1"] = double(bytes[0]) / double(grains);
  state.counters["B/grain 2"] = double(bytes[1]) / double(grains);
}

// Gauss–Seidel alone (no exact cluster solves): the sweep kernel's own update rate.
void BM_SweepsOnly(benchmark::State& state) { run_shear(state, false, false); }

// Steady averages of p, s, T (in units of γ̇² with γ̇ = 1) at N = 1000, ν = 0.8, μ = 0 over
// 2 strain units after 0.5 of transient, at the tolerance given in units of 10⁻¹².
void BM_Tolerance(benchmark::State& state) {
  const double tolerance = state.range(0) * 1e-12, strain_step = 1e-3;
  Engine engine = sheared(1000, 0.8, 0.0, strain_step, tolerance);
  for (int k = 0; k < 500; ++k) engine.step();
  const int steps = 2000;
  double p = 0, s = 0, t = 0, sweeps = 0, seconds = 0;
  for (auto _ : state) {
    const double cpu = cpu_seconds();
    for (int k = 0; k < steps; ++k) {
      sweeps += engine.step().iterations;
      const Mat2 sigma = stress(engine.state(), engine.box(), engine.rate(), engine.contacts()).total();
      p += pressure(sigma);
      s += shear_stress(sigma);
      t += granular_temperature(engine.state(), engine.box(), engine.rate());
    }
    seconds = cpu_seconds() - cpu;
  }
  state.counters["p"] = p / steps;
  state.counters["s"] = s / steps;
  state.counters["T"] = t / steps;
  state.counters["sweeps"] = sweeps / steps;
  state.counters["s/strain"] = seconds / (steps * strain_step);
}

}  // namespace

// Scaling with N at ν = 0.8, γ̇dt = 10⁻³: in steady state, after 2 strain units, and from
// the affine start (transient included), for a like-for-like comparison at N = 10⁵. The
// start-up transient outlasts strain 0.5 in large systems (the work per step settles by
// ≈ 1.3 at N = 10⁵, T by ≈ 1.3 at 10⁴); 4000 steps at N = 10³, whose cost per step
// fluctuates by ±10 % over half a strain unit with the system's own fluctuations.
BENCHMARK(BM_Shear)
    ->Args({1000, 800, 0, 10, 2000, 4000, 1})
    ->Args({10000, 800, 0, 10, 2000, 500, 1})
    ->Args({100000, 800, 0, 10, 2000, 200, 1})
    ->Args({1000, 800, 0, 10, 0, 200, 1})
    ->Args({10000, 800, 0, 10, 0, 200, 1})
    ->Args({100000, 800, 0, 10, 0, 200, 1})
    ->Args({100000, 800, 0, 10, 0, 5, 1})
    ->Args({1000, 800, 40, 10, 500, 200, 1})
    ->Args({1000, 800, 40, 10, 0, 50, 1})
    ->Args({10000, 800, 40, 10, 0, 50, 1})
    ->Args({100000, 800, 40, 10, 0, 10, 1})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
// Time to solution at N = 2000 (the peer comparison), γ̇dt = 10⁻³ and 5·10⁻³: 1 strain after 0.5.
BENCHMARK(BM_Shear)
    ->Args({2000, 600, 0, 10, 500, 1000, 1})
    ->Args({2000, 800, 0, 10, 500, 1000, 1})
    ->Args({2000, 600, 0, 50, 100, 200, 1})
    ->Args({2000, 800, 0, 50, 100, 200, 1})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
// Without the exact cluster solves, μ = 0, in steady state: more sweeps, slower per strain,
// but the rate of the Gauss–Seidel kernel itself.
BENCHMARK(BM_SweepsOnly)
    ->Args({1000, 800, 0, 10, 500, 200, 1})
    ->Args({10000, 800, 0, 10, 500, 50, 1})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
// Threads at N = 10⁵ (wall time): 1 and 2 from the same start.
BENCHMARK(BM_Threads)
    ->Args({100000, 800, 0, 10, 20, 50, 1})
    ->Args({100000, 800, 0, 10, 20, 50, 2})
    ->Args({100000, 800, 40, 10, 0, 5, 1})
    ->Args({100000, 800, 40, 10, 0, 5, 2})
    ->Iterations(1)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
// Threads in steady state at N = 10⁵ (2 strain units of warm-up, as BM_Shear's steady
// cases), μ = 0, and μ = 0.4 from rest.
BENCHMARK(BM_Speedup)
    ->Args({100000, 800, 0, 10, 2000, 30, 3})
    ->Args({100000, 800, 40, 10, 0, 3, 2})
    ->Iterations(1)
    ->UseRealTime()
    ->Unit(benchmark::kSecond);
BENCHMARK(BM_Tolerance)->Arg(1000000)->Arg(100)->Iterations(1)->Unit(benchmark::kSecond);

BENCHMARK_MAIN();
