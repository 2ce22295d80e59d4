#include "correlation/clusters.hpp"

#include <algorithm>
#include <numeric>
#include <string>

#include "core/error.hpp"

namespace granflow::correlation {

std::vector<std::int32_t> contact_clusters(std::size_t grains, const std::vector<std::array<std::int32_t, 2>>& pairs) {
  // Union–find with path halving; roots are kept at the lowest index of their set.
  std::vector<std::size_t> parent(grains);
  std::iota(parent.begin(), parent.end(), std::size_t(0));
  auto root = [&](std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  std::vector<char> touched(grains, 0);
  for (const auto& [i, j] : pairs) {
    if (i < 0 || j < 0 || std::size_t(i) >= grains || std::size_t(j) >= grains)
      throw UsageError("contact (" + std::to_string(i) + ", " + std::to_string(j) + ") names a grain outside the " +
                       std::to_string(grains) + " grains");
    touched[i] = touched[j] = 1;
    const std::size_t a = root(std::size_t(i)), b = root(std::size_t(j));
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
  std::vector<std::size_t> size(grains, 0);
  for (std::size_t i = 0; i < grains; ++i)
    if (touched[i]) ++size[root(i)];
  std::vector<std::size_t> roots;
  for (std::size_t i = 0; i < grains; ++i)
    if (size[i] > 0) roots.push_back(i);
  // Roots are the lowest index of their cluster, so a stable sort by size breaks ties by it.
  std::stable_sort(roots.begin(), roots.end(), [&](std::size_t a, std::size_t b) { return size[a] > size[b]; });
  std::vector<std::int32_t> label_of_root(grains, 0), label(grains, 0);
  for (std::size_t k = 0; k < roots.size(); ++k) label_of_root[roots[k]] = std::int32_t(k + 1);
  for (std::size_t i = 0; i < grains; ++i)
    if (touched[i]) label[i] = label_of_root[root(i)];
  return label;
}

}  // namespace granflow::correlation
