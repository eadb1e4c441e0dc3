#include "experiment/gain_curve.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/suggest.h"

namespace kfw {

namespace {

bool curve_parameter(const ParamSpec& p) {
  const bool continuous = p.scale == Scale::kLinear || p.scale == Scale::kLog;
  return continuous && p.min < p.max && p.key.rfind("sim.", 0) != 0 && p.key.rfind("ukf.", 0) != 0;
}

}  // namespace

std::vector<std::string> gain_curve_parameters(const Scenario& s) {
  std::vector<std::string> keys;
  for (const auto& p : s.params().specs()) {
    if (curve_parameter(p)) keys.push_back(p.key);
  }
  return keys;
}

std::string default_gain_curve_parameter(const Scenario& s, const ParamValues& values,
                                         const Dataset* data) {
  auto here = s.gain(values, data);
  if (!here) return {};
  std::vector<std::string> keys = gain_curve_parameters(s);
  std::stable_partition(keys.begin(), keys.end(), [&](const std::string& k) {
    return s.params().find(k)->scale == Scale::kLog;
  });
  for (const auto& k : keys) {
    const ParamSpec* p = s.params().find(k);
    ParamValues v = values;
    const double now = values.count(k) ? values.at(k) : p->def;
    // The far end of the range from the current value.
    v[k] = (now - p->min) > (p->max - now) ? p->min : p->max;
    auto there = s.gain(v, data);
    if (!there) return k;  // the steady state itself depends on it
    for (const auto& [key, g] : *here) {
      if (key.rfind("K.", 0) != 0) continue;
      const auto it = there->find(key);
      if (it == there->end() || std::abs(it->second - g) > 1e-9 * std::max(1.0, std::abs(g)))
        return k;
    }
  }
  return {};
}

namespace {

// What the curve draws: the entries whose key starts with `prefix`, or exactly `entries`.
struct Selection {
  std::string prefix;
  const std::vector<std::string>* entries = nullptr;
  bool picks(const std::string& k) const {
    if (!entries) return k.rfind(prefix, 0) == 0;
    return std::find(entries->begin(), entries->end(), k) != entries->end();
  }
};

// x_key resolved against what gain() reports, or the message naming what it does report.
Expected<std::string> x_quantity(const Metrics& here, const std::string& x_key,
                                 const Selection& sel) {
  std::string x = x_key;  // a model file's derived quantity by its own name: "beta"
  if (!x.empty() && !here.count(x) && here.count("derived." + x)) x = "derived." + x;
  if (x.empty() || here.count(x)) return x;
  std::vector<std::string> others;
  for (const auto& [k, v] : here) {
    if (!sel.picks(k)) others.push_back(k);
  }
  std::string msg = unknown_message("quantity of the steady state", x_key, others);
  if (msg.find("did you mean") == std::string::npos) {
    std::string derived;  // what a model file declares for this axis
    for (const auto& k : others) {
      if (k.rfind("derived.", 0) == 0) derived += (derived.empty() ? "" : ", ") + k.substr(8);
    }
    msg += derived.empty() ? " (this model declares no derived scalar)"
                           : " (derived scalars: " + derived + ")";
  }
  return Error{"gain curve: --x: " + msg};
}

Expected<GainCurve> curve(const Scenario& s, const ParamValues& values, const std::string& key,
                          std::size_t points, const Dataset* data, const Selection& sel,
                          const std::string& x_key, double lo, double hi) {
  const ParamSpec* spec = s.params().find(key);
  if (!spec || !curve_parameter(*spec)) {
    return Error{"gain curve: '" + key + "' is not a continuous filter parameter"};
  }
  auto here = s.gain(values, data);
  if (!here) return here.err();
  GainCurve c;
  c.key = key;
  c.log = spec->scale == Scale::kLog;
  c.steady = *here;
  c.at_x = values.count(key) ? values.at(key) : spec->def;
  bool declared = true;
  const auto add = [&](const std::string& k, double v) {
    c.entries.push_back(k);
    c.units.push_back(describe_metric(s, k).unit);
    c.at.push_back(v);
    declared = declared && is_declared_metric(s, k);
  };
  if (sel.entries) {
    for (const auto& k : *sel.entries) {
      const auto it = here->find(k);
      if (it == here->end()) return Error{"gain curve: the steady state reports no '" + k + "'"};
      add(k, it->second);
    }
  } else {
    for (const auto& [k, v] : *here) {
      if (sel.picks(k)) add(k, v);
    }
  }
  if (!declared) c.units.clear();
  if (c.entries.empty()) {
    return Error{"gain curve: the scenario reports no '" + sel.prefix + "' gains"};
  }
  auto x = x_quantity(*here, x_key, sel);
  if (!x) return x.err();
  c.x_key = *x;
  if (!(lo < hi)) {
    lo = spec->min;
    hi = spec->max;
  }
  points = std::max<std::size_t>(points, 2);
  c.x.resize(points);
  for (std::size_t i = 0; i < points; ++i) {
    const double u = static_cast<double>(i) / static_cast<double>(points - 1);
    c.x[i] = c.log ? lo * std::pow(hi / lo, u) : lo + u * (hi - lo);
  }
  c.values.assign(c.entries.size(),
                  std::vector<double>(points, std::numeric_limits<double>::quiet_NaN()));
  if (!c.x_key.empty()) c.x_metric.assign(points, std::numeric_limits<double>::quiet_NaN());
  ParamValues v = values;
  for (std::size_t i = 0; i < points; ++i) {
    v[key] = c.x[i];
    auto g = s.gain(v, data);
    if (!g) continue;  // no steady state here: a gap in the curve
    if (!c.x_key.empty() && g->count(c.x_key)) c.x_metric[i] = g->at(c.x_key);
    for (std::size_t e = 0; e < c.entries.size(); ++e) {
      if (auto it = g->find(c.entries[e]); it != g->end() && std::isfinite(it->second))
        c.values[e][i] = it->second;
    }
  }
  return c;
}

}  // namespace

Expected<GainCurve> gain_curve(const Scenario& s, const ParamValues& values, const std::string& key,
                               std::size_t points, const Dataset* data, const std::string& prefix,
                               const std::string& x_key) {
  return curve(s, values, key, points, data, Selection{prefix, nullptr}, x_key, 0.0, 0.0);
}

Expected<GainCurve> gain_curve_of(const Scenario& s, const ParamValues& values,
                                  const std::string& key, const std::vector<std::string>& entries,
                                  const std::string& x_key, std::size_t points, const Dataset* data,
                                  double lo, double hi) {
  return curve(s, values, key, points, data, Selection{"", &entries}, x_key, lo, hi);
}

}  // namespace kfw
