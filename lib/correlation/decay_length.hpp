#pragma once
// ξ_|C|: the decay length of |C̄(ℓ)|, the correlation length used for thesis Figs 5.2–5.10.
//
// Why. Eq. 5.2 taken literally on the signed C̄ (correlation_length) is a harmonic mean of
// contact distances in dilute flows but ill-conditioned in dense ones: C̄ > 0 near contact,
// and inside every cluster Σ_i F^i = 0 puts −W/2 into a long negative tail, so ∫C̄ dℓ can
// cross zero (ξ = 194 ± 2400 at ν = 0.8, e = 0, N = 1000). The thesis reads ξ as the decay
// length of |C| ("C(ℓ) ∼ exp(−ℓ/ξ)", Fig. 5.2), and for |C̄| = A e^{−ℓ/ξ},
// ∫ℓ|C̄|dℓ / ∫|C̄|dℓ = ξ exactly.
//
// Definition. The radial bins are merged `coarse` at a time into coarse bins
// [ℓ_c⁻, ℓ_c⁺) (the last one may be partial). Per coarse bin, exactly from the pair sums
// (no discretisation of the integrals, as for eq. 5.2):
//   I_c = ∫_c C̄ dℓ   = Σ_c (w/ℓ) / (2πW),      J_c = ∫_c ℓ C̄ dℓ = Σ_c w / (2πW).
// Noise floor: a_c = max(|I_c| − k·δI_c, 0), δI_c the block-jackknife standard error of I_c
// over the run's blocks (k = `noise`, 2 by default): soft thresholding at k standard errors,
// which removes the noise that |C̄| would otherwise integrate (and ℓ-weight), at the price
// of a downward bias from the part of the tail hidden in the noise. With fewer than two
// blocks there is no error estimate and no reduction (δI_c = 0).
// Bias (tests/unit/test_correlation_abs.cpp): subtracting k·δI from every bin shortens the
// ℓ-weighted profile, so ξ_|C| comes out low by a few per cent (−5 % for A e^{−ℓ/2} with a
// noise of 0.4 % of A per σ/20 bin), which is ≈ 10 of its own jackknife errors: the errors
// below are statistical only. The hard threshold (`hard`: a_c = |I_c| where |I_c| > k·δI_c,
// else 0) is unbiased within its errors on the same data, but its jackknife errors are ≈ 2×
// the real scatter (the estimator jumps as bins enter or leave); soft stays the default, as
// the chapter-5 pipeline defined ξ_|C|.
// Lag of a coarse bin: ℓ_c = J_c / I_c, the C̄-weighted mean lag inside it, clamped to
// [ℓ_c⁻, ℓ_c⁺] (it can leave the bin only where C̄ changes sign inside it).
//   ξ_|C| = Σ_c ℓ_c a_c / Σ_c a_c     (NaN when every a_c = 0).
// Isolated binary contacts (every w = −F² < 0, well above noise): ξ_|C| = ΣF² / Σ(F²/d),
// the F²-weighted harmonic mean of the contact distances d, i.e. the |C̄|-weighted mean
// contact distance, and equal to eq. 5.2's ξ.
// Box-spanning correlations: where the force network spans the cell, C̄ keeps a plateau up
// to ℓ_max and ξ_|C| measures the box, not the network. The tail share
//   T = Σ_{c: (ℓ_c⁻+ℓ_c⁺)/2 > tail_from·ℓ_max} ℓ_c a_c / Σ_c ℓ_c a_c
// is the part of ∫ℓ|C̄| beyond 2ℓ_max/3 (tail_from = 2/3); the run is `measurable` when
// ξ_|C| is finite and T ≤ max_tail_share (5 %): the thesis' "ξ is too large to be measured".
// Per direction: the same estimator on the radial profile of each sector of [0, π) (pairs
// by the angle of r_ij mod π, PairSums::sector_w*), ξ_|C|(θ_k), a length (not per radian);
// the noise floor per sector and coarse bin is its own jackknife error.
//
// Errors. Block jackknife over the same per-block pair sums as C̄ and eq. 5.2's ξ: every
// leave-one-out replicate recomputes I_c, J_c, ℓ_c, a_c, ξ_|C| and T from the summed pair
// sums of the other blocks, with the noise floors k·δI_c held at their full-sample values
// (the threshold is a fixed function in all replicates; its own sampling noise is not
// propagated). Correlations between bins are thus included, unlike a propagation that
// treats bins as independent.
#include <vector>

#include "correlation/force_correlation.hpp"

namespace granflow::correlation {

struct MagnitudeSettings {
  double noise = 2;              // k: soft threshold at k jackknife errors
  double tail_from = 2.0 / 3.0;  // tail share counted beyond tail_from·ℓ_max
  double max_tail_share = 0.05;  // measurable when T ≤ this
  bool hard = false;             // hard threshold: a_c = |I_c| if |I_c| > k·δI_c, else 0
};

struct MagnitudeLength {
  double xi = 0, xi_error = 0;                  // ξ_|C| and its jackknife error
  double tail_share = 0, tail_share_error = 0;  // T and its jackknife error
  bool measurable = false;
  std::vector<double> xi_theta, xi_theta_error;  // ξ_|C|(θ_k) per sector, [angle_bins]
};

// Per coarse bin c, of the isotropic profile (sector < 0) or of sector k:
// I_c = ∫_c C dℓ and J_c = ∫_c ℓ C dℓ (for a sector: C(ℓ, θ) averaged over the sector).
// NaN when W = 0.
std::vector<double> bin_integrals(const PairSums& sums, const LagGrid& grid, int sector = -1);
std::vector<double> bin_moments(const PairSums& sums, const LagGrid& grid, int sector = -1);

struct DecayLength {
  double xi, tail_share;
};
// ξ_|C| and T from one profile (I, J per coarse bin) and its noise floors k·δI (same length;
// non-finite floors count as 0).
DecayLength decay_length(const std::vector<double>& integral, const std::vector<double>& moment,
                         const std::vector<double>& floor, const LagGrid& grid, double tail_from, bool hard = false);

// ξ_|C|, T, the flag and ξ_|C|(θ), with jackknife errors, from a run's per-block pair sums.
MagnitudeLength magnitude_length(const std::vector<PairSums>& blocks, const LagGrid& grid,
                                 const MagnitudeSettings& settings);

}  // namespace granflow::correlation
