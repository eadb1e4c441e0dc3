#include "core/tuning.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <random>
#include <thread>

#include "core/grammar.h"
#include "core/suggest.h"

namespace kfw {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

double metric_or_nan(const Metrics& m, const std::string& key) {
  auto it = m.find(key);
  return it == m.end() ? std::numeric_limits<double>::quiet_NaN() : it->second;
}
}  // namespace

Expected<Objective> objective_by_name(const std::string& name) {
  if (name == "nis") {
    return Objective([](const Metrics& m) {
      const double l = std::log(metric_or_nan(m, "nis_mean"));  // NIS / dof: target 1
      return l * l;
    });
  }
  if (name.empty()) return Error{"--objective: empty name (rmse, nll, nis or a metric)"};
  return Objective([name](const Metrics& m) { return metric_or_nan(m, name); });
}

Expected<TuneResult> tune(const Scenario& s, const Dataset& d, const ParamValues& start,
                          const std::vector<SearchParam>& params, const Objective& objective,
                          const TuneOptions& options) {
  if (params.empty()) return Error{"tune: no parameters to search"};
  const ParamTable& table = s.params();
  for (const auto& p : params) {
    const ParamSpec* spec = table.find(p.key);
    if (!spec) return Error{"tune: unknown parameter '" + p.key + "'"};
    if (spec->scale == Scale::kChoice || spec->scale == Scale::kToggle) {
      return Error{"tune: parameter '" + p.key + "' is not continuous"};
    }
    if (!(p.lo < p.hi) || (p.log && p.lo <= 0)) {
      return Error{"tune: bad range for '" + p.key + "'"};
    }
  }
  const std::size_t dim = params.size();
  // Search coordinates u in [0, 1] per parameter (log10-mapped for log scales).
  auto to_value = [&](std::size_t i, double u) {
    const auto& p = params[i];
    u = std::clamp(u, 0.0, 1.0);
    double v = p.log ? std::pow(10.0, std::log10(p.lo) + u * (std::log10(p.hi) - std::log10(p.lo)))
                     : p.lo + u * (p.hi - p.lo);
    if (table.find(p.key)->scale == Scale::kInteger) v = std::round(v);
    return v;
  };
  auto to_u = [&](std::size_t i, double v) {
    const auto& p = params[i];
    const double u =
        p.log ? (std::log10(v) - std::log10(p.lo)) / (std::log10(p.hi) - std::log10(p.lo))
              : (v - p.lo) / (p.hi - p.lo);
    return std::clamp(u, 0.0, 1.0);
  };
  TuneResult best;
  best.objective = kInf;
  int evals = 0;
  auto f = [&](const std::vector<double>& u) {
    ParamValues v = start;
    for (std::size_t i = 0; i < dim; ++i)
      v[params[i].key] = to_value(i, u[i]);
    ++evals;
    auto r = s.run(d, v);
    double y = kInf;
    if (r) {
      y = objective((*r)->metrics);
      if (!std::isfinite(y)) y = kInf;
      if (y < best.objective) {
        best.objective = y;
        best.best = v;
        best.metrics = (*r)->metrics;
      }
    }
    if (options.progress) options.progress(evals, best.objective);
    return y;
  };
  auto stop = [&] {
    return evals >= options.max_evaluations || (options.cancel && options.cancel->load());
  };

  std::vector<double> x0(dim);
  for (std::size_t i = 0; i < dim; ++i)
    x0[i] = to_u(i, param(start, params[i].key));
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  for (int restart = 0; restart <= options.restarts && !stop(); ++restart) {
    // Restart from the best so far with a fresh simplex (the first from the start values); the
    // last restart starts from a random point to escape a poor basin.
    std::vector<double> base = x0;
    if (restart > 0 && std::isfinite(best.objective)) {
      for (std::size_t i = 0; i < dim; ++i)
        base[i] = to_u(i, best.best.at(params[i].key));
    }
    if (restart == options.restarts && restart > 0) {
      for (double& b : base)
        b = uni(rng);
    }
    const double step = restart == 0 ? 0.15 : 0.08;
    std::vector<std::vector<double>> simplex(dim + 1, base);
    for (std::size_t i = 0; i < dim; ++i) {
      simplex[i + 1][i] = base[i] + (base[i] + step <= 1.0 ? step : -step);
    }
    std::vector<double> fx(dim + 1);
    for (std::size_t i = 0; i <= dim && !stop(); ++i)
      fx[i] = f(simplex[i]);
    while (!stop()) {
      std::vector<std::size_t> order(dim + 1);
      for (std::size_t i = 0; i <= dim; ++i)
        order[i] = i;
      std::sort(order.begin(), order.end(), [&](auto a, auto b) { return fx[a] < fx[b]; });
      const std::size_t lo = order.front(), hi = order.back(), second = order[dim - 1];
      double spread = 0.0;
      for (std::size_t i = 0; i <= dim; ++i) {
        for (std::size_t j = 0; j < dim; ++j) {
          spread = std::max(spread, std::abs(simplex[i][j] - simplex[lo][j]));
        }
      }
      if (spread < 1e-4) break;
      std::vector<double> c(dim, 0.0);
      for (std::size_t i = 0; i <= dim; ++i) {
        if (i == hi) continue;
        for (std::size_t j = 0; j < dim; ++j)
          c[j] += simplex[i][j] / static_cast<double>(dim);
      }
      auto along = [&](double t) {
        std::vector<double> p(dim);
        for (std::size_t j = 0; j < dim; ++j)
          p[j] = std::clamp(c[j] + t * (simplex[hi][j] - c[j]), 0.0, 1.0);
        return p;
      };
      const auto xr = along(-1.0);
      const double fr = f(xr);
      if (fr < fx[lo]) {
        const auto xe = along(-2.0);
        const double fe = stop() ? kInf : f(xe);
        if (fe < fr) {
          simplex[hi] = xe;
          fx[hi] = fe;
        } else {
          simplex[hi] = xr;
          fx[hi] = fr;
        }
      } else if (fr < fx[second]) {
        simplex[hi] = xr;
        fx[hi] = fr;
      } else {
        const auto xc = fr < fx[hi] ? along(-0.5) : along(0.5);
        const double fc = stop() ? kInf : f(xc);
        if (fc < std::min(fr, fx[hi])) {
          simplex[hi] = xc;
          fx[hi] = fc;
        } else {
          for (std::size_t i = 0; i <= dim && !stop(); ++i) {
            if (i == lo) continue;
            for (std::size_t j = 0; j < dim; ++j)
              simplex[i][j] = 0.5 * (simplex[i][j] + simplex[lo][j]);
            fx[i] = f(simplex[i]);
          }
        }
      }
    }
  }
  if (!std::isfinite(best.objective)) {
    return Error{"tune: no evaluation produced a finite objective (is the metric available?)"};
  }
  best.evaluations = evals;
  return best;
}

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
                            const std::atomic<bool>* cancel) {
  if (axes.empty()) return Error{"sweep: no --param given"};
  SweepResult out;
  out.axes = axes;
  std::vector<std::vector<double>> grid = {{}};
  for (const auto& a : axes) {
    std::vector<std::vector<double>> next;
    for (const auto& row : grid) {
      for (double v : a.values()) {
        auto r = row;
        r.push_back(s.params().find(a.key)->scale == Scale::kInteger ? std::round(v) : v);
        next.push_back(r);
      }
    }
    grid = std::move(next);
  }
  out.points = grid;
  out.metrics.resize(grid.size());
  out.errors.resize(grid.size());
  std::atomic<std::size_t> next{0};
  auto worker = [&] {
    for (std::size_t i = next++; i < grid.size(); i = next++) {
      if (cancel && cancel->load()) return;
      ParamValues v = base;
      for (std::size_t a = 0; a < axes.size(); ++a)
        v[axes[a].key] = grid[i][a];
      auto r = s.run(d, v);
      if (r) {
        out.metrics[i] = (*r)->metrics;
      } else {
        out.errors[i] = r.error();
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < std::max(1, threads); ++t)
    pool.emplace_back(worker);
  worker();
  for (auto& t : pool)
    t.join();
  return out;
}

}  // namespace kfw
