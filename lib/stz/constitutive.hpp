#pragma once
// The steady flowing branch of the STZ constitutive law (thesis eqs. 6.33–6.36), its repose
// angle, the fit of its three coefficients to steady shear runs, and the μ(I) law beside it.
// Plain functions, no I/O; docs/method/stz.md derives and justifies what is done here.
//
// Flowing branch (eq. 6.36 with its proportionality constant A):
//   x(μ) = A [sinh(κμ) − cosh(κμ)/(ζμ)],   x ≡ γ̇⟨R⟩/√T,   μ ≡ s/p,   A, κ, ζ > 0.
// Repose angle (eq. 6.35): tanθ* is the root of ζ t tanh(κt) = 1; x(tanθ*) = 0.
// Monotonicity, so that μ(x) is a function: for μ ≥ tanθ*, ζμ tanh(κμ) ≥ 1 gives ζμ ≥ 1 >
// tanh(κμ), hence dx/dμ = A[κ cosh(κμ)(1 − tanh(κμ)/(ζμ)) + cosh(κμ)/(ζμ²)] > 0, and
// x → ∞ as μ → ∞: every x ≥ 0 has exactly one μ ≥ tanθ*.
//
// μ(I) (GDR MiDi 2004; Jop, Forterre & Pouliquen 2006):
//   μ(I) = μ_s + (μ₂ − μ_s)/(1 + I₀/I),   I = γ̇d/√(P/ρ_p).
#include <limits>
#include <vector>

namespace granflow::stz {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct StzCoefficients {
  double A = kNaN, kappa = kNaN, zeta = kNaN;
};

// x(μ) of eq. 6.36 (any μ > 0: negative below tanθ*, the jammed side). NaN for μ ≤ 0 or
// non-positive coefficients.
double stz_rate(const StzCoefficients& c, double mu);
// dx/dμ.
double stz_rate_derivative(const StzCoefficients& c, double mu);
// tanθ* of eq. 6.35, to a relative 1e-15 (bisection on the bracketed, monotone
// ζ t tanh(κt) − 1). NaN for non-positive or non-finite κ, ζ.
double tan_theta_star(double kappa, double zeta);
// μ(x): the inverse of stz_rate on μ ≥ tanθ* (safeguarded Newton inside a bracket), for
// x ≥ 0 (x = 0 gives tanθ*). NaN for x < 0, non-finite x or non-positive coefficients.
double stz_stress_ratio(const StzCoefficients& c, double x);

// How the STZ coefficients are fitted.
//  - least_squares_mu: minimise Σ_k [(μ_k − μ(x_k))/σ_μ,k]², the stress ratio predicted at the
//    measured rate (σ_μ = 1 when not given). The default: unbiased where log x is not.
//  - orthogonal_distance: both axes measured; minimise Σ_k [(x_k − x(m_k))/σ_x,k]² +
//    [(μ_k − m_k)/σ_μ,k]² over the coefficients and one curve point m_k per datum (ODR).
//    Needs both errors: without them the distance mixes the units of x and μ.
enum class StzObjective { least_squares_mu, orthogonal_distance };

struct StzFit {
  StzCoefficients value;
  StzCoefficients error;                                      // standard errors (see scale below)
  double covariance[3][3] = {};                               // of (A, κ, ζ), with the same scale
  // error by the delta method; NaN where the coefficients are degenerate (see the .cpp)
  double tan_theta_star = kNaN, tan_theta_star_error = kNaN;
  double theta_star = kNaN, theta_star_error = kNaN;          // radians
  double chi2 = kNaN;                                         // of the weighted residuals at the minimum
  int dof = 0;                                                // K − 3
  // The covariance is (JᵀJ)⁻¹ of the weighted residuals times scale²: scale = √(χ²/dof) when
  // unweighted (the scatter is the only error estimate), max(1, √(χ²/dof)) when weighted (the
  // given errors are not trusted to be too large); scale = 1 when dof = 0.
  double scale = kNaN;
  bool weighted = false;
  StzObjective objective = StzObjective::least_squares_mu;
};

// Fits (A, κ, ζ) to the points (x_k, μ_k). mu_error, x_error: empty, or one positive finite
// standard error per point (least_squares_mu ignores x_error). Throws std::invalid_argument
// for fewer points than coefficients (3), sizes that differ, non-finite values, x ≤ 0, μ ≤ 0,
// non-positive errors, or orthogonal_distance without both errors; std::runtime_error when
// the minimiser fails. Starting values: a grid search (docs/method/stz.md), not a guess.
StzFit fit_stz(const std::vector<double>& x, const std::vector<double>& mu, const std::vector<double>& mu_error = {},
               const std::vector<double>& x_error = {}, StzObjective objective = StzObjective::least_squares_mu);

// The delete-one jackknife error of tanθ*: fit_stz on the points without point k, for every k,
// √((K−1)/K Σ(t_k − t̄)²). Needs no covariance, so it stands where the delta-method error is NaN
// (degenerate coefficients). NaN for fewer than 5 points or when a refit fails. Arguments as
// fit_stz.
double stz_repose_jackknife_error(const std::vector<double>& x, const std::vector<double>& mu,
                                  const std::vector<double>& mu_error = {}, const std::vector<double>& x_error = {},
                                  StzObjective objective = StzObjective::least_squares_mu);

struct MuICoefficients {
  double mu_s = kNaN, mu_2 = kNaN, I0 = kNaN;
};

// μ(I); NaN for I < 0 or I0 ≤ 0 (μ(0) = μ_s).
double mu_of_I(const MuICoefficients& c, double I);

struct MuIFit {
  MuICoefficients value;
  MuICoefficients error;
  double covariance[3][3] = {};  // of (μ_s, μ₂, I₀)
  double chi2 = kNaN;
  int dof = 0;
  double scale = kNaN;  // as StzFit::scale
  bool weighted = false;
};

// Least squares in μ of (μ_s, μ₂, I₀) to (I_k, μ_k). Same refusals as fit_stz (I ≤ 0 instead
// of x ≤ 0; μ may be any finite value).
MuIFit fit_mu_of_I(const std::vector<double>& I, const std::vector<double>& mu,
                   const std::vector<double>& mu_error = {});

// The two abscissae. With p_kin = ρ_p ν T/2 in 2D (T = ⟨|V|²⟩ without the mass, thesis eq.
// 4.5), d = 2⟨R⟩ and P the total pressure:
//   x = γ̇⟨R⟩/√T = (I/2) √((ν/2) P/p_kin),   I = γ̇d/√(P/ρ_p) = 2x / √((ν/2) P/p_kin).
// NaN unless ν, P, p_kin > 0.
double stz_rate_from_inertial_number(double I, double nu, double P, double p_kin);
double inertial_number_from_stz_rate(double x, double nu, double P, double p_kin);

// Root-mean-square residual in μ, √(Σ_k (μ_k − law_k)²/K), of each law over the same points
// (x_k for the STZ law, I_k for μ(I)). Points whose prediction is NaN are not counted.
struct LawComparison {
  double stz_rms = kNaN, mu_of_I_rms = kNaN;
  int stz_count = 0, mu_of_I_count = 0;
};
LawComparison compare_laws(const StzCoefficients& stz, const MuICoefficients& mu_i, const std::vector<double>& x,
                           const std::vector<double>& I, const std::vector<double>& mu);

}  // namespace granflow::stz
