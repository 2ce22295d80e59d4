// Biperiodic grow-and-relax packings: wall time against N at ν = 0.82, and time and
// residual overlap at ν = 0.80 and near jamming, ν = 0.84. One run per case:
// a packing is deterministic, so repetitions only measure timer noise.
//   build-*/bench/bench_packing [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include "packing/packing.hpp"

namespace {

void BM_BiperiodicPacking(benchmark::State& state) {
  granflow::PackingParams p;
  p.grains = state.range(0);
  p.packing_fraction = double(state.range(1)) / 1000;
  granflow::Packing result;
  for (auto _ : state) result = granflow::make_biperiodic_packing(p);
  state.counters["nu"] = result.packing_fraction;
  state.counters["max_overlap/sigma"] = result.max_overlap / p.mean_diameter;
  state.counters["fire_steps"] = double(result.iterations);
  state.counters["ns/grain/step"] = 1e9 * result.seconds / double(result.iterations * p.grains);
}

void BM_InclinePacking(benchmark::State& state) {
  granflow::InclineParams p;
  p.width = double(state.range(0));
  p.height = 40;
  for (auto _ : state) benchmark::DoNotOptimize(granflow::make_incline_packing(p));
}

}  // namespace

// Scaling with N at ν = 0.82 (ν is passed in thousandths).
BENCHMARK(BM_BiperiodicPacking)
    ->ArgsProduct({{1000, 10000, 100000}, {820}})
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();
// Residual overlap across ν at N = 10^4.
BENCHMARK(BM_BiperiodicPacking)
    ->ArgsProduct({{10000}, {800, 840}})
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();
BENCHMARK(BM_InclinePacking)->Arg(100)->Arg(1000)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
