// gf-incline's time loop without I/O: one Contact Dynamics step plus the every-step
// layer check and profile sample, in a dense layer flowing down a 12° incline (μ = 0,
// e = 0.5, dt = 2·10⁻³ τ, tolerance 10⁻¹⁰ as gf-incline's defaults), at N = 10³ and 10⁴
// mobile grains (base 40 and 400 mean diameters, layer ≈ 25 diameters thick). The layer
// is first released from gf-pack's dilute start and let settle and start flowing for
// 30 τ (not timed). Reports steps/s, solver sweeps per step and the wall time of the
// profile sample per step.
//   build-*/bench/bench_incline [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <memory>

#include "dynamics/engine.hpp"
#include "incline/observer.hpp"
#include "incline/start.hpp"
#include "packing/packing.hpp"

namespace {
using namespace granflow;

struct Flow {
  std::unique_ptr<Engine> engine;
  std::unique_ptr<ProfileAccumulator> profiles;
};

Flow settled_flow(std::int64_t mobile) {
  InclineParams p;
  p.grains = mobile;
  p.width = double(mobile) / 25;
  p.height = 25;  // validated, but the layer follows from the number of grains
  p.seed = 1;
  const Packing packing = make_incline_packing(p);
  GrainState grains = make_grains(packing.position, packing.radius);
  grains.fixed = packing.fixed;
  double radius = 0;
  for (std::size_t i = 0; i < grains.size(); ++i)
    if (!grains.fixed[i]) radius += grains.radius[i];
  radius /= double(mobile);
  const double tau = std::sqrt(radius), dt = 2e-3 * tau;
  const Vec2 gravity = incline_gravity(1, 12);
  Material material;
  material.restitution = 0.5;
  Flow flow;
  flow.engine = std::make_unique<Engine>(grains, packing.box, 0.0, material, SolverSettings{}, dt, gravity);
  while (flow.engine->time() < 30 * tau) flow.engine->step();
  flow.profiles = std::make_unique<ProfileAccumulator>(profile_grid(packing.box, 6 * radius), 5000);
  return flow;
}

void BM_InclineStep(benchmark::State& state) {
  Flow flow = settled_flow(state.range(0));
  Engine& engine = *flow.engine;
  double sample_seconds = 0;
  std::int64_t sweeps = 0;
  for (auto _ : state) {
    sweeps += engine.step().iterations;
    const auto t0 = std::chrono::steady_clock::now();
    sample_incline(engine, *flow.profiles);
    sample_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  const double steps = double(state.iterations());
  state.counters["steps/s"] = benchmark::Counter(steps, benchmark::Counter::kIsRate);
  state.counters["sweeps/step"] = double(sweeps) / steps;
  state.counters["sample_s/step"] = sample_seconds / steps;
}

}  // namespace

BENCHMARK(BM_InclineStep)->Arg(1000)->Iterations(2000)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_InclineStep)->Arg(10000)->Iterations(200)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
