#include "correlation/fft_correlation.hpp"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <mutex>
#include <new>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "core/format.hpp"
#include "correlation/sector_index.hpp"

namespace granflow::correlation {

namespace {

std::mutex& planner_lock() {
  static std::mutex m;
  return m;
}

struct FftwFree {
  void operator()(void* p) const { fftw_free(p); }
};
template <class T>
using FftwBuffer = std::unique_ptr<T[], FftwFree>;

template <class T>
FftwBuffer<T> fftw_buffer(std::size_t count) {
  T* p = static_cast<T*>(fftw_malloc(sizeof(T) * std::max<std::size_t>(count, 1)));
  if (!p) throw std::bad_alloc();
  return FftwBuffer<T>(p);
}

// A plan, destroyed under the planner's lock.
class Plan {
 public:
  Plan() = default;
  explicit Plan(fftw_plan p) : plan_(p) {
    if (!p) throw std::runtime_error("FFTW could not make a plan");
  }
  Plan(const Plan&) = delete;
  Plan& operator=(const Plan&) = delete;
  Plan(Plan&& o) noexcept : plan_(std::exchange(o.plan_, nullptr)) {}
  // Only ever assigned to an empty plan (while the lock is held), so nothing is destroyed here.
  Plan& operator=(Plan&& o) noexcept {
    std::swap(plan_, o.plan_);
    return *this;
  }
  ~Plan() {
    if (plan_) {
      std::lock_guard<std::mutex> lock(planner_lock());
      fftw_destroy_plan(plan_);
    }
  }
  fftw_plan get() const { return plan_; }

 private:
  fftw_plan plan_ = nullptr;
};

// The smallest 2^a 3^b 5^c 7^d ≥ n.
int smooth_size(int n) {
  for (int m = std::max(n, 1);; ++m) {
    int r = m;
    for (int p : {2, 3, 5, 7})
      while (r % p == 0) r /= p;
    if (r == 1) return m;
  }
}

// s = δ reduced into [−Lx/2, Lx/2], the x component of a2 (as LagPairs).
double reduced_offset(const Box& box) { return box.offset - box.lx * std::round(box.offset / box.lx); }

// The grid cell (c1, c2) of a wrapped position.
struct Cell {
  int c1, c2;
};
Cell cell_of(const Vec2& r, const Box& box, double s, const FftShape& shape) {
  const double v = r.y() / box.ly;
  double u = (r.x() - v * s) / box.lx;
  u -= std::floor(u);
  return {std::clamp(int(u * shape.m1), 0, shape.m1 - 1), std::clamp(int(v * shape.m2), 0, shape.m2 - 1)};
}

}  // namespace

FftShape fft_shape(const Box& box, double cell) {
  if (!(cell > 0) || !std::isfinite(cell)) throw UsageError("option --fft-cell: must be > 0");
  const double m1 = std::ceil(box.lx / cell - 1e-9), m2 = std::ceil(box.ly / cell - 1e-9);
  if (m1 * m2 > kMaxFftPoints)
    throw UsageError("option --fft-cell: " + format_number(cell) + " gives an FFT grid of " + format_number(m1) +
                     " x " + format_number(m2) + " cells on a box of " + format_number(box.lx) + " x " +
                     format_number(box.ly) + "; use at most " + format_number(kMaxFftPoints) + " cells");
  FftShape s{smooth_size(int(m1)), smooth_size(int(m2))};
  if (s.points() > kMaxFftPoints)
    throw UsageError("option --fft-cell: " + format_number(cell) + " gives an FFT grid of " + std::to_string(s.m1) +
                     " x " + std::to_string(s.m2) + " cells; use at most " + format_number(kMaxFftPoints) + " cells");
  return s;
}

std::vector<Vec2> snapped_positions(const std::vector<Vec2>& position, const Box& box, const FftShape& shape) {
  const double s = reduced_offset(box);
  std::vector<Vec2> out;
  out.reserve(position.size());
  for (const Vec2& r : position) {
    const Cell c = cell_of(r, box, s, shape);
    const double u = (c.c1 + 0.5) / shape.m1, v = (c.c2 + 0.5) / shape.m2;
    out.emplace_back(u * box.lx + v * s, v * box.ly);
  }
  return out;
}

// Buffers and plans for one grid shape: the real grid (m2 rows of m1), its half-spectrum
// (m2 rows of m1/2 + 1) and the summed power of both components.
struct FftCorrelator::Workspace {
  FftShape shape;
  FftwBuffer<double> grid;
  FftwBuffer<fftw_complex> spectrum;
  std::vector<double> power;
  Plan forward, backward;

  explicit Workspace(const FftShape& s) : shape(s) {
    const std::size_t real = std::size_t(s.m1) * std::size_t(s.m2), half = std::size_t(s.m1 / 2 + 1) * s.m2;
    grid = fftw_buffer<double>(real);
    spectrum = fftw_buffer<fftw_complex>(half);
    power.assign(half, 0.0);
    std::lock_guard<std::mutex> lock(planner_lock());
    // ESTIMATE leaves the arrays alone while planning and picks the algorithm without timing.
    forward = Plan(fftw_plan_dft_r2c_2d(s.m2, s.m1, grid.get(), spectrum.get(), FFTW_ESTIMATE));
    backward = Plan(fftw_plan_dft_c2r_2d(s.m2, s.m1, spectrum.get(), grid.get(), FFTW_ESTIMATE));
  }
};

FftCorrelator::FftCorrelator(const LagGrid& grid, double cell)
    : grid_(grid), cell_(cell), sectors_(std::make_unique<const SectorIndex>(grid)) {}
FftCorrelator::~FftCorrelator() = default;
FftCorrelator::FftCorrelator(FftCorrelator&&) noexcept = default;
FftCorrelator& FftCorrelator::operator=(FftCorrelator&&) noexcept = default;

FftShape FftCorrelator::shape() const { return work_ ? work_->shape : FftShape{}; }

void FftCorrelator::accumulate(const LoadedGrains& grains, PairSums& sums, std::vector<double>& map) {
  for (const Vec2& f : grains.force) sums.norm += f.squaredNorm();
  if (grains.position.size() < 2) return;
  const Box& box = grains.box;
  const LagGrid& grid = grid_;
  if (grid.max_lag() > 0.5 * std::min(box.lx, box.ly) * (1 + 1e-12))
    throw UsageError("option --max-lag: " + format_number(grid.max_lag()) + " is beyond half the shorter box side " +
                     format_number(0.5 * std::min(box.lx, box.ly)));
  const FftShape shape = fft_shape(box, cell_);
  if (!work_ || !(work_->shape == shape)) {
    work_.reset();  // free the old grid before allocating the new one
    work_ = std::make_unique<Workspace>(shape);
  }
  Workspace& w = *work_;
  const int m1 = shape.m1, m2 = shape.m2;
  const std::size_t real = std::size_t(m1) * std::size_t(m2);
  const double s = reduced_offset(box);

  std::vector<int> cell(grains.position.size());
  for (std::size_t i = 0; i < cell.size(); ++i) {
    const Cell c = cell_of(grains.position[i], box, s, shape);
    cell[i] = c.c2 * m1 + c.c1;
  }
  std::fill(w.power.begin(), w.power.end(), 0.0);
  for (int component = 0; component < 2; ++component) {
    std::fill(w.grid.get(), w.grid.get() + real, 0.0);
    for (std::size_t i = 0; i < cell.size(); ++i) w.grid[std::size_t(cell[i])] += grains.force[i][component];
    fftw_execute(w.forward.get());
    for (std::size_t q = 0; q < w.power.size(); ++q)
      w.power[q] += w.spectrum[q][0] * w.spectrum[q][0] + w.spectrum[q][1] * w.spectrum[q][1];
  }
  for (std::size_t q = 0; q < w.power.size(); ++q) {
    w.spectrum[q][0] = w.power[q];
    w.spectrum[q][1] = 0;
  }
  fftw_execute(w.backward.get());  // grid = m1·m2·A(k)

  // Every lattice lag within ℓ_max, binned as Correlator::accumulate bins a pair.
  const SectorIndex& sectors = *sectors_;
  const double max_lag = grid.max_lag(), cutoff2 = max_lag * max_lag;
  LagBinner binner(grid, sectors, sums, map);
  // A(k)/2 per unordered pair, and FFTW's unnormalised inverse.
  const double scale = 0.5 / double(real);
  for (int k2 = 0; k2 < m2; ++k2) {
    const int j2 = 2 * k2 <= m2 ? k2 : k2 - m2;  // k2 ∈ (−m2/2, m2/2]
    const double v = double(j2) / m2, y = v * box.ly;
    if (y * y >= cutoff2) continue;
    for (int k1 = 0; k1 < m1; ++k1) {
      double x = double(k1) / m1 * box.lx + v * s;
      x -= box.lx * std::round(x / box.lx);
      const double lag2 = x * x + y * y;
      if (lag2 >= cutoff2 || lag2 == 0) continue;
      binner.add(x, y, lag2, scale * w.grid[std::size_t(k2) * std::size_t(m1) + std::size_t(k1)]);
    }
  }
}

}  // namespace granflow::correlation
