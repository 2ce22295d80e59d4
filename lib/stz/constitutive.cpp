#include "stz/constitutive.hpp"

#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_multifit_nlinear.h>
#include <gsl/gsl_vector.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>

namespace granflow::stz {

namespace {

bool positive(double v) { return std::isfinite(v) && v > 0; }
bool valid(const StzCoefficients& c) { return positive(c.A) && positive(c.kappa) && positive(c.zeta); }

// ∂x/∂p·p for p = A, κ, ζ at μ: the derivatives in the logarithms of the coefficients, which
// is how the fit is parametrised (every coefficient stays positive).
void stz_log_gradient(const StzCoefficients& c, double mu, double out[3]) {
  const double ch = std::cosh(c.kappa * mu), sh = std::sinh(c.kappa * mu);
  out[0] = c.A * (sh - ch / (c.zeta * mu));
  out[1] = c.A * c.kappa * mu * (ch - sh / (c.zeta * mu));
  out[2] = c.A * ch / (c.zeta * mu);
}

// A trial step of the trust region that leaves the model's domain (overflow, NaN) must be
// rejected, not end the fit: GSL stops at a failed residual evaluation, so such residuals
// are replaced by a value far above any acceptable one, which the step test rejects.
constexpr double kOutside = 1e30;
double finite_or_outside(double r) { return std::isfinite(r) ? r : kOutside; }

// μ(x) on the branch μ ≥ t = tanθ* (given, so that a fit computes it once per coefficient set).
double invert(const StzCoefficients& c, double t, double x) {
  if (x == 0) return t;
  double lo = t, hi = 2 * t;
  while (stz_rate(c, hi) < x) {
    lo = hi;
    hi *= 2;
  }
  // Newton from the bracket's middle; a step that leaves the bracket is replaced by bisection,
  // and the bracket shrinks around the root at every step (x(μ) is increasing there).
  double m = 0.5 * (lo + hi);
  for (int i = 0; i < 200; ++i) {
    const double f = stz_rate(c, m) - x;
    if (f == 0) return m;
    (f < 0 ? lo : hi) = m;
    const double newton = m - f / stz_rate_derivative(c, m);
    const double next = (newton > lo && newton < hi) ? newton : 0.5 * (lo + hi);
    if (std::abs(next - m) <= 1e-15 * m || hi - lo <= 1e-15 * hi) return next;
    m = next;
  }
  return m;
}

// GSL's default error handler aborts the program; errors are handled from return codes.
struct GslErrorsOff {
  gsl_error_handler_t* previous = gsl_set_error_handler_off();
  ~GslErrorsOff() { gsl_set_error_handler(previous); }
};

struct Problem {
  std::size_t n = 0, p = 0;
  std::function<void(const double* q, double* r)> f;     // r[n]
  std::function<void(const double* q, double* jac)> df;  // jac[n·p], row-major
};

struct Minimum {
  std::vector<double> q, covariance;  // covariance: (JᵀJ)⁻¹, p×p row-major, unscaled
  double chi2 = kNaN;
  bool ok = false;
};

int gsl_f(const gsl_vector* x, void* params, gsl_vector* f) {
  const Problem& problem = *static_cast<const Problem*>(params);
  std::vector<double> r(problem.n);
  problem.f(gsl_vector_const_ptr(x, 0), r.data());
  for (std::size_t k = 0; k < problem.n; ++k) gsl_vector_set(f, k, finite_or_outside(r[k]));
  return GSL_SUCCESS;
}

int gsl_df(const gsl_vector* x, void* params, gsl_matrix* j) {
  const Problem& problem = *static_cast<const Problem*>(params);
  std::vector<double> jac(problem.n * problem.p);
  problem.df(gsl_vector_const_ptr(x, 0), jac.data());
  for (std::size_t k = 0; k < problem.n; ++k)
    for (std::size_t i = 0; i < problem.p; ++i) gsl_matrix_set(j, k, i, jac[k * problem.p + i]);
  return GSL_SUCCESS;
}

// Levenberg–Marquardt (GSL trust region) from `start`; ok only at a finite minimum with a
// covariance.
Minimum minimise(Problem problem, const std::vector<double>& start) {
  Minimum result;
  GslErrorsOff errors_off;
  gsl_multifit_nlinear_parameters parameters = gsl_multifit_nlinear_default_parameters();
  std::unique_ptr<gsl_multifit_nlinear_workspace, void (*)(gsl_multifit_nlinear_workspace*)> work(
      gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &parameters, problem.n, problem.p),
      gsl_multifit_nlinear_free);
  std::unique_ptr<gsl_matrix, void (*)(gsl_matrix*)> covariance(gsl_matrix_alloc(problem.p, problem.p),
                                                                gsl_matrix_free);
  if (!work || !covariance) return result;
  gsl_multifit_nlinear_fdf fdf{};
  fdf.f = gsl_f;
  fdf.df = gsl_df;
  fdf.n = problem.n;
  fdf.p = problem.p;
  fdf.params = &problem;
  gsl_vector_const_view x0 = gsl_vector_const_view_array(start.data(), problem.p);
  if (gsl_multifit_nlinear_init(&x0.vector, &fdf, work.get()) != GSL_SUCCESS) return result;
  int info = 0;
  const int status = gsl_multifit_nlinear_driver(1000, 1e-13, 1e-13, 0.0, nullptr, nullptr, &info, work.get());
  // No step reduces χ² any more (GSL_ENOPROG, reported as GSL_EMAXITER with info = GSL_ENOPROG
  // at the first iteration): the current point is the minimum to working precision.
  const bool at_minimum = status == GSL_ENOPROG || (status == GSL_EMAXITER && info == GSL_ENOPROG);
  if (status != GSL_SUCCESS && !at_minimum) return result;
  if (gsl_multifit_nlinear_covar(gsl_multifit_nlinear_jac(work.get()), 0.0, covariance.get()) != GSL_SUCCESS)
    return result;
  const gsl_vector* residual = gsl_multifit_nlinear_residual(work.get());
  gsl_blas_ddot(residual, residual, &result.chi2);
  const gsl_vector* x = gsl_multifit_nlinear_position(work.get());
  result.q.assign(gsl_vector_const_ptr(x, 0), gsl_vector_const_ptr(x, 0) + problem.p);
  result.covariance.resize(problem.p * problem.p);
  for (std::size_t i = 0; i < problem.p; ++i)
    for (std::size_t j = 0; j < problem.p; ++j)
      result.covariance[i * problem.p + j] = gsl_matrix_get(covariance.get(), i, j);
  result.ok =
      std::isfinite(result.chi2) && result.chi2 < kOutside &&
      std::all_of(result.q.begin(), result.q.end(), [](double v) { return std::isfinite(v); }) &&
      std::all_of(result.covariance.begin(), result.covariance.end(), [](double v) { return std::isfinite(v); });
  return result;
}

// Refusals shared by both fits.
std::vector<double> weights(const std::vector<double>& error, std::size_t n, const char* what) {
  if (error.empty()) return std::vector<double>(n, 1.0);
  if (error.size() != n) throw std::invalid_argument(std::string(what) + ": one error per point is needed");
  std::vector<double> w(n);
  for (std::size_t k = 0; k < n; ++k) {
    if (!positive(error[k])) throw std::invalid_argument(std::string(what) + ": errors must be positive and finite");
    w[k] = 1 / error[k];
  }
  return w;
}

void check_points(const std::vector<double>& abscissa, const std::vector<double>& mu, const char* what,
                  const char* abscissa_name, bool mu_positive) {
  if (abscissa.size() != mu.size())
    throw std::invalid_argument(std::string(what) + ": " + abscissa_name + " and mu differ in length");
  if (mu.size() < 3)
    throw std::invalid_argument(std::string(what) + ": " + std::to_string(mu.size()) + " points for 3 coefficients");
  for (std::size_t k = 0; k < mu.size(); ++k) {
    if (!positive(abscissa[k]))
      throw std::invalid_argument(std::string(what) + ": " + abscissa_name + " must be positive and finite");
    if (!std::isfinite(mu[k]) || (mu_positive && mu[k] <= 0))
      throw std::invalid_argument(std::string(what) +
                                  (mu_positive ? ": mu must be positive and finite" : ": mu must be finite"));
  }
}

// Scale of the covariance: see StzFit::scale.
double covariance_scale(double chi2, int dof, bool weighted) {
  if (dof <= 0) return 1.0;
  const double s = std::sqrt(chi2 / dof);
  return weighted ? std::max(1.0, s) : s;
}

StzCoefficients from_log(const double* q) { return {std::exp(q[0]), std::exp(q[1]), std::exp(q[2])}; }

// Least squares in μ: r_k = w_k (μ_k − μ(x_k)); with x(μ(x_k)) = x_k,
// ∂μ/∂log p = −(p ∂x/∂p)/(dx/dμ).
Problem least_squares_mu_problem(const std::vector<double>& x, const std::vector<double>& mu,
                                 const std::vector<double>& w) {
  Problem problem;
  problem.n = x.size();
  problem.p = 3;
  problem.f = [&x, &mu, &w](const double* q, double* r) {
    const StzCoefficients c = from_log(q);
    const double t = tan_theta_star(c.kappa, c.zeta);
    for (std::size_t k = 0; k < x.size(); ++k) r[k] = w[k] * (mu[k] - invert(c, t, x[k]));
  };
  problem.df = [&x, &w](const double* q, double* jac) {
    const StzCoefficients c = from_log(q);
    const double t = tan_theta_star(c.kappa, c.zeta);
    for (std::size_t k = 0; k < x.size(); ++k) {
      const double m = invert(c, t, x[k]);
      double g[3];
      stz_log_gradient(c, m, g);
      g[0] = x[k];  // = A ∂x/∂A at the curve point, exactly
      const double slope = stz_rate_derivative(c, m);
      for (int i = 0; i < 3; ++i) jac[k * 3 + i] = w[k] * g[i] / slope;
    }
  };
  return problem;
}

// Starting values. For a trial (tanθ*, κ), eq. 6.35 gives ζ = 1/(tanθ* tanh(κ tanθ*)) and
// x = A·g(μ) is linear in A, so A = Σ x g/Σ g² over the points with g > 0. The trial's
// objective is then evaluated exactly (least squares in μ); the grid spans tanθ* from 5 % to
// 102 % of the smallest μ and κ from 0.1 to 300 (log-spaced), and the best few trials are
// polished by Levenberg–Marquardt. No start is guessed from the data's shape.
std::vector<std::vector<double>> stz_starts(const std::vector<double>& x, const std::vector<double>& mu,
                                            const std::vector<double>& w, std::size_t keep) {
  const double mu_min = *std::min_element(mu.begin(), mu.end());
  struct Trial {
    double objective;
    std::vector<double> q;
  };
  std::vector<Trial> trials;
  constexpr int kT = 40, kK = 40;
  for (int i = 0; i < kT; ++i) {
    const double t = mu_min * (0.05 + (1.02 - 0.05) * i / (kT - 1));
    for (int j = 0; j < kK; ++j) {
      const double kappa = std::pow(10.0, -1 + 3.5 * j / (kK - 1));
      const double zeta = 1 / (t * std::tanh(kappa * t));
      double xg = 0, gg = 0;
      for (std::size_t k = 0; k < x.size(); ++k) {
        const double g = std::sinh(kappa * mu[k]) - std::cosh(kappa * mu[k]) / (zeta * mu[k]);
        if (g > 0 && std::isfinite(g)) {
          xg += x[k] * g;
          gg += g * g;
        }
      }
      const double A = xg / gg;
      if (!positive(A) || !positive(zeta)) continue;
      const StzCoefficients c{A, kappa, zeta};
      double objective = 0;
      for (std::size_t k = 0; k < x.size(); ++k) {
        const double r = w[k] * (mu[k] - invert(c, t, x[k]));
        objective += r * r;
      }
      if (std::isfinite(objective)) trials.push_back({objective, {std::log(A), std::log(kappa), std::log(zeta)}});
    }
  }
  std::sort(trials.begin(), trials.end(), [](const Trial& a, const Trial& b) { return a.objective < b.objective; });
  std::vector<std::vector<double>> starts;
  for (std::size_t i = 0; i < trials.size() && starts.size() < keep; ++i) starts.push_back(trials[i].q);
  return starts;
}

}  // namespace

double stz_rate(const StzCoefficients& c, double mu) {
  if (!valid(c) || !positive(mu)) return kNaN;
  return c.A * (std::sinh(c.kappa * mu) - std::cosh(c.kappa * mu) / (c.zeta * mu));
}

double stz_rate_derivative(const StzCoefficients& c, double mu) {
  if (!valid(c) || !positive(mu)) return kNaN;
  const double ch = std::cosh(c.kappa * mu), sh = std::sinh(c.kappa * mu);
  return c.A * (c.kappa * ch - c.kappa * sh / (c.zeta * mu) + ch / (c.zeta * mu * mu));
}

double tan_theta_star(double kappa, double zeta) {
  if (!positive(kappa) || !positive(zeta)) return kNaN;
  // h(t) = ζ t tanh(κt) − 1 rises strictly from −1 at t = 0: bracket, then bisect.
  const auto h = [&](double t) { return zeta * t * std::tanh(kappa * t) - 1; };
  double lo = 0, hi = 1 / zeta;
  while (h(hi) < 0) {
    lo = hi;
    hi *= 2;
  }
  for (int i = 0; i < 200 && hi - lo > 1e-15 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (h(mid) < 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double stz_stress_ratio(const StzCoefficients& c, double x) {
  if (!valid(c) || !std::isfinite(x) || x < 0) return kNaN;
  return invert(c, tan_theta_star(c.kappa, c.zeta), x);
}

StzFit fit_stz(const std::vector<double>& x, const std::vector<double>& mu, const std::vector<double>& mu_error,
               const std::vector<double>& x_error, StzObjective objective) {
  check_points(x, mu, "STZ fit", "x", true);
  const std::size_t n = x.size();
  const std::vector<double> wm = weights(mu_error, n, "STZ fit (mu errors)");
  std::vector<double> wx;
  if (objective == StzObjective::orthogonal_distance) {
    if (mu_error.empty() || x_error.empty())
      throw std::invalid_argument("STZ fit: orthogonal distance regression needs errors on both x and mu");
    wx = weights(x_error, n, "STZ fit (x errors)");
  }

  // Least squares in μ from the best grid trials; the lowest minimum wins.
  Minimum best;
  for (const auto& start : stz_starts(x, mu, wm, 4)) {
    Minimum m = minimise(least_squares_mu_problem(x, mu, wm), start);
    if (m.ok && (!best.ok || m.chi2 < best.chi2)) best = m;
  }
  if (!best.ok) throw std::runtime_error("STZ fit: the least-squares minimisation did not converge");

  if (objective == StzObjective::orthogonal_distance) {
    // Unknowns: log A, log κ, log ζ, then log m_k (the curve point of datum k, positive).
    // Residuals: wx_k (x_k − x(m_k)), then wm_k (μ_k − m_k). Started from the least-squares fit,
    // with m_k = μ(x_k) on its curve.
    Problem problem;
    problem.n = 2 * n;
    problem.p = 3 + n;
    problem.f = [&](const double* q, double* r) {
      const StzCoefficients c = from_log(q);
      for (std::size_t k = 0; k < n; ++k) {
        const double m = std::exp(q[3 + k]);
        r[k] = wx[k] * (x[k] - stz_rate(c, m));
        r[n + k] = wm[k] * (mu[k] - m);
      }
    };
    problem.df = [&](const double* q, double* jac) {
      const StzCoefficients c = from_log(q);
      std::fill(jac, jac + problem.n * problem.p, 0.0);
      for (std::size_t k = 0; k < n; ++k) {
        const double m = std::exp(q[3 + k]);
        double g[3];
        stz_log_gradient(c, m, g);
        for (int i = 0; i < 3; ++i) jac[k * problem.p + i] = -wx[k] * g[i];
        jac[k * problem.p + 3 + k] = -wx[k] * stz_rate_derivative(c, m) * m;
        jac[(n + k) * problem.p + 3 + k] = -wm[k] * m;
      }
    };
    std::vector<double> start(best.q);
    const StzCoefficients c = from_log(best.q.data());
    for (std::size_t k = 0; k < n; ++k) start.push_back(std::log(stz_stress_ratio(c, x[k])));
    Minimum odr = minimise(problem, start);
    if (!odr.ok) throw std::runtime_error("STZ fit: the orthogonal distance regression did not converge");
    // The coefficients' covariance is the leading 3×3 block of the full one (the curve points
    // are nuisance parameters).
    std::vector<double> block(9);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) block[i * 3 + j] = odr.covariance[i * problem.p + j];
    best.q.assign(odr.q.begin(), odr.q.begin() + 3);
    best.covariance = block;
    best.chi2 = odr.chi2;
  }

  StzFit fit;
  fit.objective = objective;
  fit.weighted = !mu_error.empty();
  fit.value = from_log(best.q.data());
  fit.chi2 = best.chi2;
  fit.dof = int(n) - 3;
  fit.scale = covariance_scale(fit.chi2, fit.dof, fit.weighted);
  const double p[3] = {fit.value.A, fit.value.kappa, fit.value.zeta};
  // From the logarithms to the coefficients: cov(p_i, p_j) = p_i p_j cov(log p_i, log p_j).
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) fit.covariance[i][j] = fit.scale * fit.scale * p[i] * p[j] * best.covariance[i * 3 + j];
  fit.error = {std::sqrt(fit.covariance[0][0]), std::sqrt(fit.covariance[1][1]), std::sqrt(fit.covariance[2][2])};

  // tanθ* and its error: implicit differentiation of h = ζ t tanh(κt) − 1 = 0,
  // ∂t/∂κ = −ζ t² sech²(κt)/h_t, ∂t/∂ζ = −t tanh(κt)/h_t, h_t = ζ tanh(κt) + ζκt sech²(κt).
  const double t = tan_theta_star(fit.value.kappa, fit.value.zeta);
  const double th = std::tanh(fit.value.kappa * t), sech2 = 1 - th * th;
  const double ht = fit.value.zeta * th + fit.value.zeta * fit.value.kappa * t * sech2;
  const double dk = -fit.value.zeta * t * t * sech2 / ht, dz = -t * th / ht;
  // In the logarithms the minimiser worked in (∂t/∂log κ = κ ∂t/∂κ): the better conditioned
  // form. Where the coefficients are degenerate (points near the κ → 0 limit x = c₁μ − c₂/μ,
  // which fixes tanθ* but not A, κ, ζ), the three terms are huge and cancel: a variance left
  // with fewer than 8 of their digits is not a result, and the error is NaN, not a round-off 0
  // (stz_repose_jackknife_error then gives one).
  const double a = fit.value.kappa * dk, b = fit.value.zeta * dz, s2 = fit.scale * fit.scale;
  const double t1 = a * a * s2 * best.covariance[4], t2 = 2 * a * b * s2 * best.covariance[5],
               t3 = b * b * s2 * best.covariance[8];
  const double var = t1 + t2 + t3;
  fit.tan_theta_star = t;
  fit.tan_theta_star_error = var > 1e-8 * (std::abs(t1) + std::abs(t2) + std::abs(t3)) ? std::sqrt(var) : kNaN;
  fit.theta_star = std::atan(t);
  fit.theta_star_error = fit.tan_theta_star_error / (1 + t * t);
  return fit;
}

double stz_repose_jackknife_error(const std::vector<double>& x, const std::vector<double>& mu,
                                  const std::vector<double>& mu_error, const std::vector<double>& x_error,
                                  StzObjective objective) {
  const std::size_t n = x.size();
  if (n < 5) return kNaN;
  std::vector<double> t(n);
  for (std::size_t k = 0; k < n; ++k) {
    auto without = [k](const std::vector<double>& v) {
      if (v.empty()) return v;
      std::vector<double> w(v);
      w.erase(w.begin() + std::ptrdiff_t(k));
      return w;
    };
    try {
      t[k] = fit_stz(without(x), without(mu), without(mu_error), without(x_error), objective).tan_theta_star;
    } catch (const std::runtime_error&) {
      return kNaN;
    }
    if (!std::isfinite(t[k])) return kNaN;
  }
  double mean = 0;
  for (double v : t) mean += v / double(n);
  double sum = 0;
  for (double v : t) sum += (v - mean) * (v - mean);
  return std::sqrt(double(n - 1) / double(n) * sum);
}

double mu_of_I(const MuICoefficients& c, double I) {
  if (!std::isfinite(I) || I < 0 || !positive(c.I0)) return kNaN;
  return c.mu_s + (c.mu_2 - c.mu_s) * I / (I + c.I0);
}

MuIFit fit_mu_of_I(const std::vector<double>& I, const std::vector<double>& mu, const std::vector<double>& mu_error) {
  check_points(I, mu, "mu(I) fit", "I", false);
  const std::size_t n = I.size();
  const std::vector<double> w = weights(mu_error, n, "mu(I) fit (mu errors)");

  // For a fixed I₀ the law is linear in (μ_s, μ₂ − μ_s), with basis (1, s_k), s_k = I_k/(I_k + I₀):
  // weighted linear least squares on a log grid of I₀ from 10⁻³ I_min to 10³ I_max gives the
  // start; Levenberg–Marquardt in (μ_s, μ₂, log I₀) then polishes all three together.
  const auto [i_min, i_max] = std::minmax_element(I.begin(), I.end());
  const double l_lo = std::log(*i_min) - std::log(1e3), l_hi = std::log(*i_max) + std::log(1e3);
  double best_objective = std::numeric_limits<double>::infinity();
  std::vector<double> start;
  constexpr int kGrid = 400;
  for (int g = 0; g < kGrid; ++g) {
    const double l = l_lo + (l_hi - l_lo) * g / (kGrid - 1), I0 = std::exp(l);
    double s00 = 0, s01 = 0, s11 = 0, b0 = 0, b1 = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const double s = I[k] / (I[k] + I0), ww = w[k] * w[k];
      s00 += ww;
      s01 += ww * s;
      s11 += ww * s * s;
      b0 += ww * mu[k];
      b1 += ww * mu[k] * s;
    }
    const double det = s00 * s11 - s01 * s01;
    if (!(std::abs(det) > 1e-300)) continue;
    const double mu_s = (s11 * b0 - s01 * b1) / det, delta = (s00 * b1 - s01 * b0) / det;
    double objective = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const double r = w[k] * (mu[k] - mu_s - delta * I[k] / (I[k] + I0));
      objective += r * r;
    }
    if (objective < best_objective) {
      best_objective = objective;
      start = {mu_s, mu_s + delta, l};
    }
  }
  if (start.empty()) throw std::runtime_error("mu(I) fit: no starting point (all I equal?)");

  Problem problem;
  problem.n = n;
  problem.p = 3;
  problem.f = [&](const double* q, double* r) {
    const MuICoefficients c{q[0], q[1], std::exp(q[2])};
    for (std::size_t k = 0; k < n; ++k) r[k] = w[k] * (mu[k] - mu_of_I(c, I[k]));
  };
  problem.df = [&](const double* q, double* jac) {
    const double I0 = std::exp(q[2]);
    for (std::size_t k = 0; k < n; ++k) {
      const double s = I[k] / (I[k] + I0);
      jac[k * 3 + 0] = -w[k] * (1 - s);
      jac[k * 3 + 1] = -w[k] * s;
      jac[k * 3 + 2] = w[k] * (q[1] - q[0]) * s * I0 / (I[k] + I0);  // −w ∂μ/∂log I₀
    }
  };
  const Minimum m = minimise(problem, start);
  if (!m.ok) throw std::runtime_error("mu(I) fit: the minimisation did not converge");

  MuIFit fit;
  fit.weighted = !mu_error.empty();
  fit.value = {m.q[0], m.q[1], std::exp(m.q[2])};
  fit.chi2 = m.chi2;
  fit.dof = int(n) - 3;
  fit.scale = covariance_scale(fit.chi2, fit.dof, fit.weighted);
  const double d[3] = {1, 1, fit.value.I0};  // ∂(μ_s, μ₂, I₀)/∂(μ_s, μ₂, log I₀), diagonal
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) fit.covariance[i][j] = fit.scale * fit.scale * d[i] * d[j] * m.covariance[i * 3 + j];
  fit.error = {std::sqrt(fit.covariance[0][0]), std::sqrt(fit.covariance[1][1]), std::sqrt(fit.covariance[2][2])};
  return fit;
}

double stz_rate_from_inertial_number(double I, double nu, double P, double p_kin) {
  if (!positive(nu) || !positive(P) || !positive(p_kin)) return kNaN;
  return 0.5 * I * std::sqrt(0.5 * nu * P / p_kin);
}

double inertial_number_from_stz_rate(double x, double nu, double P, double p_kin) {
  if (!positive(nu) || !positive(P) || !positive(p_kin)) return kNaN;
  return 2 * x / std::sqrt(0.5 * nu * P / p_kin);
}

LawComparison compare_laws(const StzCoefficients& stz, const MuICoefficients& mu_i, const std::vector<double>& x,
                           const std::vector<double>& I, const std::vector<double>& mu) {
  if (x.size() != mu.size() || I.size() != mu.size())
    throw std::invalid_argument("law comparison: x, I and mu differ in length");
  LawComparison out;
  double s_stz = 0, s_mu_i = 0;
  for (std::size_t k = 0; k < mu.size(); ++k) {
    if (!std::isfinite(mu[k])) continue;
    const double a = stz_stress_ratio(stz, x[k]), b = mu_of_I(mu_i, I[k]);
    if (std::isfinite(a)) {
      s_stz += (mu[k] - a) * (mu[k] - a);
      ++out.stz_count;
    }
    if (std::isfinite(b)) {
      s_mu_i += (mu[k] - b) * (mu[k] - b);
      ++out.mu_of_I_count;
    }
  }
  if (out.stz_count > 0) out.stz_rms = std::sqrt(s_stz / out.stz_count);
  if (out.mu_of_I_count > 0) out.mu_of_I_rms = std::sqrt(s_mu_i / out.mu_of_I_count);
  return out;
}

}  // namespace granflow::stz
