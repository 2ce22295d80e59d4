#pragma once
// Distributions of contact forces normalised by their mean, f = F/⟨F⟩ (thesis §5.2,
// Figs 5.7, 5.8), and the decision whether P(f) peaks at f > 0 or is largest at f = 0.
//
// Samples come in blocks of consecutive frames (time-correlated within a block, nearly
// independent between blocks), which give the errors: a jackknife over blocks for the
// histogram, a bootstrap over blocks (statistics/bootstrap.hpp) for the peak decision.
//
// Peak decision. A Gaussian kernel density estimate with bandwidth h (in units of f),
// reflected at f = 0 so that the boundary does not bias it:
//   P̂(f) ∝ Σ_i [φ((f − f_i)/h) + φ((f + f_i)/h)],  φ(u) = exp(−u²/2), cut at |u| = 6,
// evaluated from a histogram of f with bins h/10 wide, on the grid f = m·h/10 < f_max.
// P(f) "has a peak at f > 0" when P̂ rises from f = 0, P̂(3h) > P̂(0), and "is largest at
// f = 0" otherwise. The comparison is at a fixed point: testing at the sample's own
// maximum would call every flat-topped density peaked (its noise always has a maximum
// away from 0). 3h resolves peaks beyond ~0.3⟨F⟩ at the default h = 0.1 (the binary-
// collision peaks of the thesis lie near f ≈ 0.5–1) while a density with zero slope at 0
// (half-normal) still falls measurably by then. The confidence is the fraction of
// bootstrap replicates (blocks drawn with replacement) that reach the same decision;
// ~0.5 means undecided. Replicates keep the full sample's ⟨F⟩: the decision depends on
// the shape at resolution h, not on the force scale. The mode (location of the largest
// P̂), its error (the spread of the replicates' modes, on the grid of h/10) and P̂(0)/P̂(mode)
// are reported beside it.
#include <cstdint>
#include <limits>
#include <vector>

namespace granflow::correlation {

// Forces of one kind (normal or binary), one vector per block of frames. Stored as float:
// seven digits are plenty for a histogram, and a long run holds ~10⁷ forces.
using BlockSamples = std::vector<std::vector<float>>;

struct Distribution {
  std::vector<double> centre;   // bin centres of f = F/⟨F⟩
  std::vector<double> density;  // P(f): counts / (all samples · bin width), so ∫P = 1 over all f
  std::vector<double> error;    // jackknife over blocks (each leave-one-out with its own ⟨F⟩)
  double mean = std::numeric_limits<double>::quiet_NaN();        // ⟨F⟩
  double mean_error = std::numeric_limits<double>::quiet_NaN();  // jackknife
  std::size_t samples = 0;
};

// Bins [k·width, (k+1)·width) up to max_f; samples beyond max_f count in the normalisation
// only. Density NaN when there are no samples or ⟨F⟩ = 0.
Distribution force_distribution(const BlockSamples& blocks, double bin_width, double max_f);

// UsageError naming --force-bin-width or --kde-bandwidth when P(f)'s bins up to max_f, or
// the grid of the density estimate (10 points per bandwidth), would exceed kMaxForceBins.
void check_force_bins(double bin_width, double max_f, double bandwidth);

struct PeakDecision {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  int peak = -1;             // 1: P̂ rises from f = 0 (a peak at f > 0); 0: it falls; −1: no data
  double confidence = kNaN;  // fraction of bootstrap replicates agreeing (NaN: < 2 blocks)
  double mode = kNaN;        // f of the largest P̂
  double mode_error = kNaN;  // standard deviation of the mode over the bootstrap replicates (NaN: < 2 blocks)
  double ratio = kNaN;       // P̂(0)/P̂(mode) (1 when the maximum is at 0)
};

PeakDecision decide_peak(const BlockSamples& blocks, double bandwidth, double max_f, int replicates,
                         std::uint64_t seed);

}  // namespace granflow::correlation
