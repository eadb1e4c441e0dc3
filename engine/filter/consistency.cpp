#include "filter/consistency.h"

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
  std::vector<double> d(n);
  double c0 = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    d[i] = x[i] - mean;
    c0 += d[i] * d[i];
  }
  if (!(c0 > 0.0)) return r;
  r[0] = 1.0;
  for (std::size_t lag = 1; lag <= max_lag && lag < n; ++lag) {
    // Four partial sums: independent chains the CPU overlaps (one chain waits on each add).
    double c[4] = {0.0, 0.0, 0.0, 0.0};
    std::size_t i = lag;
    for (; i + 4 <= n; i += 4) {
      for (std::size_t j = 0; j < 4; ++j)
        c[j] += d[i + j] * d[i + j - lag];
    }
    for (; i < n; ++i)
      c[0] += d[i] * d[i - lag];
    r[lag] = ((c[0] + c[1]) + (c[2] + c[3])) / c0;
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

void add_consistency_metrics(const std::vector<InnovationChannel>& channels, const NeesSeries& nees,
                             Metrics& metrics, UndefinedMetrics& undefined) {
  constexpr double kLog2Pi = 1.8378770664093453;
  double nis_sum = 0.0, inside = 0.0, worst_p = std::numeric_limits<double>::quiet_NaN();
  double nll_sum = 0.0;
  bool nll_known = true;
  std::size_t n = 0;
  auto put = [&](const std::string& key, double v) { metrics.emplace(key, v); };
  for (const auto& c : channels) {
    const std::string key = metric_identifier(c.name);
    const std::size_t cn = count_finite(c.nis);
    if (cn == 0) {
      undefined.emplace("nis_mean." + key, "the channel never updated");
      continue;
    }
    // NIS normalised by its dof so that channels of different size average together.
    double raw = 0.0;
    for (std::size_t k = 0; k < c.nis.size(); ++k) {
      const double v = c.nis[k];
      if (!std::isfinite(v)) continue;
      raw += v;
      nis_sum += v / c.dof;
      if (c.nll.size() == c.nis.size()) {
        if (std::isfinite(c.nll[k])) {
          nll_sum += c.nll[k];
        } else {
          nll_known = false;
        }
      } else if (c.log_det_s.size() == c.nis.size() && std::isfinite(c.log_det_s[k])) {
        nll_sum += 0.5 * (c.dof * kLog2Pi + c.log_det_s[k] + v);
      } else {
        nll_known = false;
      }
    }
    put("nis_mean." + key, raw / static_cast<double>(cn));
    n += cn;
    inside += fraction_inside(c.nis, c.dof) * static_cast<double>(cn);
    if (const auto known = metrics.find("whiteness_p." + key); known != metrics.end()) {
      // Computed by the scenario already (it kept the Ljung–Box result for its plots).
      if (!(known->second >= worst_p)) worst_p = known->second;
    } else if (!c.normalized.empty()) {
      const double p = ljung_box(c.normalized, 20).p_value;
      if (std::isfinite(p)) {
        if (!(p >= worst_p)) worst_p = p;
        put("whiteness_p." + key, p);
      } else {
        undefined.emplace("whiteness_p." + key, "too few updates for 20 lags");
      }
    } else if (!c.components.empty()) {
      // Each component on its own (a white vector sequence has white components); the channel
      // is as white as its worst component.
      double channel_p = std::numeric_limits<double>::quiet_NaN();
      for (const auto& comp : c.components) {
        const std::string ckey = "whiteness_p." + key + "." + metric_identifier(comp.name);
        const double p = ljung_box(comp.normalized, 20).p_value;
        if (std::isfinite(p)) {
          if (!(p >= channel_p)) channel_p = p;
          put(ckey, p);
        } else {
          undefined.emplace(ckey, "too few updates for 20 lags");
        }
      }
      if (std::isfinite(channel_p)) {
        if (!(channel_p >= worst_p)) worst_p = channel_p;
        put("whiteness_p." + key, channel_p);
      } else {
        undefined.emplace("whiteness_p." + key, "too few updates for 20 lags");
      }
    } else {
      undefined.emplace("whiteness_p." + key, "the channel is not scalar");
    }
  }
  if (n) {
    put("nis_mean", nis_sum / static_cast<double>(n));
    put("nis_in_bounds", inside / static_cast<double>(n));
    if (nll_known) {
      put("nll", nll_sum / static_cast<double>(n));
    } else {
      undefined.emplace("nll", "the channels do not report their innovation covariance");
    }
  } else {
    for (const char* k : {"nis_mean", "nis_in_bounds", "nll"})
      undefined.emplace(k, "no measurement update in this run");
  }
  if (std::isfinite(worst_p)) {
    put("whiteness_p", worst_p);
  } else {
    undefined.emplace("whiteness_p", "no channel with enough updates for 20 lags");
  }
  if (!nees.nees.empty() && count_finite(nees.nees)) {
    put("nees_mean", mean_finite(nees.nees) / nees.dof);
    put("nees_in_bounds", fraction_inside(nees.nees, nees.dof));
  } else {
    // No finite NEES: no truth, or (NeesSeries::truth) a covariance singular wherever truth is
    // known — a noise-free sensor, R = 0, pins the state; not a missing column.
    const std::string why = !nees.truth ? "no truth column"
                            : !nees.error_finite
                                ? "the estimation error overflows wherever truth is known"
                                : "the covariance of the states with truth is singular "
                                  "wherever truth is known (a noise-free sensor, R = 0?)";
    undefined.emplace("nees_mean", why);
    undefined.emplace("nees_in_bounds", why);
  }
}

}  // namespace kfw
