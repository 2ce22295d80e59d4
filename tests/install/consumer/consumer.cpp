// Reads a trajectory through an installed libgranflow: its grains, frames and last step.
#include <cstdio>

#include "core/version.hpp"
#include "io/trajectory.hpp"

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  const granflow::io::TrajectoryReader trajectory(argv[1]);
  const granflow::io::Frame last = trajectory.frame(trajectory.frame_count() - 1);
  std::printf("granflow %s\ngrains %zu frames %zu last step %lld\n", granflow::version().c_str(),
              trajectory.grain_count(), trajectory.frame_count(), static_cast<long long>(last.step));
}
