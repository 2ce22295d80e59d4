// Speed of D²min (stz/d2min.hpp) on a frame pair of N = 10⁴ and 10⁵ grains: a dense random
// configuration (a square lattice of spacing 1, each point jittered by ±0.3, i.e. disks of
// diameter ≈ 1 at ν ≈ 0.8) in a Lees–Edwards box, neighbours within two diameters (≈ 12 per
// grain), the current frame a shear of strain 0.05 plus random non-affine jitter. Three
// parts: the whole computation (neighbour search and fit), the fit on bonds found once, and
// the unwrapping of two stored frames.
#include <benchmark/benchmark.h>

#include <cmath>

#include "core/random.hpp"
#include "stz/d2min.hpp"

using namespace granflow;
using namespace granflow::stz;

namespace {

struct FramePair {
  Box box;
  std::vector<Vec2> reference, current, displacement;
  double offset_change = 0;
};

FramePair frame_pair(int n, std::uint64_t seed) {
  Rng rng(seed);
  const int side = int(std::round(std::sqrt(double(n))));
  FramePair p;
  p.box = Box{double(side), double(side), true, 0.3 * side};
  const double strain = 0.05;
  p.offset_change = strain * p.box.ly;
  for (int iy = 0; iy < side; ++iy)
    for (int ix = 0; ix < side; ++ix) {
      const Vec2 r(ix + 0.5 + rng.uniform(-0.3, 0.3), iy + 0.5 + rng.uniform(-0.3, 0.3));
      const Vec2 u(strain * (r.y() - 0.5 * side) + rng.uniform(-0.02, 0.02), rng.uniform(-0.02, 0.02));
      p.reference.push_back(r);
      p.displacement.push_back(u);
      Vec2 wrapped = r + u, v = Vec2::Zero();
      Box after = p.box;
      after.shift_offset(p.offset_change);
      after.wrap(wrapped, v, 0.0);
      p.current.push_back(wrapped);
    }
  return p;
}

}  // namespace

static void BM_D2min(benchmark::State& state) {
  const FramePair p = frame_pair(int(state.range(0)), 1);
  D2min d;
  for (auto _ : state) {
    d = compute_d2min(p.reference, p.box, p.displacement, p.offset_change, 2.0);
    benchmark::DoNotOptimize(d);
  }
  double bonds = 0;
  for (int k : d.neighbours) bonds += k;
  state.counters["grains"] = double(p.reference.size());
  state.counters["neighbours"] = bonds / double(p.reference.size());
  state.counters["per_grain"] = benchmark::Counter(
      double(p.reference.size()), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_D2min)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);

static void BM_D2minFitOnly(benchmark::State& state) {
  const FramePair p = frame_pair(int(state.range(0)), 1);
  const ReferenceBonds bonds = reference_bonds(p.reference, p.box, 2.0);
  for (auto _ : state) {
    D2min d = compute_d2min(bonds, p.displacement, p.offset_change);
    benchmark::DoNotOptimize(d);
  }
  state.counters["grains"] = double(p.reference.size());
}
BENCHMARK(BM_D2minFitOnly)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);

static void BM_Unwrap(benchmark::State& state) {
  const FramePair p = frame_pair(int(state.range(0)), 1);
  Box after = p.box;
  after.shift_offset(p.offset_change);
  const std::vector<StoredFrame> frames = {{p.reference, p.box, 0.0}, {p.current, after, 1.0}};
  const double rate = p.offset_change / p.box.ly;
  for (auto _ : state) {
    Unwrapped u = unwrap_displacements(frames, rate);
    benchmark::DoNotOptimize(u);
  }
  state.counters["grains"] = double(p.reference.size());
}
BENCHMARK(BM_Unwrap)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
