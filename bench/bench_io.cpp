// Trajectory writing speed: per-step observables and whole frames with contacts.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "io/trajectory.hpp"

using namespace granflow;

namespace {
std::string scratch(const char* name) { return (std::filesystem::temp_directory_path() / name).string(); }

io::TrajectoryWriter writer_for(const std::string& path, int n) {
  io::TrajectoryWriter w(path);
  io::GrainProperties g{std::vector<double>(n, 0.7), std::vector<double>(n, 1.5), std::vector<std::uint8_t>(n, 0)};
  w.write_grains(g, Box{100, 100, true, 0});
  return w;
}
}  // namespace

// Rows per second of scalar observables (gf-shear appends several every step).
static void BM_ObservableAppend(benchmark::State& state) {
  const std::string path = scratch("granflow_bench_obs.h5");
  std::int64_t step = 0;
  {
    auto w = writer_for(path, 10);
    for (auto _ : state) {
      w.append_observable("pressure", step, 1e-3 * double(step), 1.0);
      ++step;
    }
    w.close();
  }
  state.SetItemsProcessed(state.iterations());
  std::filesystem::remove(path);
}
BENCHMARK(BM_ObservableAppend);

// One stored frame of N grains with 2N contacts (compressed, chunked).
static void BM_FrameAppend(benchmark::State& state) {
  const int n = int(state.range(0));
  const std::string path = scratch("granflow_bench_frame.h5");
  io::Frame f;
  f.box = Box{100, 100, true, 0};
  f.position.assign(n, Vec2(1, 2));
  f.velocity.assign(n, Vec2(0.1, 0.2));
  f.orientation.assign(n, 0.3);
  f.angular_velocity.assign(n, 0.4);
  f.has_contacts = true;
  for (int c = 0; c < 2 * n; ++c) {
    f.contacts.pair.push_back({c % n, (c + 1) % n});
    f.contacts.normal_force.push_back(c);
    f.contacts.tangential_force.push_back(0.5 * c);
    f.contacts.branch.push_back(Vec2(1, 0));
    f.contacts.binary_force.push_back(0);
    f.contacts.pre_normal_velocity.push_back({0.1, 0.2});
    f.contacts.age.push_back(c);
  }
  {
    auto w = writer_for(path, n);
    for (auto _ : state) {
      w.append_frame(f);
      ++f.step;
    }
    w.close();
  }
  state.SetItemsProcessed(state.iterations() * n);
  std::filesystem::remove(path);
}
BENCHMARK(BM_FrameAppend)->Arg(1000)->Arg(10000);

BENCHMARK_MAIN();
