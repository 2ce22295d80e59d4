#include "correlation/anisotropy_fit.hpp"

#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_multifit_nlinear.h>
#include <gsl/gsl_vector.h>

#include <cmath>
#include <memory>

namespace granflow::correlation {

namespace {

struct Data {
  const std::vector<double>& theta;
  const std::vector<double>& y;
  std::vector<double> weight;  // 1/σ_k
  double scale;                // ξ/(2π)
  double smear;                // sin(Δθ)/Δθ
};

// Residuals r_k = (y_k − m_k)/σ_k, m_k = scale·(1 − a0·smear·sin 2(θ_k − θ0)).
int residuals(const gsl_vector* x, void* params, gsl_vector* f) {
  const Data& d = *static_cast<const Data*>(params);
  const double a0 = gsl_vector_get(x, 0), theta0 = gsl_vector_get(x, 1);
  for (std::size_t k = 0; k < d.y.size(); ++k) {
    const double model = d.scale * (1 - a0 * d.smear * std::sin(2 * (d.theta[k] - theta0)));
    gsl_vector_set(f, k, (d.y[k] - model) * d.weight[k]);
  }
  return GSL_SUCCESS;
}

int jacobian(const gsl_vector* x, void* params, gsl_matrix* j) {
  const Data& d = *static_cast<const Data*>(params);
  const double a0 = gsl_vector_get(x, 0), theta0 = gsl_vector_get(x, 1);
  for (std::size_t k = 0; k < d.y.size(); ++k) {
    const double phase = 2 * (d.theta[k] - theta0);
    gsl_matrix_set(j, k, 0, d.scale * d.smear * std::sin(phase) * d.weight[k]);
    gsl_matrix_set(j, k, 1, -2 * d.scale * a0 * d.smear * std::cos(phase) * d.weight[k]);
  }
  return GSL_SUCCESS;
}

// GSL's default error handler aborts the program; errors are handled from return codes.
struct GslErrorsOff {
  gsl_error_handler_t* previous = gsl_set_error_handler_off();
  ~GslErrorsOff() { gsl_set_error_handler(previous); }
};

}  // namespace

AnisotropyFit fit_anisotropy(const std::vector<double>& theta, const std::vector<double>& xi_theta,
                             const std::vector<double>& error, double xi, double sector_width) {
  AnisotropyFit fit;
  const std::size_t n = xi_theta.size();
  if (n < 3 || theta.size() != n || !std::isfinite(xi) || xi == 0) return fit;
  for (std::size_t k = 0; k < n; ++k)
    if (!std::isfinite(xi_theta[k]) || !std::isfinite(theta[k])) return fit;

  bool weighted = error.size() == n;
  for (double e : error) weighted = weighted && std::isfinite(e) && e > 0;
  Data data{theta, xi_theta, std::vector<double>(n, 1.0), xi / (2 * M_PI),
            sector_width > 0 ? std::sin(sector_width) / sector_width : 1.0};
  if (weighted)
    for (std::size_t k = 0; k < n; ++k) data.weight[k] = 1 / error[k];

  // Start from the projection on sin 2θ and cos 2θ (exact for equally spaced sectors):
  // y/scale − 1 = −a0·smear·cos 2θ0 · sin 2θ + a0·smear·sin 2θ0 · cos 2θ.
  double s = 0, c = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double u = xi_theta[k] / data.scale - 1;
    s += 2.0 / double(n) * u * std::sin(2 * theta[k]);
    c += 2.0 / double(n) * u * std::cos(2 * theta[k]);
  }
  const double start[2] = {std::hypot(s, c) / data.smear, 0.5 * std::atan2(c, -s)};

  GslErrorsOff errors_off;
  gsl_multifit_nlinear_parameters parameters = gsl_multifit_nlinear_default_parameters();
  std::unique_ptr<gsl_multifit_nlinear_workspace, void (*)(gsl_multifit_nlinear_workspace*)> work(
      gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &parameters, n, 2), gsl_multifit_nlinear_free);
  std::unique_ptr<gsl_matrix, void (*)(gsl_matrix*)> covariance(gsl_matrix_alloc(2, 2), gsl_matrix_free);
  if (!work || !covariance) return fit;
  gsl_multifit_nlinear_fdf fdf{};
  fdf.f = residuals;
  fdf.df = jacobian;
  fdf.n = n;
  fdf.p = 2;
  fdf.params = &data;
  gsl_vector_const_view x0 = gsl_vector_const_view_array(start, 2);
  if (gsl_multifit_nlinear_init(&x0.vector, &fdf, work.get()) != GSL_SUCCESS) return fit;
  int info = 0;
  const int status = gsl_multifit_nlinear_driver(200, 1e-12, 1e-12, 0.0, nullptr, nullptr, &info, work.get());
  // No step reduces χ² (GSL_ENOPROG; at the first iteration the driver reports it as
  // GSL_EMAXITER with info = GSL_ENOPROG): the start is already the minimum, which it is
  // whenever the weights are equal, the projection above then being the least-squares fit.
  const bool at_minimum = status == GSL_ENOPROG || (status == GSL_EMAXITER && info == GSL_ENOPROG);
  if ((status != GSL_SUCCESS && !at_minimum) ||
      gsl_multifit_nlinear_covar(gsl_multifit_nlinear_jac(work.get()), 0.0, covariance.get()) != GSL_SUCCESS)
    return fit;

  double chi2 = 0;
  gsl_blas_ddot(gsl_multifit_nlinear_residual(work.get()), gsl_multifit_nlinear_residual(work.get()), &chi2);
  const double dof = double(n - 2);
  fit.chi2_per_dof = dof > 0 ? chi2 / dof : AnisotropyFit::kNaN;
  const double inflate =
      dof > 0 ? (weighted ? std::max(1.0, std::sqrt(chi2 / dof)) : std::sqrt(chi2 / dof)) : AnisotropyFit::kNaN;
  const gsl_vector* x = gsl_multifit_nlinear_position(work.get());
  double a0 = gsl_vector_get(x, 0), theta0 = gsl_vector_get(x, 1);
  if (a0 < 0) {
    a0 = -a0;
    theta0 += M_PI / 2;
  }
  theta0 -= M_PI * std::floor((theta0 + M_PI / 2) / M_PI);  // into [−π/2, π/2)
  fit.a0 = a0;
  fit.theta0 = theta0;
  fit.a0_error = inflate * std::sqrt(gsl_matrix_get(covariance.get(), 0, 0));
  fit.theta0_error = inflate * std::sqrt(gsl_matrix_get(covariance.get(), 1, 1));
  fit.weighted = weighted;
  fit.converged = std::isfinite(a0) && std::isfinite(theta0);
  return fit;
}

AnisotropyFit fit_anisotropy_about_mean(const std::vector<double>& theta, const std::vector<double>& y,
                                        const std::vector<double>& error, double sector_width) {
  const std::size_t n = y.size();
  if (theta.size() != n) return AnisotropyFit{};
  const bool with_errors = error.size() == n;
  std::vector<double> finite_theta, finite_y, finite_error;
  double mean = 0;
  int finite = 0;
  for (std::size_t k = 0; k < n; ++k) {
    if (!std::isfinite(y[k])) continue;
    mean += y[k], ++finite;
    finite_theta.push_back(theta[k]);
    finite_y.push_back(y[k]);
    if (with_errors) finite_error.push_back(error[k]);
  }
  if (finite < 3) return AnisotropyFit{};
  return fit_anisotropy(finite_theta, finite_y, finite_error, 2 * M_PI * mean / finite, sector_width);
}

}  // namespace granflow::correlation
