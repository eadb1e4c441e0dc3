#include "core/statistics.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace kfw {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}

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

// Numerical Recipes' split: series for x < a + 1, continued fraction (Lentz) above.
double gamma_p(double a, double x) {
  if (!(a > 0.0) || !(x >= 0.0)) return kNaN;
  if (x == 0.0) return 0.0;
  const double gln = std::lgamma(a);
  if (x < a + 1.0) {
    double ap = a, sum = 1.0 / a, del = sum;
    for (int n = 0; n < 1000; ++n) {
      ap += 1.0;
      del *= x / ap;
      sum += del;
      if (std::abs(del) < std::abs(sum) * 1e-16) break;
    }
    return sum * std::exp(-x + a * std::log(x) - gln);
  }
  const double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 1000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1.0) < 1e-16) break;
  }
  return 1.0 - std::exp(-x + a * std::log(x) - gln) * h;
}

double chi2_cdf(double x, double k) {
  return x <= 0.0 ? 0.0 : gamma_p(0.5 * k, 0.5 * x);
}

double chi2_quantile(double p, double k) {
  if (!(p > 0.0 && p < 1.0) || !(k > 0.0)) return kNaN;
  double lo = 0.0, hi = std::max(1.0, k);
  while (chi2_cdf(hi, k) < p)
    hi *= 2.0;
  for (int i = 0; i < 200 && hi - lo > 1e-14 * std::max(1.0, hi); ++i) {
    const double mid = 0.5 * (lo + hi);
    (chi2_cdf(mid, k) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
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
