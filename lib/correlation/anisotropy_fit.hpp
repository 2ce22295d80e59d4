#pragma once
// Fit of the angular dependence of the correlation length, thesis eq. 5.3:
//   ξ(θ) = ξ/(2π) · (1 − a0 sin 2(θ − θ0)),
// with ξ the isotropic length (eq. 5.2, given) and (a0, θ0) fitted by weighted
// nonlinear least squares (GSL gsl_multifit_nlinear, trust region / Levenberg–Marquardt).
//
// Sector averages: data averaged over sectors of width Δθ centred on θ_k follow the
// model with a0 replaced by a0·sin(Δθ)/Δθ (the exact average of sin 2θ over a sector),
// which the fit uses so that a0 is not biased low by the sector width.
//
// Uncertainties: the parameter covariance (JᵀJ)⁻¹ of the weighted residuals, scaled by
// max(1, √(χ²/dof)) when the data errors are given (the errors are then not trusted to be
// too large), or by √(χ²/dof) with unit weights when they are not (then the scatter
// about the fit is the only error estimate); dof = K − 2.
// Reported with a0 ≥ 0 and θ0 in [−π/2, π/2) (a0 → −a0 with θ0 → θ0 + π/2 is the same curve).
#include <limits>
#include <vector>

namespace granflow::correlation {

struct AnisotropyFit {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  double a0 = kNaN, a0_error = kNaN;
  double theta0 = kNaN, theta0_error = kNaN;
  double chi2_per_dof = kNaN;
  bool weighted = false;   // errors came from the given data errors
  bool converged = false;  // false: no fit (too few or non-finite data, or GSL failed)
};

// theta: sector centres (radians); xi_theta: ξ(θ_k); error: its standard errors (empty, or
// any non-finite or non-positive entry: unweighted fit); xi: the isotropic ξ;
// sector_width: Δθ of the averages (0 for values at points).
AnisotropyFit fit_anisotropy(const std::vector<double>& theta, const std::vector<double>& xi_theta,
                             const std::vector<double>& error, double xi, double sector_width);

// Eq. 5.3's shape for a length per direction, y(θ) = m (1 − a0 sin 2(θ − θ0)) with m the mean
// of the finite y_k (not fitted): fit_anisotropy with ξ = 2π m on the finite sectors only,
// with their errors (weighted unless one of those is not finite and positive). No fit
// (NaN) with fewer than 3 finite sectors.
AnisotropyFit fit_anisotropy_about_mean(const std::vector<double>& theta, const std::vector<double>& y,
                                        const std::vector<double>& error, double sector_width);

}  // namespace granflow::correlation
