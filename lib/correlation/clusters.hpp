#pragma once
// Contact clusters (thesis Fig. 5.1): grains that touch during a short window, grouped
// into connected networks. The window's contact graph is the union of the contacts of
// its stored frames; a cluster is a connected component of that graph.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace granflow::correlation {

// One label per grain: 0 for grains without contact, 1, 2, … for clusters in decreasing
// size (equal sizes: the one holding the lowest grain index first). UsageError when a
// pair names a grain outside 0..grains−1.
std::vector<std::int32_t> contact_clusters(std::size_t grains, const std::vector<std::array<std::int32_t, 2>>& pairs);

}  // namespace granflow::correlation
