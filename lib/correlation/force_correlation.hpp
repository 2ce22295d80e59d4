#pragma once
// Spatial correlation of the total contact forces on grains (thesis eq. 5.1–5.3).
//
// Forces. A contact (i, j) with branch b = r_i − r_j (minimum image), n̂ = b/|b| (from
// j to i) and t̂ = perp(n̂) pushes i with F_n n̂ + F_t t̂ and j with the opposite; F^i is
// the sum over i's contacts. Only grains with at least one contact enter eq. 5.1; the
// others have F^i = 0 and would add nothing anyway.
//
// Estimator. Eq. 5.1 sums each unordered pair once at ℓ = r^i − r^j, which depends on
// the grains' numbering; we symmetrise it, giving each pair half of its weight
// w = F^i·F^j at +ℓ and half at −ℓ, so C(ℓ) = C(−ℓ) and the angle average is eq. 5.1
// unchanged. With W = Σ_i F^i·F^i and the lag density understood per unit area,
//   C(ℓ)  = (1/W) Σ_{i>j} w_ij ½[δ²(ℓ − r_ij) + δ²(ℓ + r_ij)],
//   C̄(ℓ)  = (1/2π)∫dθ C = (1/W) Σ_{i>j} w_ij δ(ℓ − ℓ_ij) / (2π ℓ_ij)   (isotropic part),
// where r_ij is the Lees–Edwards minimum image and ℓ_ij = |r_ij|. Sum rule: since
// contact forces are internal, Σ_i F^i = 0, so Σ_{i>j} w_ij = −W/2 over all pairs.
//
// Every pair closer than a maximum lag ℓ_max ≤ min(Lx, Ly)/2 (where the minimum image is
// unique) is visited exactly, with cells in the sheared frame of the box; nothing beyond
// ℓ_max is counted anywhere. The sums are kept unbinned wherever an integral needs them:
//   ξ (eq. 5.2) = ∫_0^ℓmax dℓ ℓ C̄ / ∫_0^ℓmax dℓ C̄
//               = Σ_{ℓ_ij<ℓmax} w_ij / Σ_{ℓ_ij<ℓmax} w_ij/ℓ_ij,
// exact for the sampled pairs: the radial bins only group the two sums (Σw and Σw/ℓ
// per bin), they do not discretise the integrals. For isolated binary contacts
// (w = −F², ℓ = contact distance d) this is the F²-weighted harmonic mean of d.
//   ξ(θ) = ∫_0^ℓmax dℓ ℓ C(ℓ, θ) / (2π ∫_0^ℓmax dℓ C̄), so that ∫_0^{2π} ξ(θ) dθ = ξ as
// eq. 5.3 requires; it is π-periodic (C(ℓ) = C(−ℓ)) and is averaged over K sectors
// of [0, π): ξ(θ_k) = Σ_{pairs with angle mod π in sector k} w / (2Δθ Σ_all w/ℓ),
// Δθ = π/K.
//   ξ_dir(θ), eq. 5.2 per direction: ∫_0^ℓmax dℓ ℓ C(ℓ, θ) / ∫_0^ℓmax dℓ C(ℓ, θ), numerator
// and denominator each averaged over the sector: ξ_dir(θ_k) = Σ_k w / Σ_k w/ℓ (a length), so
// that ξ(θ) = ξ_dir(θ)·∫dℓ C(ℓ, θ) / (2π ∫dℓ C̄), and the ratios' Σ_k w/ℓ-weighted mean over
// all sectors is ξ. A mean of the lags in (0, ℓ_max) with weights C(ℓ, θ)dℓ, it can leave
// that range only where C takes both signs: NaN where Σ_k w/ℓ = 0 or the ratio is outside
// (0, ℓ_max] (the two sums of opposite signs, or Σ_k w/ℓ nearly cancelled).
//   ξ_length, eq. 5.2 with C read as a density per unit length, C_L(ℓ) = 2πℓ C̄(ℓ)
// = (1/W) Σ_{i>j} w_ij δ(ℓ − ℓ_ij) (the radial pair sum per unit ℓ, not divided by 2πℓ):
//   ξ_length = ∫_0^ℓmax dℓ ℓ C_L / ∫_0^ℓmax dℓ C_L = ∫ ℓ² C̄ dℓ / ∫ ℓ C̄ dℓ
//            = Σ_{ℓ_ij<ℓmax} w_ij ℓ_ij / Σ_{ℓ_ij<ℓmax} w_ij,
// exact likewise (Σwℓ and Σw per bin). For isolated binary contacts it is the F²-weighted
// arithmetic mean of d (≥ the harmonic mean ξ); for C̄ = A e^{−ℓ/λ} (ℓ_max → ∞), 2λ against ξ = λ.
//   C̄ in radial bin b: Σ_{pairs in b} w / (W · π(ℓ_{b+1}² − ℓ_b²)).
//   The map: ½Σ w at ±r_ij on a square grid of lag vectors (lab frame, bins of side h
// whose edges are the multiples of h, so the lag axes are bin edges), divided by W h².
//   Per sector and coarse radial bin (`coarse` radial bins merged), Σw and Σw/ℓ again: the
// radial profile of C(ℓ, θ) from which decay_length.hpp takes ξ_|C|(θ).
#include <algorithm>
#include <cstddef>
#include <memory>
#include <vector>

#include "core/vec.hpp"
#include "geometry/box.hpp"
#include "io/trajectory.hpp"

namespace granflow::correlation {

// Bounds on the tables an analysis allocates (per run, and per block of frames): larger
// counts come from a mistyped width, not from a measurement, and would exhaust memory.
inline constexpr double kMaxRadialBins = 1e5;  // radial bins of C(ℓ) (--bin-width, --max-lag)
inline constexpr double kMaxSectorBins = 1e6;  // sectors × coarse radial bins (--angle-bins, --abs-bin-width)
inline constexpr double kMaxMapSide = 2000;    // map bins per axis (--map-bin)
inline constexpr double kMaxForceBins = 1e5;   // bins of P(f) and grid points of its density estimate

// The binning shared by every frame and every run of one analysis.
struct LagGrid {
  double bin_width = 0;  // radial bins [bΔ, (b+1)Δ)
  int radial_bins = 0;   // ℓ_max = radial_bins · bin_width
  int angle_bins = 0;    // sectors of [0, π)
  double map_bin = 0;    // side h of the map's square bins
  int map_half = 0;      // the map spans [−map_half·h, map_half·h]² (2·map_half bins per axis)
  int coarse = 1;        // radial bins per coarse bin (ξ_|C|); the last coarse bin may be partial

  // UsageError naming the option when a value is out of range (coarse < 1: --abs-bin-width)
  // or gives more bins than the bounds above.
  static LagGrid make(double bin_width, double max_lag, int angle_bins, double map_bin, int coarse = 1);
  double max_lag() const { return radial_bins * bin_width; }
  int coarse_bins() const { return (radial_bins + coarse - 1) / coarse; }
  double coarse_lower(int c) const { return c * coarse * bin_width; }
  double coarse_upper(int c) const { return std::min(radial_bins, (c + 1) * coarse) * bin_width; }
  double sector_width() const;
  int map_side() const { return 2 * map_half; }
};

// The grains of one frame that carry at least one contact, and the total contact force
// on each (see the header comment).
struct LoadedGrains {
  Box box;
  std::vector<Vec2> position;  // wrapped into the primary cell
  std::vector<Vec2> force;
};
// UsageError when a contact names a grain outside 0..grains−1, itself, or has a zero branch.
LoadedGrains loaded_grains(const io::Frame& frame);

// Sums over pairs that are additive over frames (blocks of frames are sums of these).
struct PairSums {
  double norm = 0;                        // W = Σ_i F^i·F^i
  std::vector<double> w;                  // [radial_bins]   Σ_{i>j} F^i·F^j
  std::vector<double> w_over_lag;         // [radial_bins]   Σ_{i>j} F^i·F^j / ℓ_ij
  std::vector<double> w_times_lag;        // [radial_bins]   Σ_{i>j} F^i·F^j · ℓ_ij (ξ_length only)
  std::vector<double> sector;             // [angle_bins]    Σ_{i>j} F^i·F^j by angle of r_ij mod π
  std::vector<double> sector_w;           // [angle_bins][coarse_bins]  Σ F^i·F^j by sector and coarse bin
  std::vector<double> sector_w_over_lag;  // [angle_bins][coarse_bins]  Σ F^i·F^j / ℓ_ij likewise

  explicit PairSums(const LagGrid& grid = {});
  PairSums& operator+=(const PairSums& other);
};

class SectorIndex;

// The pair sums of frames on one LagGrid (whose lookup tables it builds once).
class Correlator {
 public:
  explicit Correlator(const LagGrid& grid);
  ~Correlator();
  Correlator(Correlator&&) noexcept;
  Correlator& operator=(Correlator&&) noexcept;

  // Adds the pair sums of one frame to sums, and w at r_ij (for one of the two orders of
  // each pair) to map ([map_side][map_side], row = y bin, column = x bin; empty: no map;
  // correlation_map symmetrises it). The box must satisfy ℓ_max ≤ min(Lx, Ly)/2.
  void accumulate(const LoadedGrains& grains, PairSums& sums, std::vector<double>& map) const;

  const LagGrid& grid() const { return grid_; }

 private:
  LagGrid grid_;
  std::unique_ptr<const SectorIndex> sectors_;
};

// The density C is read as in eq. 5.2: per unit area (C̄, the reproduction's reading: ξ) or
// per unit length (C_L = 2πℓ C̄: ξ_length), see the header comment.
enum class Density { area, length };

// Estimators from (summed) pair sums; NaN where undefined (W = 0 or empty sums).
std::vector<double> isotropic_correlation(const PairSums& sums, const LagGrid& grid);  // C̄ per radial bin
// ξ, eq. 5.2: Σw / Σ(w/ℓ) (area) or Σwℓ / Σw (length).
double correlation_length(const PairSums& sums, Density density = Density::area);
// ξ with both integrals truncated at the upper edge of each radial bin (convergence check).
std::vector<double> truncated_correlation_length(const PairSums& sums, Density density = Density::area);
std::vector<double> angular_correlation_length(const PairSums& sums, const LagGrid& grid);    // ξ(θ_k)
std::vector<double> direction_correlation_length(const PairSums& sums, const LagGrid& grid);  // ξ_dir(θ_k)
// C on the map grid: ½(map at ℓ + map at −ℓ) / (W h²); NaN in bins not wholly inside
// the disc |ℓ| < ℓ_max.
std::vector<double> correlation_map(const std::vector<double>& map, double norm, const LagGrid& grid);

// Axes: radial bin centres, sector centres θ_k = (k + ½)π/K, map bin centres (x and y alike).
std::vector<double> radial_centres(const LagGrid& grid);
std::vector<double> sector_centres(const LagGrid& grid);
std::vector<double> map_centres(const LagGrid& grid);

}  // namespace granflow::correlation
