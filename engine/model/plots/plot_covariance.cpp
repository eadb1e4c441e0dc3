// The covariance plot block: the sample covariance of several derived series (errors, say)
// beside a declared design matrix — seed 004's simulated error covariance against the design
// values — and the evaluation, once per run, of every block's expressions of parameters
// (trajectory points, design matrices).
#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "model/expression.h"
#include "model/model_reader.h"
#include "model/model_result.h"
#include "model/model_spec.h"
#include "model/plots/model_plots.h"

namespace kfw::model {

using nlohmann::json;

namespace {

constexpr KindMask kDesign = kParamSymbol | kDtSymbol;

// "exclude": {"SERIES": "CHANNEL", ...}: the channel (with an outlier_column) whose marked
// samples leave an instant out.
Status parse_exclude(const detail::Reader& p, const json& j, const std::string& key,
                     const ModelSpec& m, PlotBlockSpec& out) {
  out.exclude.assign(out.series.size(), std::string());
  auto it = j.find("exclude");
  if (it == j.end()) return Ok{};
  if (!out.instants)
    return p.error(key + ".exclude", "applies to instants: set \"instants\": true");
  if (!it->is_object()) return p.error(key + ".exclude", "expected {\"SERIES\": \"CHANNEL\"}");
  std::vector<std::string> series, channels;
  for (const auto& s : out.series)
    series.push_back(s.key);
  for (const auto& c : m.channels) {
    if (!c.outlier_column.empty()) channels.push_back(c.name);
  }
  for (auto e = it->begin(); e != it->end(); ++e) {
    const std::string at = key + ".exclude." + truncate_token(e.key());
    std::size_t i = 0;
    while (i < series.size() && series[i] != e.key() && series[i] != "derived." + e.key())
      ++i;
    if (i == series.size()) return p.error(at, unknown_message("series", e.key(), series));
    if (!e->is_string()) return p.error(at, "expected a channel name");
    const std::string c = e->get<std::string>();
    if (std::find(channels.begin(), channels.end(), c) == channels.end()) {
      return p.error(at, unknown_message("channel with an outlier_column", c, channels));
    }
    out.exclude[i] = c;
  }
  return Ok{};
}

}  // namespace

Status parse_covariance_block(const detail::Reader& p, const json& j, const std::string& key,
                              const ModelSpec& m, const ParamTable&, PlotBlockSpec& out) {
  auto it = j.find("series");
  if (it == j.end()) return p.error(key, "missing key 'series'");
  std::vector<std::string> known;
  for (const auto& d : m.derived) {
    if (d.series()) known.push_back("derived." + d.name);
  }
  auto names = detail::name_list(p, *it, key + ".series");
  if (!names) return names.err();
  for (std::size_t i = 0; i < names->size(); ++i) {
    const std::string at = it->is_array() ? detail::idx(key + ".series", i) : key + ".series";
    auto line = detail::plot_line(p, (*names)[i], at, m, known, "derived series");
    if (!line) return line.err();
    out.series.push_back(*line);
  }
  const int n = static_cast<int>(out.series.size());
  if (!j.contains("design")) return p.error(key, "missing key 'design'");
  auto design = p.matrix(j["design"], key + ".design", n, n, kDesign, "parameters and dt", true);
  if (!design) return design.err();
  if (auto st = p.symmetric(*design); !st) return st;
  for (const auto& e : design->e)
    out.design.push_back(e.text);
  if (auto at = j.find("instants"); at != j.end()) {
    if (!at->is_boolean()) return p.error(key + ".instants", "expected true or false");
    out.instants = at->get<bool>();
  }
  return parse_exclude(p, j, key, m, out);
}

Status add_plot_points(const ModelSpec& m, const ParamValues& values, double dt, ModelResult& r) {
  std::vector<double> vars(m.symbols.names.size(), 0.0);
  for (std::size_t i = 0; i < m.param_slots.size(); ++i)
    vars[static_cast<std::size_t>(m.param_slots[i])] = param(values, m.param_keys[i]);
  vars[static_cast<std::size_t>(m.dt_slot)] = dt;
  std::size_t total = 0;
  for (const auto& b : m.plots)
    total += 2 * b.points.size() + b.design.size();
  if (total == 0) return Ok{};
  std::vector<double> out(total, 0.0);
  ExprGroup group;
  std::size_t k = 0;
  for (const auto& b : m.plots) {
    for (const auto& pt : b.points) {
      group.add(pt.x, &out[k++]);
      group.add(pt.y, &out[k++]);
    }
    for (const auto& e : b.design)
      group.add(e, &out[k++]);
  }
  if (auto st = group.bind(m.symbols, vars.data()); !st) return st;
  group.eval();
  k = 0;
  for (const auto& b : m.plots) {
    for (const auto& pt : b.points) {
      const double px = out[k++], py = out[k++];
      if (std::isfinite(px) && std::isfinite(py)) r.plot_points.push_back({b.id, pt.name, px, py});
    }
    if (b.design.empty()) continue;
    const auto first = out.begin() + static_cast<std::ptrdiff_t>(k);
    r.plot_matrices.emplace_back(
        b.id, std::vector<double>(first, first + static_cast<std::ptrdiff_t>(b.design.size())));
    k += b.design.size();
  }
  return Ok{};
}

namespace {

// The sample covariance (mean removed, count − 1) of vectors of n.
void sample_covariance(const std::vector<std::vector<double>>& rows, CovarianceData& c) {
  c.count = rows.size();
  if (c.count < 2) return;
  std::vector<double>& mean = c.mean;
  mean.assign(c.n, 0.0);
  for (const auto& v : rows) {
    for (std::size_t i = 0; i < c.n; ++i)
      mean[i] += v[i] / static_cast<double>(c.count);
  }
  std::fill(c.sample.begin(), c.sample.end(), 0.0);
  for (const auto& v : rows) {
    for (std::size_t i = 0; i < c.n; ++i) {
      for (std::size_t j = 0; j < c.n; ++j)
        c.sample[i * c.n + j] += (v[i] - mean[i]) * (v[j] - mean[j]);
    }
  }
  for (auto& x : c.sample)
    x /= static_cast<double>(c.count - 1);
}

// Instants: the rows where every series has a new finite value since the last instant, each
// series its latest value; one holding a sample its exclude channel marks is left out.
CovarianceData instant_covariance(const PlotBlockSpec& b, const ModelResult& r,
                                  const std::vector<const std::vector<double>*>& cols,
                                  CovarianceData c) {
  std::vector<const std::vector<double>*> marks(c.n, nullptr);
  for (std::size_t i = 0; i < c.n && i < b.exclude.size(); ++i) {
    for (const auto& ch : r.chans) {
      if (ch.name == b.exclude[i] && !ch.outlier.empty()) marks[i] = &ch.outlier;
    }
  }
  std::vector<std::vector<double>> rows;
  std::vector<double> latest(c.n, 0.0);
  std::vector<bool> fresh(c.n, false), marked(c.n, false);
  for (std::size_t k = 0; k < r.steps(); ++k) {
    bool all = true;
    for (std::size_t i = 0; i < c.n; ++i) {
      const double v = (*cols[i])[k];
      if (std::isfinite(v)) {
        latest[i] = v;
        fresh[i] = true;
        const double o = marks[i] ? (*marks[i])[k] : 0.0;
        marked[i] = std::isfinite(o) && o != 0.0;
      }
      all = all && fresh[i];
    }
    if (!all) continue;
    if (std::find(marked.begin(), marked.end(), true) != marked.end()) {
      ++c.excluded;
    } else {
      rows.push_back(latest);
    }
    std::fill(fresh.begin(), fresh.end(), false);
  }
  sample_covariance(rows, c);
  return c;
}

}  // namespace

CovarianceData covariance_block_data(const PlotBlockSpec& b, const ModelResult& r) {
  CovarianceData c;
  c.n = b.series.size();
  std::vector<const std::vector<double>*> cols;
  for (const auto& line : b.series) {
    for (std::size_t i = 0; i < r.derived_names.size(); ++i) {
      if ("derived." + r.derived_names[i] == line.key) cols.push_back(&r.derived[i]);
    }
  }
  c.sample.assign(c.n * c.n, std::numeric_limits<double>::quiet_NaN());
  c.mean.assign(c.n, std::numeric_limits<double>::quiet_NaN());
  for (const auto& [id, m] : r.plot_matrices) {
    if (id == b.id) c.design = m;
  }
  if (cols.size() != c.n) return c;
  if (b.instants) return instant_covariance(b, r, cols, std::move(c));
  // Two passes: the means over the steps where every series is finite, then the products.
  const auto all_finite = [&](std::size_t k) {
    for (const auto* col : cols) {
      if (!std::isfinite((*col)[k])) return false;
    }
    return true;
  };
  std::vector<double> mean(c.n, 0.0);
  for (std::size_t k = 0; k < r.steps(); ++k) {
    if (!all_finite(k)) continue;
    ++c.count;
    for (std::size_t i = 0; i < c.n; ++i)
      mean[i] += (*cols[i])[k];
  }
  if (c.count < 2) return c;
  for (auto& x : mean)
    x /= static_cast<double>(c.count);
  c.mean = mean;
  std::fill(c.sample.begin(), c.sample.end(), 0.0);
  for (std::size_t k = 0; k < r.steps(); ++k) {
    if (!all_finite(k)) continue;
    for (std::size_t i = 0; i < c.n; ++i) {
      for (std::size_t j = 0; j < c.n; ++j)
        c.sample[i * c.n + j] += ((*cols[i])[k] - mean[i]) * ((*cols[j])[k] - mean[j]);
    }
  }
  for (auto& x : c.sample)
    x /= static_cast<double>(c.count - 1);
  return c;
}

}  // namespace kfw::model
