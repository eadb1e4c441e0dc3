#include "experiment/sweep.h"

#include <cmath>
#include <limits>

#include "core/suggest.h"
#include "experiment/parallel.h"

namespace kfw {

std::size_t SweepResult::stopped() const {
  std::size_t n = 0;
  for (const auto& e : errors)
    n += e.empty() ? 0 : 1;
  return n;
}

std::vector<double> SweepAxis::values() const {
  std::vector<double> v;
  for (int i = 0; i < n; ++i) {
    const double f = n == 1 ? 0.0 : static_cast<double>(i) / (n - 1);
    v.push_back(log ? std::pow(10.0, std::log10(lo) + f * (std::log10(hi) - std::log10(lo)))
                    : lo + f * (hi - lo));
  }
  return v;
}

std::vector<double> grid_point(const std::vector<std::vector<double>>& values, std::size_t index) {
  std::vector<double> row(values.size());
  for (std::size_t a = values.size(); a-- > 0;) {
    const auto na = values[a].size();
    row[a] = values[a][index % na];
    index /= na;
  }
  return row;
}

std::optional<std::size_t> grid_size(const std::vector<SweepAxis>& axes, std::size_t limit) {
  std::size_t points = 1;
  for (const auto& ax : axes) {
    const auto n = static_cast<std::size_t>(std::max(ax.n, 1));
    if (points > limit / n) return std::nullopt;
    points *= n;
  }
  return points;
}

std::size_t shard_size(std::size_t total, const Shard& shard) {
  const std::size_t first = shard.index - 1;
  if (shard.count == 0 || total <= first) return 0;
  return (total - first + shard.count - 1) / shard.count;
}

Expected<SweepAxis> parse_sweep_axis(const ParamTable& table, const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0) {
    return Error{"--param expects key=lo:hi:n[:log], got " + quote_token(text)};
  }
  SweepAxis a;
  a.key = text.substr(0, eq);
  const ParamSpec* spec = table.find(a.key);
  if (!spec) {
    std::vector<std::string> keys;
    for (const auto& s : table.specs())
      keys.push_back(s.key);
    return Error{"--param: " + unknown_message("parameter", a.key, keys)};
  }
  auto grid = parse_grid(std::string_view(text).substr(eq + 1), "--param " + a.key);
  if (!grid) return grid.err();
  a.lo = grid->lo;
  a.hi = grid->hi;
  a.n = static_cast<int>(grid->n);
  // Without :log or :lin, the parameter's own scale decides (log for variances).
  a.log = grid->spacing == Spacing::kLog ||
          (grid->spacing == Spacing::kDefault && spec->scale == Scale::kLog);
  for (double v : {a.lo, a.hi}) {
    if (auto st = table.check(a.key, spec->scale == Scale::kInteger ? std::round(v) : v); !st) {
      return Error{"--param: " + st.error()};
    }
  }
  if (a.log && (a.lo <= 0 || a.hi <= 0)) {
    return Error{"--param " + a.key + ": log spacing needs lo, hi > 0 (add :lin for linear)"};
  }
  return a;
}

Expected<SweepResult> sweep(const Scenario& s, const Dataset& d, const ParamValues& base,
                            const std::vector<SweepAxis>& axes, int threads,
                            const std::atomic<bool>* cancel, const Shard& shard,
                            const std::function<void(std::size_t)>& progress) {
  if (axes.empty()) return Error{"sweep: no --param given"};
  const auto total = grid_size(axes, std::numeric_limits<std::size_t>::max());
  if (!total) return Error{"sweep: the grid is too large"};
  std::vector<std::vector<double>> values;
  for (const auto& a : axes) {
    if (!s.params().find(a.key)) return Error{"sweep: unknown parameter '" + a.key + "'"};
    values.push_back(a.values());
  }
  SweepResult out;
  out.axes = axes;
  for (std::size_t i = shard.index - 1; i < *total; i += shard.count)
    out.indices.push_back(i);
  const std::size_t n = out.indices.size();
  out.points.resize(n);
  out.metrics.resize(n);
  out.errors.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    std::vector<double> row = grid_point(values, out.indices[k]);
    for (std::size_t a = 0; a < axes.size(); ++a) {
      if (s.params().find(axes[a].key)->scale == Scale::kInteger) row[a] = std::round(row[a]);
    }
    out.points[k] = std::move(row);
  }
  std::atomic<std::size_t> done{0};
  parallel_for(n, threads, [&](std::size_t k) {
    if (cancel && cancel->load()) return;
    ParamValues v = base;
    for (std::size_t a = 0; a < axes.size(); ++a)
      v[axes[a].key] = out.points[k][a];
    auto r = s.run(d, v);
    if (r) {
      out.metrics[k] = (*r)->metrics;
    } else {
      out.errors[k] = r.error();
    }
    const std::size_t finished = ++done;
    if (progress) progress(finished);
  });
  return out;
}

}  // namespace kfw
