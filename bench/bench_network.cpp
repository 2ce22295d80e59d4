// Speed of gf-network's per-frame analysis (FrameAnalyser::analyse: fabric moments, angular
// and deflection histograms, per-grain pairs of long-lived contacts) on synthetic dense
// networks of N = 10³, 10⁴, 10⁵ grains with ≈ 2N contacts, to show that the cost stays
// linear in N (the per-grain pairs cost Σk², bounded per grain). Reported per contact.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>

#include "core/random.hpp"
#include "network/network.hpp"

using namespace granflow;
using namespace granflow::network;

namespace {

// A jittered triangular lattice (side × side grains, periodic indices) keeping two of each
// grain's three forward neighbour bonds (right, upper, upper diagonal) at random: 2N
// contacts, k ≈ 4 per grain. Ages: 30 % new (1), the rest long-lived (2–100).
ContactRecords synthetic_network(int n, std::uint64_t seed) {
  Rng rng(seed);
  const int side = int(std::round(std::sqrt(double(n))));
  std::vector<Vec2> position;
  for (int iy = 0; iy < side; ++iy)
    for (int ix = 0; ix < side; ++ix)
      position.push_back(Vec2(ix + 0.5 * (iy % 2) + 0.05 * rng.uniform(-1, 1), iy * 0.866 + 0.05 * rng.uniform(-1, 1)));
  struct Row {
    std::int32_t i, j;
    Vec2 branch;
  };
  std::vector<Row> rows;
  for (int iy = 0; iy < side; ++iy)
    for (int ix = 0; ix < side; ++ix) {
      const int i = iy * side + ix, up = (iy + 1) % side;
      const int diagonal_x = (iy % 2) ? (ix + 1) % side : ix;  // the upper-right neighbour
      const int neighbour[3] = {iy * side + (ix + 1) % side, up * side + (diagonal_x + side - 1) % side,
                                up * side + diagonal_x};
      // Lattice offsets (the branch of a periodic pair is its minimum image, not r_i − r_j).
      const Vec2 offset[3] = {Vec2(1, 0), Vec2(-0.5, 0.866), Vec2(0.5, 0.866)};
      const int dropped = int(rng.uniform() * 3);
      for (int b = 0; b < 3; ++b) {
        if (b == dropped) continue;
        const int j = neighbour[b];
        const Vec2 jitter = 0.05 * Vec2(rng.uniform(-1, 1), rng.uniform(-1, 1));
        const Vec2 branch = -offset[b] + jitter;  // r_i − r_j
        if (i < j) rows.push_back({std::int32_t(i), std::int32_t(j), branch});
        else rows.push_back({std::int32_t(j), std::int32_t(i), -branch});
      }
    }
  std::sort(rows.begin(), rows.end(), [](const Row& a, const Row& b) { return a.i != b.i ? a.i < b.i : a.j < b.j; });
  ContactRecords c;
  for (const Row& r : rows) {
    c.pair.push_back({r.i, r.j});
    c.branch.push_back(r.branch);
    c.normal_force.push_back(-std::log(1 - rng.uniform()));
    c.tangential_force.push_back(0.1 * rng.uniform(-1, 1));
    c.binary_force.push_back(-std::log(1 - rng.uniform()));
    c.pre_normal_velocity.push_back({0, 0});
    c.age.push_back(rng.uniform() < 0.3 ? 1 : 2 + std::int64_t(rng.uniform() * 99));
  }
  return c;
}

}  // namespace

// One frame through the analyser with gf-network's default histograms (36 × 36 bins).
static void BM_AnalyseFrame(benchmark::State& state) {
  const int n = int(state.range(0));
  const ContactRecords contacts = synthetic_network(n, 1);
  const std::size_t grains =
      std::size_t(std::round(std::sqrt(double(n)))) * std::size_t(std::round(std::sqrt(double(n))));
  FrameAnalyser analyser;
  Histograms h(36, 36);
  FrameSums sums;
  for (auto _ : state) {
    sums = analyser.analyse(contacts, grains, &h);
    benchmark::DoNotOptimize(sums);
  }
  state.counters["grains"] = double(grains);
  state.counters["contacts"] = double(contacts.size());
  state.counters["pairs"] = sums.deflection_pairs;
  state.counters["per_contact"] = benchmark::Counter(
      double(contacts.size()), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_AnalyseFrame)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
