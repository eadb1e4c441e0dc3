#include "core/consistency.h"

#include <cmath>
#include <limits>

#include "core/scenario.h"
#include "core/statistics.h"

namespace kfw {

namespace {
std::vector<double> finite_only(const std::vector<double>& v) {
  std::vector<double> out;
  out.reserve(v.size());
  for (double x : v) {
    if (std::isfinite(x)) out.push_back(x);
  }
  return out;
}
}  // namespace

NisBounds nis_bounds(double dof, std::size_t window, double alpha) {
  const double w = static_cast<double>(window < 1 ? 1 : window);
  return {chi2_quantile(0.5 * alpha, dof * w) / w, chi2_quantile(1.0 - 0.5 * alpha, dof * w) / w};
}

std::vector<double> moving_average_finite(const std::vector<double>& v, std::size_t window) {
  std::vector<double> out(v.size(), std::numeric_limits<double>::quiet_NaN());
  if (window == 0) return out;
  std::vector<double> ring(window, 0.0);
  double sum = 0.0;
  std::size_t count = 0, head = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v[i])) continue;
    if (count == window) {
      sum -= ring[head];
    } else {
      ++count;
    }
    ring[head] = v[i];
    sum += v[i];
    head = (head + 1) % window;
    if (count == window) out[i] = sum / static_cast<double>(window);
  }
  return out;
}

std::vector<double> autocorrelation(const std::vector<double>& v, std::size_t max_lag) {
  const auto x = finite_only(v);
  const std::size_t n = x.size();
  std::vector<double> r(max_lag + 1, std::numeric_limits<double>::quiet_NaN());
  if (n < 2) return r;
  double mean = 0.0;
  for (double a : x)
    mean += a;
  mean /= static_cast<double>(n);
  double c0 = 0.0;
  for (double a : x)
    c0 += (a - mean) * (a - mean);
  if (!(c0 > 0.0)) return r;
  for (std::size_t lag = 0; lag <= max_lag && lag < n; ++lag) {
    double c = 0.0;
    for (std::size_t i = lag; i < n; ++i)
      c += (x[i] - mean) * (x[i - lag] - mean);
    r[lag] = c / c0;
  }
  return r;
}

Whiteness ljung_box(const std::vector<double>& v, std::size_t max_lag) {
  Whiteness w;
  w.acf = autocorrelation(v, max_lag);
  w.n = count_finite(v);
  const double n = static_cast<double>(w.n);
  w.band = w.n ? 1.96 / std::sqrt(n) : std::numeric_limits<double>::quiet_NaN();
  if (w.n <= max_lag + 1) {
    w.q = w.p_value = std::numeric_limits<double>::quiet_NaN();
    return w;
  }
  double q = 0.0;
  for (std::size_t k = 1; k <= max_lag; ++k)
    q += w.acf[k] * w.acf[k] / (n - static_cast<double>(k));
  w.q = n * (n + 2.0) * q;
  w.p_value = 1.0 - chi2_cdf(w.q, static_cast<double>(max_lag));
  return w;
}

namespace {
// A channel name as a metric key suffix: "range 1" -> "range_1".
std::string key_of(std::string name) {
  for (char& ch : name) {
    if (ch == ' ') ch = '_';
  }
  return name;
}
}  // namespace

void add_consistency_metrics(const std::vector<InnovationChannel>& channels, const NeesSeries& nees,
                             std::map<std::string, double>& metrics) {
  double nis_sum = 0.0, inside = 0.0, worst_p = std::numeric_limits<double>::quiet_NaN();
  std::map<std::string, double> per_channel;
  std::size_t n = 0, counted = 0;
  for (const auto& c : channels) {
    const std::size_t cn = count_finite(c.nis);
    if (cn == 0) continue;
    // NIS normalised by its dof so that channels of different size average together.
    for (double v : c.nis) {
      if (std::isfinite(v)) nis_sum += v / c.dof;
    }
    n += cn;
    inside += fraction_inside(c.nis, c.dof) * static_cast<double>(cn);
    counted += cn;
    if (!c.normalized.empty()) {
      const double p = ljung_box(c.normalized, 20).p_value;
      if (std::isfinite(p) && !(p >= worst_p)) worst_p = p;
      if (std::isfinite(p) && channels.size() > 1) per_channel["whiteness_p." + key_of(c.name)] = p;
    }
  }
  auto put = [&](const char* key, double v) { metrics.emplace(key, v); };
  if (n) {
    put("nis_mean",
        nis_sum / static_cast<double>(n) * (channels.size() == 1 ? channels[0].dof : 1.0));
    put("nis_in_bounds", inside / static_cast<double>(counted));
  }
  if (std::isfinite(worst_p)) put("whiteness_p", worst_p);
  for (const auto& [k, v] : per_channel)
    metrics.emplace(k, v);
  if (!nees.nees.empty() && count_finite(nees.nees)) {
    put("nees_mean", mean_finite(nees.nees));
    put("nees_dof", nees.dof);
    put("nees_in_bounds", fraction_inside(nees.nees, nees.dof));
  }
}

}  // namespace kfw
