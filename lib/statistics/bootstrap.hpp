#pragma once
// Block bootstrap: the uncertainty of a decision (or any statistic) taken from samples that
// come in blocks of consecutive frames, correlated within a block and nearly independent
// between blocks. Each replicate draws as many blocks as there are, uniformly with
// replacement, and recomputes the statistic from them; the spread of the replicates, or
// the fraction that reach the same decision, is the uncertainty. Used where the statistic
// is not a smooth function of block sums (gf-correlate's peak decision for P(f), a
// comparison of two kernel density values), where the jackknife (statistics/jackknife.hpp)
// does not apply.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>

namespace granflow {

// Calls replicate(draws) for each of `replicates` replicates, draws being `blocks` block
// indices drawn with replacement, in order, from Rng(seed): the same seed gives the same
// replicates. Nothing with no blocks.
void block_bootstrap(std::size_t blocks, int replicates, std::uint64_t seed,
                     const std::function<void(std::span<const std::size_t>)>& replicate);

// The fraction of replicates for which agrees(draws) holds (~0.5: undecided); NaN with fewer
// than two blocks or no replicates, which cannot tell anything.
double bootstrap_agreement(std::size_t blocks, int replicates, std::uint64_t seed,
                           const std::function<bool(std::span<const std::size_t>)>& agrees);

}  // namespace granflow
