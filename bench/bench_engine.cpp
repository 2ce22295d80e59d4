// Contact Dynamics engine: cost of simple shear (Lees–Edwards, e = 0.5) from the affine
// start in biperiodic packings, per step, per contact update and per unit strain.
//
//   build-*/bench/bench_engine                                       everything (~1 h)
//   build-*/bench/bench_engine --benchmark_filter='Shear/1000/'      quick: N = 1000 only
//   build-*/bench/bench_engine --benchmark_filter='Shear/2000/'      time to solution, N = 2000
//   build-*/bench/bench_engine --benchmark_filter=Tolerance          p, s, T at tolerance 1e-6 vs 1e-10
//
// Arguments of BM_Shear: N, ν·1000, μ·100, γ̇dt·10⁴, warm-up steps (not timed), timed steps.
// Every case runs once (a run is deterministic; repetitions would only measure the noise of
// the machine); times are the CPU time of the process. Counters:
//   s/strain         time per unit strain            steps/s      steps per second
//   updates/s        local contact solves per second (one visit of one contact, in a sweep
//                    or a residual check)
//   sweeps           mean Gauss–Seidel sweeps per step   clusters   mean cluster solves per step
//   candidates, contacts   per step (mean)            rebuilds     pair-list rebuilds per step
//   ns/grain         time per grain per step        B/grain      Engine::allocated_bytes() / N
//   unconverged      steps that reached max_iterations
#include <benchmark/benchmark.h>

#include <cstdint>
#include <map>
#include <utility>

#include "dynamics/engine.hpp"
#include "dynamics/observables.hpp"
#include "packing/packing.hpp"

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

Engine sheared(std::int64_t grains, double nu, double mu, double strain_step, double tolerance) {
  const Packing& p = packing(grains, nu);
  GrainState state = make_grains(p.position, p.radius);
  const double rate = 1.0;
  add_affine_flow(state, p.box, rate);
  SolverSettings settings;
  settings.tolerance = tolerance;
  return Engine(std::move(state), p.box, rate, Material{0.5, 0.0, mu}, settings, strain_step / rate);
}

void BM_Shear(benchmark::State& state) {
  const std::int64_t grains = state.range(0);
  const double nu = state.range(1) / 1000.0, mu = state.range(2) / 100.0, strain_step = state.range(3) * 1e-4;
  const std::int64_t warm = state.range(4), steps = state.range(5);
  Engine engine = sheared(grains, nu, mu, strain_step, 1e-10);
  for (std::int64_t k = 0; k < warm; ++k) engine.step();
  double sweeps = 0, clusters = 0, candidates = 0, contacts = 0, updates = 0, rebuilds = 0, unconverged = 0;
  for (auto _ : state) {
    for (std::int64_t k = 0; k < steps; ++k) {
      const StepReport& r = engine.step();
      sweeps += r.iterations;
      clusters += r.cluster_solves;
      candidates += r.candidates;
      contacts += r.contacts;
      updates += double(r.contact_updates);
      rebuilds += r.pairs_rebuilt;
      unconverged += !r.converged;
    }
  }
  const double n = double(steps);
  using benchmark::Counter;
  state.counters["s/strain"] = Counter(n * strain_step, Counter::kIsRate | Counter::kInvert);
  state.counters["steps/s"] = Counter(n, Counter::kIsRate);
  state.counters["updates/s"] = Counter(updates, Counter::kIsRate);
  state.counters["ns/grain"] = Counter(1e-9 * n * double(grains), Counter::kIsRate | Counter::kInvert);
  state.counters["sweeps"] = sweeps / n;
  state.counters["clusters"] = clusters / n;
  state.counters["candidates"] = candidates / n;
  state.counters["contacts"] = contacts / n;
  state.counters["rebuilds"] = rebuilds / n;
  state.counters["B/grain"] = double(engine.allocated_bytes()) / double(grains);
  state.counters["unconverged"] = unconverged;
}

// Steady averages of p, s, T (in units of γ̇² with γ̇ = 1) at N = 1000, ν = 0.8, μ = 0 over
// 2 strain units after 0.5 of transient, at the tolerance given in units of 10⁻¹².
void BM_Tolerance(benchmark::State& state) {
  const double tolerance = state.range(0) * 1e-12, strain_step = 1e-3;
  Engine engine = sheared(1000, 0.8, 0.0, strain_step, tolerance);
  for (int k = 0; k < 500; ++k) engine.step();
  const int steps = 2000;
  double p = 0, s = 0, t = 0, sweeps = 0;
  for (auto _ : state) {
    for (int k = 0; k < steps; ++k) {
      sweeps += engine.step().iterations;
      const Mat2 sigma = stress(engine.state(), engine.box(), engine.rate(), engine.contacts()).total();
      p += pressure(sigma);
      s += shear_stress(sigma);
      t += granular_temperature(engine.state(), engine.box(), engine.rate());
    }
  }
  using benchmark::Counter;
  state.counters["p"] = p / steps;
  state.counters["s"] = s / steps;
  state.counters["T"] = t / steps;
  state.counters["sweeps"] = sweeps / steps;
  state.counters["s/strain"] = Counter(steps * strain_step, Counter::kIsRate | Counter::kInvert);
}

}  // namespace

// Scaling with N at ν = 0.8, γ̇dt = 10⁻³: steady state after 0.5 strain at N = 10³, 10⁴ (μ = 0);
// from the affine start (transient included) at every N, for a like-for-like comparison.
BENCHMARK(BM_Shear)
    ->Args({1000, 800, 0, 10, 500, 1000})
    ->Args({10000, 800, 0, 10, 500, 300})
    ->Args({1000, 800, 0, 10, 0, 200})
    ->Args({10000, 800, 0, 10, 0, 200})
    ->Args({100000, 800, 0, 10, 0, 200})
    ->Args({1000, 800, 40, 10, 500, 200})
    ->Args({1000, 800, 40, 10, 0, 50})
    ->Args({10000, 800, 40, 10, 0, 50})
    ->Args({100000, 800, 40, 10, 0, 20})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
// Time to solution at N = 2000 (the peer comparison), γ̇dt = 10⁻³ and 5·10⁻³: 1 strain after 0.5.
BENCHMARK(BM_Shear)
    ->Args({2000, 600, 0, 10, 500, 1000})
    ->Args({2000, 800, 0, 10, 500, 1000})
    ->Args({2000, 600, 0, 50, 100, 200})
    ->Args({2000, 800, 0, 50, 100, 200})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Tolerance)->Arg(1000000)->Arg(100)->Iterations(1)->Unit(benchmark::kSecond);

BENCHMARK_MAIN();
