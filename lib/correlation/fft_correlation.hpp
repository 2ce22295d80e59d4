#pragma once
// The force correlation of force_correlation.hpp by FFT, for lags out to half the box,
// where the exact pair sums visit every pair of the frame (N² work).
//
// Lattice coordinates. With the Lees–Edwards images spanning the lattice a1 = (Lx, 0),
// a2 = (s, Ly) (s = δ reduced into [−Lx/2, Lx/2], as the pair sums use), a position is
// r = H·(u, v), H = [a1 a2], and (u, v) ∈ [0, 1)² is periodic with period 1 in both:
// every periodic image of the sheared cell is an integer shift of (u, v). A grid of
// m1 × m2 cells in (u, v) is therefore a periodic grid whatever δ is, and the cyclic
// autocorrelation of a field on it is a sum over all pairs and all their images.
//
// Method. Each grain's F^i is added to the cell holding its lattice coordinates (nearest
// grid point), once per component x and y. With f_x, f_y these grids,
//   A(k) = Σ_c f(c)·f(c + k) = IFFT(|FFT f_x|² + |FFT f_y|²)(k) / (m1 m2)
// is Σ F^i·F^j over the ordered pairs (i, j) whose cells differ by the lattice lag
// k = (k1, k2) (i = j included at k = 0). The lag k maps back to the real lag
// ℓ = (k1/m1)·a1 + (k2/m2)·a2 with k2 ∈ (−m2/2, m2/2] (so |ℓ_y| ≤ Ly/2) and ℓ_x reduced
// into [−Lx/2, Lx/2]: the minimum image whenever it is shorter than min(Lx, Ly)/2 ≥ ℓ_max.
// Every k with 0 < |ℓ| < ℓ_max then enters PairSums and the map exactly as a pair at ℓ
// does in Correlator::accumulate, with weight A(k)/2 (A counts each unordered pair at +ℓ
// and at −ℓ; PairSums counts it once). k = 0 (a grain with itself, and grains sharing a
// cell) is left out, as the pair sums leave out coincident centres.
//
// Binning error. The result is exactly (to round-off) the pair sums of the grains moved to
// their cell centres (snapped_positions); a lag is moved by less than one cell diagonal in
// each direction, |Δℓ| < |a1|/m1 + |a2|/m2. Grains closer than a cell can share one and
// are lost from the sums; with cells smaller than the closest approach of two grains
// (default σ/20) none are.
//
// Determinism. Plans are made with FFTW_ESTIMATE: FFTW_MEASURE would time candidate
// algorithms and keep the fastest, so two runs on the same input could use different
// algorithms and differ in the last bits. ESTIMATE picks by a fixed heuristic; with the
// same sizes, the same 16-byte-aligned buffers (fftw_malloc) and one thread, identical
// inputs give identical bits.
//
// Threads. FFTW's planner is not thread-safe; plans are made and destroyed under one lock
// shared by all FftCorrelators, and executed on the correlator's own buffers only.
#include <cstddef>
#include <memory>
#include <vector>

#include "correlation/force_correlation.hpp"

namespace granflow::correlation {

// At most this many grid points (about 20 bytes each: the real grid, its transform and
// the power spectrum): a larger grid comes from a mistyped --fft-cell.
inline constexpr double kMaxFftPoints = 67108864;  // 2^26, ≈ 1.3 GB

struct FftShape {
  int m1 = 0, m2 = 0;  // cells along a1 (x) and along a2
  double points() const { return double(m1) * double(m2); }
  bool operator==(const FftShape& o) const { return m1 == o.m1 && m2 == o.m2; }
};

// The smallest grid whose cells are at most `cell` long along x (Lx/m1) and along y
// (Ly/m2), each count rounded up to a product of 2, 3, 5 and 7 (which FFTW transforms
// fastest). UsageError naming --fft-cell if cell ≤ 0 or the grid has more than
// kMaxFftPoints points.
FftShape fft_shape(const Box& box, double cell);

// The positions moved to the centres of their grid cells: Correlator's pair sums of these
// equal FftCorrelator's sums of the originals to round-off (the test of the method).
std::vector<Vec2> snapped_positions(const std::vector<Vec2>& position, const Box& box, const FftShape& shape);

// The pair sums of frames on one LagGrid by FFT, on grids of cells ≤ `cell`.
class FftCorrelator {
 public:
  FftCorrelator(const LagGrid& grid, double cell);
  ~FftCorrelator();
  FftCorrelator(FftCorrelator&&) noexcept;
  FftCorrelator& operator=(FftCorrelator&&) noexcept;

  // As Correlator::accumulate (the same sums, map layout and normalisation), for any
  // ℓ_max ≤ min(Lx, Ly)/2. Plans and buffers are kept while the grid shape stays the same.
  void accumulate(const LoadedGrains& grains, PairSums& sums, std::vector<double>& map);

  const LagGrid& grid() const { return grid_; }
  double cell() const { return cell_; }
  // The shape of the last frame's grid (m1 = m2 = 0 before the first).
  FftShape shape() const;

 private:
  struct Workspace;
  LagGrid grid_;
  double cell_;
  std::unique_ptr<const SectorIndex> sectors_;
  std::unique_ptr<Workspace> work_;
};

}  // namespace granflow::correlation
