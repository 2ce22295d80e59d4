#pragma once
// The engine's parallel building blocks. Each gives the same result, bit for bit, for any
// number of threads: the engine's trajectories must not depend on it.
#include <algorithm>
#include <cstddef>
#include <vector>

namespace granflow {

// for (i = 0; i < count; ++i) body(i), split into static chunks over `threads` OpenMP
// threads (one thread: in this thread). For loops whose iterations are independent.
template <class Index, class Body>
inline void parallel_for(int threads, Index count, Body body) {
#pragma omp parallel for num_threads(threads) if (threads > 1) schedule(static)
  for (Index i = 0; i < count; ++i) body(i);
}

// Stable counting sort into buckets 0 … buckets − 1, O(entries + buckets). entries(emit)
// calls emit(key, item) for every entry, in the same order both times it is called;
// start receives the buckets' offsets (buckets + 1 of them, the last the total), then
// resize(total) is called, then place(item, slot) for every entry, the slots ascending
// within a bucket in the entries' order.
template <class Entries, class Resize, class Place>
void counting_sort(std::size_t buckets, std::vector<int>& start, Entries entries, Resize resize, Place place) {
  start.assign(buckets + 1, 0);
  entries([&](std::size_t key, const auto&) { ++start[key + 1]; });
  for (std::size_t k = 0; k < buckets; ++k) start[k + 1] += start[k];
  resize(std::size_t(start[buckets]));
  // start[k] serves as bucket k's cursor, and so ends as the start of bucket k + 1.
  entries([&](std::size_t key, const auto& item) { place(item, start[key]++); });
  for (std::size_t k = buckets; k > 0; --k) start[k] = start[k - 1];
  start[0] = 0;
}

// The items q of [0, count) for which keep(q) holds, gathered in order by threads: counted
// by chunks, then, after resize(kept), place(q, k) for each with its rank k among the kept.
// The ranks, hence the result, do not depend on the number of threads.
template <class Keep, class Resize, class Place>
void gather(std::ptrdiff_t count, int threads, std::vector<std::size_t>& chunk_start, Keep keep, Resize resize,
            Place place) {
  constexpr std::ptrdiff_t chunk = 4096;
  const std::ptrdiff_t chunks = (count + chunk - 1) / chunk;
  chunk_start.assign(chunks + 1, 0);
  // One chunk is not worth waking the threads for (twice).
  const int workers = threads > 1 && chunks > 1 ? threads : 1;
  parallel_for(workers, chunks, [&](std::ptrdiff_t h) {
    std::size_t kept = 0;
    for (std::ptrdiff_t q = h * chunk; q < std::min(count, (h + 1) * chunk); ++q) kept += keep(q);
    chunk_start[h + 1] = kept;
  });
  for (std::ptrdiff_t h = 0; h < chunks; ++h) chunk_start[h + 1] += chunk_start[h];
  resize(chunk_start[chunks]);
  // The items kept are listed first, by advancing the list's end or not: a jump on keep(q),
  // which is as good as random (which rows bear, say), would mispredict.
  parallel_for(workers, chunks, [&](std::ptrdiff_t h) {
    std::ptrdiff_t kept[chunk];
    std::ptrdiff_t n = 0;
    for (std::ptrdiff_t q = h * chunk; q < std::min(count, (h + 1) * chunk); ++q) {
      kept[n] = q;
      n += keep(q);
    }
    for (std::ptrdiff_t t = 0; t < n; ++t) place(kept[t], chunk_start[h] + std::size_t(t));
  });
}

}  // namespace granflow
