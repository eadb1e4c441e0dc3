#include "model/model_stat_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "core/limits.h"
#include "core/suggest.h"
#include "model/imm/imm_spec.h"
#include "model/model_eval.h"
#include "model/model_reader.h"
#include "model/model_result.h"

namespace kfw::model {

namespace {

using nlohmann::json;

const std::vector<std::pair<std::string, Stat>>& stat_names() {
  static const std::vector<std::pair<std::string, Stat>> names = {
      {"rms", Stat::kRms}, {"max_abs", Stat::kMaxAbs}, {"final", Stat::kFinal},
      {"min", Stat::kMin}, {"max", Stat::kMax},        {"mean", Stat::kMean}};
  return names;
}

// The grid axis a series names ("imm.PARAM" or "imm.PARAM.WHAT"), its index and WHAT; -1 when it
// names none.
int grid_axis_of(const ModelSpec& m, const std::string& of, std::string& what) {
  if (!m.modes || of.rfind("imm.", 0) != 0) return -1;
  for (std::size_t a = 0; a < m.modes->grid.size(); ++a) {
    const std::string head = "imm." + m.modes->grid[a].param;
    if (of == head) {
      what.clear();
      return static_cast<int>(a);
    }
    if (of.rfind(head + ".", 0) == 0) {
      what = of.substr(head.size() + 1);
      if (what == "centre" || what == "low" || what == "high" || what == "span") {
        return static_cast<int>(a);
      }
    }
  }
  return -1;
}

std::vector<std::string> series_names(const ModelSpec& m) {
  std::vector<std::string> out;
  for (const auto& d : m.derived) {
    if (d.series()) out.push_back("derived." + d.name);
  }
  if (!m.modes) return out;
  for (const auto& g : m.modes->grid) {
    for (const char* w : {"", ".centre", ".low", ".high", ".span"})
      out.push_back("imm." + g.param + w);
  }
  return out;
}

Expected<StatMetricSpec> parse_one(const detail::Reader& p, const std::string& name, const json& j,
                                   const ModelSpec& m) {
  const std::string key = "model.metrics." + name;
  StatMetricSpec s;
  s.name = s.label = name;
  if (!j.is_object()) return p.error(key, "expected {\"of\", \"stat\", \"from\", ...}");
  if (auto st =
          p.only_keys(j, key, {"of", "stat", "from", "label", "unit", "description", "direction"});
      !st) {
    return st.err();
  }
  auto of = p.string(j, "of", key, true);
  if (!of) return of.err();
  s.of = *of;
  const auto known = series_names(m);
  if (std::find(known.begin(), known.end(), s.of) == known.end()) {
    return p.error(key + ".of", unknown_message("series", s.of, known));
  }
  auto stat = p.string(j, "stat", key, true);
  if (!stat) return stat.err();
  const auto& names = stat_names();
  const auto it =
      std::find_if(names.begin(), names.end(), [&](const auto& n) { return n.first == *stat; });
  if (it == names.end()) {
    std::vector<std::string> list;
    for (const auto& n : names)
      list.push_back(n.first);
    return p.error(key + ".stat", unknown_message("statistic", *stat, list));
  }
  s.stat = it->second;
  if (j.contains("from")) {
    auto e = p.expr(j["from"], key + ".from", detail::kParamsOnly, detail::kParamsOnlyWhat);
    if (!e) return e.err();
    s.from = *e;
  }
  for (auto [k, out] : {std::pair{"label", &s.label}, std::pair{"unit", &s.unit},
                        std::pair{"description", &s.description}}) {
    auto v = p.string(j, k, key, false, *out);
    if (!v) return v.err();
    *out = *v;
  }
  auto dir = p.string(j, "direction", key, false, "none");
  if (!dir) return dir.err();
  if (*dir == "lower") {
    s.direction = Direction::kLower;
  } else if (*dir == "higher") {
    s.direction = Direction::kHigher;
  } else if (*dir != "none") {
    return p.error(key + ".direction", "expected lower, higher or none, got '" + *dir + "'");
  }
  return s;
}

double statistic(Stat stat, const std::vector<double>& t, const std::vector<double>& v,
                 double from) {
  double acc = 0.0, last = std::numeric_limits<double>::quiet_NaN();
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  std::size_t n = 0;
  for (std::size_t k = 0; k < v.size() && k < t.size(); ++k) {
    if (t[k] < from || !std::isfinite(v[k])) continue;
    ++n;
    last = v[k];
    lo = std::min(lo, v[k]);
    hi = std::max(hi, v[k]);
    acc += stat == Stat::kRms ? v[k] * v[k] : stat == Stat::kMean ? v[k] : 0.0;
  }
  if (n == 0) return std::numeric_limits<double>::quiet_NaN();
  switch (stat) {
    case Stat::kRms:
      return std::sqrt(acc / static_cast<double>(n));
    case Stat::kMean:
      return acc / static_cast<double>(n);
    case Stat::kMaxAbs:
      return std::max(std::fabs(lo), std::fabs(hi));
    case Stat::kFinal:
      return last;
    case Stat::kMin:
      return lo;
    case Stat::kMax:
      return hi;
  }
  return last;
}

// A grid axis's series: the estimate, the centre, the grid's ends, or how far the grid reaches
// around the estimate, max(|low − R̂|, |high − R̂|).
std::vector<double> grid_series(const ImmSeries::Axis& axis, const std::string& what) {
  if (what.empty()) return axis.estimate;
  if (what == "centre") return axis.centre;
  double lo = axis.values.front(), hi = lo;
  for (double v : axis.values) {
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  const double c0 = 0.5 * (lo + hi);  // values are at the initial centre
  std::vector<double> out(axis.centre.size());
  for (std::size_t k = 0; k < out.size(); ++k) {
    const double low = lo + axis.centre[k] - c0, high = hi + axis.centre[k] - c0;
    out[k] = what == "low" ? low
             : what == "high"
                 ? high
                 : std::max(std::fabs(low - axis.estimate[k]), std::fabs(high - axis.estimate[k]));
  }
  return out;
}

}  // namespace

Status parse_stat_metrics(const detail::Reader& p, const json& block, ModelSpec& m) {
  if (!block.is_object()) {
    return p.error("model.metrics", "expected {\"NAME\": {\"of\": ..., \"stat\": ...}, ...}");
  }
  for (auto it = block.begin(); it != block.end(); ++it) {
    const std::string& name = it.key();
    const bool ok = !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.';
    });
    if (!ok || name.size() > limits::kMaxNameChars) {
      return p.error("model.metrics." + name.substr(0, 40),
                     "a metric's name: letters, digits, _ and ., at most " +
                         std::to_string(limits::kMaxNameChars) + " characters");
    }
    bool taken = name.rfind("derived.", 0) == 0 || name.rfind("imm.", 0) == 0 ||
                 name.rfind("K.", 0) == 0 || name.rfind("rmse", 0) == 0;
    for (const auto& shared : shared_metric_specs()) {
      const std::string stem = shared.key.substr(0, shared.key.find(".<"));
      taken = taken || name == stem || name.rfind(stem + ".", 0) == 0;
    }
    if (taken) {
      return p.error("model.metrics." + name,
                     "names a metric kfw reports itself (rmse…, nis…, nees…, derived.…, imm.…)");
    }
    auto s = parse_one(p, name, it.value(), m);
    if (!s) return s.err();
    m.stat_metrics.push_back(std::move(*s));
  }
  return Ok{};
}

std::vector<MetricSpec> stat_metric_specs(const ModelSpec& spec) {
  std::vector<MetricSpec> out;
  for (const auto& s : spec.stat_metrics) {
    std::string about = s.description;
    if (about.empty()) {
      about = std::string(s.stat == Stat::kRms ? "RMS" : "statistic") + " of " + s.of;
    }
    out.push_back({s.name, s.label, s.unit, about, MetricGroup::kScenario, s.direction});
  }
  return out;
}

namespace {

// A time of parameters only (a metric's `from`, model.metrics_from); −∞ where none is given.
double time_at(const ModelSpec& spec, const ParamValues& values, const Expr& e) {
  double from = -std::numeric_limits<double>::infinity();
  if (e.text.empty()) return from;
  if (e.dep == Dep::kConst) return e.value;  // a number ("10"): no parser on the run's path
  std::vector<double> vars(spec.symbols.names.size(), 0.0);
  for (std::size_t i = 0; i < spec.param_slots.size(); ++i)
    vars[static_cast<std::size_t>(spec.param_slots[i])] = param(values, spec.param_keys[i]);
  ExprGroup g;
  g.add(e.text, &from);
  if (g.bind(spec.symbols, vars.data()).ok()) g.eval();
  return from;
}

template <class V>
void drop_front(V& v, std::size_t n) {
  v.erase(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(std::min(n, v.size())));
}

}  // namespace

std::size_t metrics_from_row(const ModelSpec& spec, const ParamValues& values,
                             const std::vector<double>& t, double& at) {
  at = time_at(spec, values, spec.metrics_from);
  if (!(at > -std::numeric_limits<double>::infinity())) return 0;
  return static_cast<std::size_t>(std::lower_bound(t.begin(), t.end(), at) - t.begin());
}

std::vector<InnovationChannel> channels_from(std::vector<InnovationChannel> channels,
                                             std::size_t from) {
  for (auto& c : channels) {
    drop_front(c.nis, from);
    drop_front(c.normalized, from);
    drop_front(c.log_det_s, from);
    drop_front(c.nll, from);
    for (auto& comp : c.components)
      drop_front(comp.normalized, from);
  }
  return channels;
}

NeesSeries nees_from(NeesSeries nees, std::size_t from) {
  drop_front(nees.nees, from);
  return nees;
}

void add_stat_metrics(const ModelSpec& spec, const ParamValues& values, ModelResult& r) {
  for (const auto& s : spec.stat_metrics) {
    const double from = time_at(spec, values, s.from);
    std::vector<double> series;
    std::string what;
    if (const int a = grid_axis_of(spec, s.of, what); a >= 0 && r.imm) {
      series = grid_series(r.imm->axes[static_cast<std::size_t>(a)], what);
    } else {
      const std::string name = s.of.substr(std::string("derived.").size());
      for (std::size_t q = 0; q < r.derived_names.size(); ++q) {
        if (r.derived_names[q] == name) series = r.derived[q];
      }
    }
    const double v = statistic(s.stat, r.t, series, from);
    if (std::isfinite(v)) {
      r.metrics[s.name] = v;
    } else {
      const bool reached = !r.t.empty() && r.t.back() >= from;
      r.undefined[s.name] = reached
                                ? "no finite value of " + s.of + " from t = " + number(from) + " s"
                                : "the run ends before t = " + number(from) + " s";
    }
  }
}

}  // namespace kfw::model
