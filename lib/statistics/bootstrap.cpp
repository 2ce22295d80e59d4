#include "statistics/bootstrap.hpp"

#include <algorithm>
#include <limits>
#include <vector>

#include "core/random.hpp"

namespace granflow {

void block_bootstrap(std::size_t blocks, int replicates, std::uint64_t seed,
                     const std::function<void(std::span<const std::size_t>)>& replicate) {
  if (blocks == 0) return;
  Rng rng(seed);
  std::vector<std::size_t> draws(blocks);
  for (int r = 0; r < replicates; ++r) {
    // min(): uniform() < 1, but its product with the count may round up to it.
    for (std::size_t& d : draws) d = std::min(blocks - 1, std::size_t(rng.uniform() * double(blocks)));
    replicate(draws);
  }
}

double bootstrap_agreement(std::size_t blocks, int replicates, std::uint64_t seed,
                           const std::function<bool(std::span<const std::size_t>)>& agrees) {
  if (blocks < 2 || replicates < 1) return std::numeric_limits<double>::quiet_NaN();
  int agree = 0;
  block_bootstrap(blocks, replicates, seed,
                  [&](std::span<const std::size_t> draws) { agree += agrees(draws) ? 1 : 0; });
  return double(agree) / replicates;
}

}  // namespace granflow
