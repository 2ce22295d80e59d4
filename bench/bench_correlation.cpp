// Speed of gf-correlate's pair sums (C(ℓ), ξ, ξ(θ), map) on synthetic dense frames:
// 10⁴ grains (σ = 1.4, Δ = 0.26σ) at ν ≈ 0.8, every grain in contact with its lattice
// neighbours (the worst case: in sheared frames at ν = 0.8 about half of them are).
// Binning of gf-correlate's defaults: bins σ/20, ℓ_max = 15σ, map bins σ/5 (and ℓ_max =
// 20σ for comparison; the cost grows as ℓ_max²). Targets: one frame ≤ 50 ms; 500 frames
// ≤ 1 min, on one core.
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>

#include "core/random.hpp"
#include "correlation/fft_correlation.hpp"
#include "correlation/force_correlation.hpp"
#include "io/trajectory.hpp"

using namespace granflow;
using namespace granflow::correlation;

namespace {
constexpr double kSigma = 1.4;

// Grains on a jittered triangular lattice filling a square Lees–Edwards box at ν ≈ 0.8,
// each touching its right and upper neighbours with random forces.
io::Frame synthetic_frame(int n, std::uint64_t seed) {
  Rng rng(seed);
  const int side = int(std::round(std::sqrt(double(n))));
  std::vector<double> radius(side * side);
  double area = 0;
  for (double& r : radius) {
    r = 0.5 * kSigma * (1 + 0.26 * rng.uniform(-1, 1));
    area += M_PI * r * r;
  }
  const double l = std::sqrt(area / 0.8), a = l / side;
  io::Frame f;
  f.box = Box{l, l, true, 0.37 * l};
  for (int iy = 0; iy < side; ++iy)
    for (int ix = 0; ix < side; ++ix)
      f.position.push_back(
          Vec2((ix + 0.5 * (iy % 2) + 0.1 * rng.uniform(-1, 1)) * a, (iy + 0.1 * rng.uniform(-1, 1)) * a));
  auto& c = f.contacts;
  for (int iy = 0; iy < side; ++iy)
    for (int ix = 0; ix < side; ++ix) {
      const int i = iy * side + ix;
      for (int j : {iy * side + (ix + 1) % side, ((iy + 1) % side) * side + ix}) {
        c.pair.push_back({std::int32_t(i), std::int32_t(j)});
        c.branch.push_back(f.box.minimum_image(f.position[i] - f.position[j]));
        c.normal_force.push_back(-std::log(1 - rng.uniform()));
        c.tangential_force.push_back(0.1 * rng.uniform(-1, 1));
        c.binary_force.push_back(0);
        c.pre_normal_velocity.push_back({0, 0});
        c.age.push_back(1);
      }
    }
  f.has_contacts = true;
  f.velocity.assign(f.position.size(), Vec2::Zero());
  f.orientation.assign(f.position.size(), 0);
  f.angular_velocity.assign(f.position.size(), 0);
  return f;
}

// max_lag_sigma = 0: half the box (--whole-box), with map bins coarsened to the bound on the
// map's side as gf-correlate's default does.
LagGrid grid_for(const io::Frame& f, double max_lag_sigma) {
  const double max_lag = max_lag_sigma > 0 ? std::min(max_lag_sigma * kSigma, 0.5 * f.box.lx) : 0.5 * f.box.lx;
  return LagGrid::make(kSigma / 20, max_lag, 24, std::max(kSigma / 5, 2 * max_lag / kMaxMapSide));
}
}  // namespace

// Pair sums of one frame (C(ℓ), ξ, ξ(θ) and the map), forces already summed per grain.
static void BM_CorrelateFrame(benchmark::State& state) {
  const io::Frame frame = synthetic_frame(int(state.range(0)), 1);
  const LagGrid grid = grid_for(frame, double(state.range(1)));
  const LoadedGrains grains = loaded_grains(frame);
  std::vector<double> map(std::size_t(grid.map_side()) * grid.map_side());
  const Correlator correlator(grid);
  for (auto _ : state) {
    PairSums sums(grid);
    correlator.accumulate(grains, sums, map);
    benchmark::DoNotOptimize(sums.w.data());
  }
  state.counters["grains"] = double(grains.position.size());
  state.counters["max_lag"] = grid.max_lag();
}
BENCHMARK(BM_CorrelateFrame)
    ->Args({1000, 15})
    ->Args({10000, 15})
    ->Args({10000, 20})
    ->Args({10000, 30})
    ->Args({10000, 0})  // to half the box: every pair, N²
    ->Unit(benchmark::kMillisecond);

// Once each: every pair of a 10⁵-grain frame to half the box (the cost the FFT avoids), and
// a 10⁶-grain frame at the default ℓ_max = 15σ.
BENCHMARK(BM_CorrelateFrame)->Args({100000, 0})->Args({1000000, 15})->Iterations(1)->Unit(benchmark::kSecond);

// The same sums by FFT (--map-method fft) on a grid of cells σ/divisor: {grains, ℓ_max in σ
// (0: half the box), divisor}. The 10⁶-grain frame (≈ 0.5 GB of grid at σ/5) runs once.
static void BM_CorrelateFrameFft(benchmark::State& state) {
  const io::Frame frame = synthetic_frame(int(state.range(0)), 1);
  const LagGrid grid = grid_for(frame, double(state.range(1)));
  const LoadedGrains grains = loaded_grains(frame);
  std::vector<double> map(std::size_t(grid.map_side()) * grid.map_side());
  FftCorrelator fft(grid, kSigma / double(state.range(2)));
  for (auto _ : state) {
    PairSums sums(grid);
    fft.accumulate(grains, sums, map);
    benchmark::DoNotOptimize(sums.w.data());
  }
  state.counters["grains"] = double(grains.position.size());
  state.counters["max_lag"] = grid.max_lag();
  state.counters["grid_m1"] = fft.shape().m1;
  state.counters["grid_m2"] = fft.shape().m2;
}
BENCHMARK(BM_CorrelateFrameFft)
    ->Args({10000, 15, 20})
    ->Args({10000, 30, 20})
    ->Args({10000, 0, 20})
    ->Args({10000, 0, 10})
    ->Args({100000, 0, 20})
    ->Args({100000, 0, 10})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CorrelateFrameFft)->Args({1000000, 0, 5})->Iterations(1)->Unit(benchmark::kSecond);

// The average over 500 frames as gf-correlate does it per frame (forces per grain from the
// contacts, then the pair sums), on 10 distinct frames cycled.
static void BM_Average500Frames(benchmark::State& state) {
  std::vector<io::Frame> frames;
  for (std::uint64_t s = 0; s < 10; ++s) frames.push_back(synthetic_frame(10000, s + 1));
  const LagGrid grid = grid_for(frames.front(), 15);
  for (auto _ : state) {
    const Correlator correlator(grid);
    PairSums sums(grid);
    std::vector<double> map(std::size_t(grid.map_side()) * grid.map_side());
    for (int k = 0; k < 500; ++k) correlator.accumulate(loaded_grains(frames[k % 10]), sums, map);
    benchmark::DoNotOptimize(correlation_length(sums));
  }
}
BENCHMARK(BM_Average500Frames)->Unit(benchmark::kSecond)->Iterations(1);

// Reading one stored 10⁴-grain frame with its contacts (gf-correlate reads each frame once).
static void BM_ReadFrame(benchmark::State& state) {
  const std::string path = (std::filesystem::temp_directory_path() / "granflow_bench_correlation.h5").string();
  io::Frame frame = synthetic_frame(10000, 1);
  {
    io::TrajectoryWriter w(path);
    w.write_grains(io::GrainProperties{std::vector<double>(frame.position.size(), 0.7),
                                       std::vector<double>(frame.position.size(), 1.5),
                                       std::vector<std::uint8_t>(frame.position.size(), 0)},
                   frame.box);
    for (int k = 0; k < 20; ++k) {
      frame.step = k;
      w.append_frame(frame);
    }
    w.close();
  }
  io::TrajectoryReader reader(path);
  std::size_t k = 0;
  for (auto _ : state) benchmark::DoNotOptimize(reader.frame(k++ % 20).position.data());
  std::filesystem::remove(path);
}
BENCHMARK(BM_ReadFrame)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
