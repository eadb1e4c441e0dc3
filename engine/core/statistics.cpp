#include "core/statistics.h"

#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/special_functions/gamma.hpp>
#include <cmath>
#include <limits>

namespace kfw {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Errors come back as NaN (the callers' convention), never as exceptions.
using Policy = boost::math::policies::policy<
    boost::math::policies::domain_error<boost::math::policies::ignore_error>,
    boost::math::policies::overflow_error<boost::math::policies::ignore_error>,
    boost::math::policies::evaluation_error<boost::math::policies::ignore_error>>;
constexpr Policy kPolicy{};
}  // namespace

double mean_finite(const std::vector<double>& v, std::size_t from) {
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t i = from; i < v.size(); ++i) {
    if (std::isfinite(v[i])) {
      sum += v[i];
      ++n;
    }
  }
  return n ? sum / static_cast<double>(n) : kNaN;
}

double rmse_finite(const std::vector<double>& a, const std::vector<double>& b, std::size_t from) {
  double sum = 0.0;
  std::size_t n = 0;
  const std::size_t end = std::min(a.size(), b.size());
  for (std::size_t i = from; i < end; ++i) {
    const double d = a[i] - b[i];
    if (std::isfinite(d)) {
      sum += d * d;
      ++n;
    }
  }
  return n ? std::sqrt(sum / static_cast<double>(n)) : kNaN;
}

double last_finite(const std::vector<double>& v) {
  for (auto it = v.rbegin(); it != v.rend(); ++it) {
    if (std::isfinite(*it)) return *it;
  }
  return kNaN;
}

std::size_t count_finite(const std::vector<double>& v) {
  return static_cast<std::size_t>(
      std::count_if(v.begin(), v.end(), [](double x) { return std::isfinite(x); }));
}

// Boost.Math (libboost-math-dev, header-only): accurate at the large degrees of freedom that
// Monte Carlo bounds need (N runs × n states).
double gamma_p(double a, double x) {
  if (!(a > 0.0) || !(x >= 0.0) || std::isinf(a)) return kNaN;
  if (std::isinf(x)) return 1.0;
  return boost::math::gamma_p(a, x, kPolicy);
}

double chi2_cdf(double x, double k) {
  if (!(k > 0.0) || std::isinf(k) || std::isnan(x)) return kNaN;
  if (x <= 0.0) return 0.0;
  if (std::isinf(x)) return 1.0;
  return boost::math::cdf(boost::math::chi_squared_distribution<double, Policy>(k), x);
}

double chi2_quantile(double p, double k) {
  if (!(p > 0.0 && p < 1.0) || !(k > 0.0) || std::isinf(k)) return kNaN;
  return boost::math::quantile(boost::math::chi_squared_distribution<double, Policy>(k), p);
}

double fraction_inside(const std::vector<double>& nis, double dof, double alpha) {
  const double lo = chi2_quantile(0.5 * alpha, dof), hi = chi2_quantile(1.0 - 0.5 * alpha, dof);
  std::size_t n = 0, inside = 0;
  for (double v : nis) {
    if (!std::isfinite(v)) continue;
    ++n;
    if (v >= lo && v <= hi) ++inside;
  }
  return n ? static_cast<double>(inside) / static_cast<double>(n) : kNaN;
}

}  // namespace kfw
