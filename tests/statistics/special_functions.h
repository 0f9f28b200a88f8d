// The distribution functions the statistical tests need (header-only, no
// external libraries): normal, chi-square and Student t tails and
// quantiles, computed from the regularized incomplete gamma and beta
// functions, and Sidak's correction.
#pragma once
#include <cmath>
#include <functional>

namespace pt::test {

// Regularized lower incomplete gamma P(a, x) and upper Q(a, x) = 1 - P.
// Series for x < a + 1, Lentz's continued fraction otherwise.
inline double gamma_p_series(double a, double x) {
  double term = 1.0 / a, sum = term;
  for (int n = 1; n < 100000; ++n) {
    term *= x / (a + n);
    sum += term;
    if (std::fabs(term) < std::fabs(sum) * 1e-16) break;
  }
  return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

inline double gamma_q_fraction(double a, double x) {
  const double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 100000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::fabs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::fabs(delta - 1.0) < 1e-16) break;
  }
  return h * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

inline double regularized_gamma_q(double a, double x) {
  if (x <= 0) return 1.0;
  if (!std::isfinite(x)) return 0.0;
  return x < a + 1.0 ? 1.0 - gamma_p_series(a, x) : gamma_q_fraction(a, x);
}

// Regularized incomplete beta I_x(a, b), continued fraction (Lentz) on the
// side where it converges fast.
inline double beta_fraction(double a, double b, double x) {
  const double tiny = 1e-300;
  double c = 1.0, d = 1.0 - (a + b) * x / (a + 1.0);
  if (std::fabs(d) < tiny) d = tiny;
  d = 1.0 / d;
  double h = d;
  for (int m = 1; m < 100000; ++m) {
    const int m2 = 2 * m;
    double aa = m * (b - m) * x / ((a + m2 - 1.0) * (a + m2));
    d = 1.0 + aa * d;
    if (std::fabs(d) < tiny) d = tiny;
    c = 1.0 + aa / c;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1.0 / d;
    h *= d * c;
    aa = -(a + m) * (a + b + m) * x / ((a + m2) * (a + m2 + 1.0));
    d = 1.0 + aa * d;
    if (std::fabs(d) < tiny) d = tiny;
    c = 1.0 + aa / c;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::fabs(delta - 1.0) < 1e-16) break;
  }
  return h;
}

inline double regularized_beta(double a, double b, double x) {
  if (x <= 0) return 0.0;
  if (x >= 1) return 1.0;
  const double front =
      std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x));
  if (x < (a + 1.0) / (a + b + 2.0)) return front * beta_fraction(a, b, x) / a;
  return 1.0 - front * beta_fraction(b, a, 1.0 - x) / b;
}

// Inverts a decreasing survival function sf on [lo, hi] by bisection.
inline double invert_decreasing(const std::function<double(double)>& sf, double p, double lo, double hi) {
  for (int i = 0; i < 300; ++i) {
    const double mid = 0.5 * (lo + hi);
    (sf(mid) > p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// Standard normal: upper tail P(Z > z) and its inverse.
inline double normal_sf(double z) { return 0.5 * std::erfc(z / std::sqrt(2.0)); }
inline double normal_upper_quantile(double p) { return invert_decreasing(normal_sf, p, -40.0, 40.0); }

// Chi-square with k degrees of freedom: upper tail and upper quantile.
inline double chi2_sf(double x, double k) { return regularized_gamma_q(0.5 * k, 0.5 * x); }
inline double chi2_upper_quantile(double p, double k) {
  return invert_decreasing([k](double x) { return chi2_sf(x, k); }, p, 0.0, 100.0 * k + 1000.0);
}

// Student t with nu degrees of freedom: upper tail P(T > t).
inline double student_t_sf(double t, double nu) {
  const double tail = 0.5 * regularized_beta(0.5 * nu, 0.5, nu / (nu + t * t));
  return t >= 0 ? tail : 1.0 - tail;
}
inline double student_t_upper_quantile(double p, double nu) {
  return invert_decreasing([nu](double t) { return student_t_sf(t, nu); }, p, -1e3, 1e3);
}

// Sidak: the level of each of k independent tests for a family-wise level alpha.
inline double sidak(double alpha, int k) { return 1.0 - std::pow(1.0 - alpha, 1.0 / k); }

}  // namespace pt::test
