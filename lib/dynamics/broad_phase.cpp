#include "dynamics/broad_phase.hpp"

#include <algorithm>
#include <cmath>

#include <omp.h>

#include "dynamics/branch_free.hpp"
#include "dynamics/capacity.hpp"
#include "dynamics/parallel.hpp"
#include "neighbours/cell_list.hpp"

namespace granflow {

void BroadPhase::moved(double vmax, double rate, double dt) {
  // The step moved grain i by dt·v_i = dt·(ṽ_i + γ̇(y_i − Ly/2)x̂), y_i before the move,
  // so the separation d of a pair changed by dt·(ṽ_i − ṽ_j + γ̇·d_y·x̂). vmax is measured
  // after the move: before it |ṽ| ≤ vmax·(1 + |γ̇|dt). While a pair closes in from the
  // list's reach to the alert distance, |d_y| ≤ 2R_max + reach + 2·dt·v.
  const double v = vmax * (1 + std::fabs(rate) * dt);
  drift_ += dt * (2 * v + std::fabs(rate) * (2 * max_radius_ + reach_ + 2 * dt * v));
}

bool BroadPhase::find(const GrainState& s, const Box& box, double alert, int threads) {
  // Relative margin: gaps are compared with round-off.
  const bool rebuilt = !(drift_ < reach_ - alert - 1e-9 * reach_);
  if (rebuilt) rebuild(s, box, alert, threads);

  // Candidates change little from step to step: room for an eighth more than last time.
  const std::size_t last = candidates_.size();
  candidates_.clear();
  fit_capacity(candidates_, last + last / 8);
  double overlap = 0;
  constexpr std::size_t block = 8192;
  if (threads == 1 || pairs_.size() <= block) {
    overlap = select(s, box, alert, 0, pairs_.size(), candidates_);
  } else {
    // Blocks of pairs filtered in parallel, each into its thread's buffer, and appended in
    // order as soon as the blocks before it are: only one block per thread is held twice.
    const std::ptrdiff_t blocks = std::ptrdiff_t((pairs_.size() + block - 1) / block);
    candidate_blocks_.resize(threads);
#pragma omp parallel num_threads(threads) reduction(max : overlap)
    {
      std::vector<Candidate>& found = candidate_blocks_[omp_get_thread_num()];
#pragma omp for ordered schedule(static, 1)
      for (std::ptrdiff_t b = 0; b < blocks; ++b) {
        found.clear();
        overlap = std::max(overlap, select(s, box, alert, b * block, std::min(pairs_.size(), (b + 1) * block), found));
#pragma omp ordered
        candidates_.insert(candidates_.end(), found.begin(), found.end());
      }
    }
  }
  // Growth by doubling (past last + last/8) leaves up to half unused.
  if (candidates_.capacity() > candidates_.size() + candidates_.size() / 2 + 64) candidates_.shrink_to_fit();
  overlap_ = overlap;
  return rebuilt;
}

// Appends the pairs first … last − 1 of the list whose gap is below the alert distance;
// returns their largest overlap.
double BroadPhase::select(const GrainState& s, const Box& box, double alert, std::size_t first, std::size_t last,
                          std::vector<Candidate>& out) const {
  const Vec2* position = s.position.data();
  const double* radius = s.radius.data();
  const double lx = box.lx, ly = box.ly, offset = box.offset;
  // Box::minimum_image and the image index k, by reciprocals instead of divisions: the
  // rounded quotients differ only for separations within an ulp of half the box, where
  // no pair is ever a candidate.
  const double to_x = 1 / lx, to_y = 1 / ly;
  double overlap = 0;
  // Whether a listed pair is a candidate is as good as random (about half are): each pair
  // is written to a small buffer and kept by advancing its end or not, without a jump.
  // Non-candidates have gap ≥ alert ≥ 0, so taking max(overlap, −gap) over all is the same.
  constexpr std::size_t kChunk = 256;
  Candidate found[kChunk];
  for (std::size_t chunk = first; chunk < last; chunk += kChunk) {
    const std::size_t end = std::min(last, chunk + kChunk);
    std::size_t kept = 0;
    for (std::size_t p = chunk; p < end; ++p) {
      const auto [i, j] = pairs_[p];
      double dx = position[i].x() - position[j].x(), dy = position[i].y() - position[j].y();
      int k = 0;
      if (box.periodic_y) {
        k = round_to_int(dy * to_y);
        dy -= k * ly;
        dx -= k * offset;
      }
      dx -= lx * round_to_int(dx * to_x);
      const double gap = std::sqrt(dx * dx + dy * dy) - radius[i] - radius[j];
      overlap = std::max(overlap, -gap);
      found[kept] = Candidate(i, j, k, dx, dy);
      kept += gap < alert;
    }
    out.insert(out.end(), found, found + kept);
  }
  return overlap;
}

// Pairs whose gap is below alert + skin (as far as the box allows), sorted by (i, j).
void BroadPhase::rebuild(const GrainState& s, const Box& box, double alert, int threads) {
  const std::size_t n = s.size();
  const double half = 0.5 * (box.periodic_y ? std::min(box.lx, box.ly) : box.lx);
  reach_ = std::max(alert, std::min(alert + skin_, half - 2 * max_radius_));
  drift_ = 0;
  CellList cells;
  cells.build(s.position, box, 2 * max_radius_ + reach_);
  // Threads search bands of cell rows, each into its own list; the order in which the
  // pairs are found does not matter, since they are sorted below.
  const int bands = cells.rows() >= 4 * threads ? threads : 1;
  std::vector<std::vector<std::array<int, 2>>> found(bands);
#pragma omp parallel num_threads(bands) if (bands > 1)
  {
    const int t = omp_get_thread_num();
    cells.for_each_pair_in_rows(cells.rows() * t / bands, cells.rows() * (t + 1) / bands, s.position,
                                [&](int i, int j, const Vec2& d) {
                                  if (s.fixed[i] && s.fixed[j]) return;
                                  if (d.norm() - s.radius[i] - s.radius[j] >= reach_) return;
                                  found[t].push_back({std::min(i, j), std::max(i, j)});
                                });
  }
  // Counting sort by i, then by j within each (short) bucket: O(pairs).
  counting_sort(
      n, bucket_,
      [&](auto emit) {
        for (const auto& band : found)
          for (const auto& p : band) emit(p[0], p);
      },
      [&](std::size_t total) { pairs_.resize(total); },
      [&](const std::array<int, 2>& p, int slot) { pairs_[slot] = p; });
  for (std::size_t i = 0; i < n; ++i) std::sort(pairs_.begin() + bucket_[i], pairs_.begin() + bucket_[i + 1]);
}

std::size_t BroadPhase::bytes() const {
  std::size_t blocks = heap_bytes(candidate_blocks_);
  for (const auto& b : candidate_blocks_) blocks += heap_bytes(b);
  return blocks + heap_bytes(pairs_) + heap_bytes(bucket_) + heap_bytes(candidates_);
}

}  // namespace granflow
