// The geometric sums of eqs. 6.27–6.29 to a non-integer limit and the model's prediction
// (network.hpp for the definitions, docs/method/network.md for the two readings of ℓ_max).
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "network/network.hpp"

namespace granflow::network {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Beyond this many terms the integer sums use their closed forms instead of a loop.
constexpr double kLoopLimit = 1e7;

bool is_integer(double x) { return std::floor(x) == x; }

// Σ_{ℓ=1}^{n} b^ℓ term by term: the definition, exact at any base (b = 1 included).
double power_sum_integer(double b, double n) {
  if (n > kLoopLimit) return b == 1 ? n : b * (1 - std::pow(b, n)) / (1 - b);
  double sum = 0, term = 1;
  for (double l = 1; l <= n; ++l) {
    term *= b;
    sum += term;
  }
  return sum;
}

// Σ_{ℓ=1}^{n} Σ_{i=0}^{ℓ} q^i m^{ℓ−i} by T_ℓ = m T_{ℓ−1} + q^ℓ (T_0 = 1): the definition
// summed in ℓ order, no division by m − q.
double mixed_sum_integer(double q, double m, double n) {
  if (n > kLoopLimit) return kNaN;
  double sum = 0, inner = 1, q_power = 1;
  for (double l = 1; l <= n; ++l) {
    q_power *= q;
    inner = m * inner + q_power;
    sum += inner;
  }
  return sum;
}

// log b for b > 0, accurate near b = 1 (b − 1 is exact there).
double log_base(double b) { return (b >= 0.5 && b <= 2) ? std::log1p(b - 1) : std::log(b); }

// Continued S(b, L) for b ≥ 0 and non-integer L: b(1 − b^L)/(1 − b), L at b = 1.
double power_sum_continued(double b, double L) {
  if (b == 1) return L;
  if (b == 0) return 0;
  return b * -std::expm1(L * log_base(b)) / (1 - b);
}

// ∂S/∂b of the continued sum for b ≥ 0 and non-integer L.
double power_sum_derivative(double b, double L) {
  if (b == 0) return 1;  // Σ ℓ b^{ℓ−1} at b = 0 for L > 0
  const double t = log_base(b);
  if (std::abs(t) * std::max(L, 1.0) < 1e-3) {
    // Near b = 1 the closed form cancels: S(e^t) = Σ_k t^k/k! F_k(L) with F_k the Faulhaber
    // polynomials Σ_{ℓ=1}^{L} ℓ^k (continued), so dS/dt = Σ_k t^k/k! F_{k+1}(L).
    const double L1 = L + 1, LL = L * L1;
    const double F1 = LL / 2;
    const double F2 = LL * (2 * L + 1) / 6;
    const double F3 = LL * LL / 4;
    const double F4 = LL * (2 * L + 1) * (3 * LL - 1) / 30;
    const double F5 = LL * LL * (2 * LL - 1) / 12;
    const double dS_dt = F1 + t * (F2 + t * (F3 / 2 + t * (F4 / 6 + t * F5 / 24)));
    return dS_dt / b;
  }
  // [1 − (L+1) b^L + L b^{L+1}]/(1 − b)², the numerator through expm1.
  const double numerator = -(L + 1) * std::expm1(L * t) + L * std::expm1((L + 1) * t);
  return numerator / ((1 - b) * (1 - b));
}

}  // namespace

bool continuation_real(double base, double limit) { return base >= 0 || is_integer(limit); }

double power_sum(double base, double limit, SumLimit how) {
  if (std::isnan(base) || std::isnan(limit)) return kNaN;
  if (limit < 0) throw std::invalid_argument("geometric sum with a negative limit");
  if (!std::isfinite(limit)) return kNaN;
  const double n = std::floor(limit);
  if (how == SumLimit::floor || n == limit || !continuation_real(base, limit)) return power_sum_integer(base, n);
  return power_sum_continued(base, limit);
}

double mixed_sum(double q, double m, double limit, SumLimit how) {
  if (std::isnan(q) || std::isnan(m) || std::isnan(limit)) return kNaN;
  if (limit < 0) throw std::invalid_argument("geometric sum with a negative limit");
  if (!std::isfinite(limit)) return kNaN;
  const double n = std::floor(limit);
  if (how == SumLimit::floor || n == limit || !continuation_real(q, limit) || !continuation_real(m, limit))
    return mixed_sum_integer(q, m, n);
  // W = (g(m) − g(q))/(m − q) with g(x) = x S(x, L). Close to m = q the quotient loses
  // digits (rounding/|m − q|); there g′ at the midpoint, whose error is O((m − q)²): both
  // are ≲ 1e-10 relative at the switch.
  const double scale = std::max({std::abs(m), std::abs(q), 1e-300});
  if (std::abs(m - q) <= 1e-5 * scale) {
    const double c = (m + q) / 2;
    return power_sum_continued(c, limit) + c * power_sum_derivative(c, limit);
  }
  return (m * power_sum_continued(m, limit) - q * power_sum_continued(q, limit)) / (m - q);
}

Prediction predict(double z, double Phi, double Psi, double a_c, double a_c_prime, double a_f, double a_f_prime,
                   double xi_ratio, SumLimit how) {
  if (std::isnan(z) || std::isnan(Phi) || std::isnan(Psi) || std::isnan(xi_ratio) || !std::isfinite(xi_ratio))
    return {kNaN, kNaN, kNaN, false};
  const double M = std::min(Phi * (z - 1), 1.0);  // the cap is on Φ(z − 1) only
  const double Q = Psi * (z - 1);
  const double L = std::max(xi_ratio - 1, 0.0);
  const double SM = power_sum(M, L, how), SQ = power_sum(Q, L, how), W = mixed_sum(Q, M, L, how);
  Prediction p;
  p.pressure = SM;
  p.shear = -0.5 * (a_f * SQ + a_c * W);
  p.xx = SM + a_f_prime / 2 * SQ + a_c_prime / 2 * W;
  p.continuation_real = continuation_real(M, L) && continuation_real(Q, L);
  return p;
}

}  // namespace granflow::network
