#include "experiment/monte_carlo.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>
#include <tuple>

#include "core/statistics.h"
#include "core/suggest.h"
#include "experiment/parallel.h"

namespace kfw {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The per-step series a part sums, taken from a run (the run itself need not be kept).
struct SeedSeries {
  std::vector<double> t;
  std::string state, label, unit;       // the primary state with truth (empty: none)
  std::vector<double> error, variance;  // x̂ − x and P of that state
  NeesSeries nees;
  std::vector<InnovationChannel> channels;
};

struct SeedOutcome {
  SeedRun run;
  SeedSeries series;
};

// One seed: simulate, filter. Errors of the input kind (exit 2) are returned; a failure during
// the work (exit 1) is the seed's stop reason.
Expected<SeedOutcome> run_seed(const Scenario& s, ParamValues v, long long seed, bool keep,
                               const std::atomic<bool>* cancel) {
  SeedOutcome outcome;
  SeedRun& out = outcome.run;
  out.seed = seed;
  v["sim.seed"] = static_cast<double>(seed);
  auto d = s.simulate(v);
  if (!d) {
    if (d.exit_code() != kExitFailed) return d.err();
    out.error = d.error();
    return outcome;
  }
  RunControl control;
  control.cancel = cancel;
  auto r = s.run(*d, v, control);
  if (!r) {
    if (r.exit_code() != kExitFailed) return r.err();
    out.error = r.error();
    return outcome;
  }
  out.metrics = (*r)->metrics;
  out.undefined = (*r)->undefined;
  out.warnings = (*r)->warnings;
  if (keep) out.result = *r;
  outcome.series.t = (*r)->t;
  const std::string primary = s.primary_state();
  for (const StateSeries& st : (*r)->states()) {
    if (!st.truth || !st.estimate || (!primary.empty() && st.key != primary)) continue;
    SeedSeries& ss = outcome.series;
    ss.state = st.key;
    ss.label = st.label;
    ss.unit = st.unit;
    const std::size_t n = std::min(st.estimate->size(), st.truth->size());
    ss.error.resize(n);
    for (std::size_t k = 0; k < n; ++k)
      ss.error[k] = (*st.estimate)[k] - (*st.truth)[k];
    if (st.variance) ss.variance = *st.variance;
    break;
  }
  outcome.series.nees = (*r)->nees_series();
  outcome.series.channels = (*r)->channels();
  for (auto& c : outcome.series.channels) {
    c.normalized.clear();
    c.log_det_s.clear();
    c.components.clear();
  }
  return outcome;
}

StepSums* find_sums(std::vector<StepSums>& v, const std::string& name) {
  for (auto& s : v) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

// The per-step series of a completed run added to the part's sums.
void accumulate(MonteCarloPart& part, const SeedSeries& r) {
  if (r.t.size() > part.t.size()) part.t = r.t;
  const NeesSeries& nees = r.nees;
  if (!nees.nees.empty() && count_finite(nees.nees) > 0) {
    if (!part.nees) part.nees = StepSums{"nees", "NEES", nees.dof, {}, {}, {}};
    part.nees->add(nees.nees);
  }
  if (!r.state.empty()) {
    if (!part.error) {
      part.error = StepSums{r.state, r.label, 1.0, {}, {}, {}};
      part.variance = StepSums{r.state, r.label, 1.0, {}, {}, {}};
      part.error_unit = r.unit;
    }
    if (part.error->name == r.state) {
      part.error->add(r.error);
      part.variance->add(r.variance);
    }
  }
  for (const auto& ch : r.channels) {
    if (ch.nis.empty()) continue;
    StepSums* s = find_sums(part.nis, ch.name);
    if (!s) {
      part.nis.push_back(StepSums{ch.name, ch.display(), ch.dof, {}, {}, {}});
      s = &part.nis.back();
    }
    s->add(ch.nis);
  }
}

ConsistencySummary consistency(const StepSums& s, double alpha) {
  ConsistencySummary c;
  c.name = s.name;
  c.label = s.label;
  c.dof = s.dof;
  const std::size_t steps = s.sum.size();
  c.average.assign(steps, kNaN);
  c.lo_k.assign(steps, kNaN);
  c.hi_k.assign(steps, kNaN);
  std::map<std::size_t, std::pair<double, double>> bounds;  // by the number of runs
  auto bounds_for = [&](std::size_t n) {
    auto it = bounds.find(n);
    if (it == bounds.end()) {
      const double nd = static_cast<double>(n);
      it = bounds
               .emplace(n, std::pair{chi2_quantile(0.5 * alpha, nd * s.dof) / nd,
                                     chi2_quantile(1.0 - 0.5 * alpha, nd * s.dof) / nd})
               .first;
    }
    return it->second;
  };
  double total = 0.0;
  std::size_t defined = 0, inside = 0;
  for (std::size_t k = 0; k < steps; ++k) {
    const std::size_t n = s.count[k];
    c.runs = std::max(c.runs, n);
    if (n == 0) continue;
    const double avg = s.sum[k] / static_cast<double>(n);
    const auto [lo, hi] = bounds_for(n);
    c.average[k] = avg;
    c.lo_k[k] = lo;
    c.hi_k[k] = hi;
    total += avg;
    ++defined;
    if (avg >= lo && avg <= hi) ++inside;
  }
  if (c.runs > 0) std::tie(c.lo, c.hi) = bounds_for(c.runs);
  c.time_average = defined ? total / static_cast<double>(defined) : kNaN;
  c.inside = defined ? static_cast<double>(inside) / static_cast<double>(defined) : kNaN;
  return c;
}

}  // namespace

void StepSums::add(const std::vector<double>& v) {
  if (v.size() > sum.size()) {
    sum.resize(v.size(), 0.0);
    sum_sq.resize(v.size(), 0.0);
    count.resize(v.size(), 0);
  }
  for (std::size_t k = 0; k < v.size(); ++k) {
    if (!std::isfinite(v[k])) continue;
    sum[k] += v[k];
    sum_sq[k] += v[k] * v[k];
    ++count[k];
  }
}

Status StepSums::merge(const StepSums& o) {
  if (o.name != name || o.dof != dof) {
    const auto text = [](const std::string& n, double d) {
      std::ostringstream os;
      os << quote_token(n) << " (dof " << d << ")";
      return os.str();
    };
    return Error{std::string(o.name != name ? "name" : "dof") + ": " + text(o.name, o.dof) +
                 " differs from the parts before it: " + text(name, dof) +
                 " (parts of different runs)"};
  }
  if (o.sum.size() > sum.size()) {
    sum.resize(o.sum.size(), 0.0);
    sum_sq.resize(o.sum.size(), 0.0);
    count.resize(o.sum.size(), 0);
  }
  for (std::size_t k = 0; k < o.sum.size(); ++k) {
    sum[k] += o.sum[k];
    sum_sq[k] += o.sum_sq[k];
    count[k] += o.count[k];
  }
  return Ok{};
}

Expected<MonteCarloPart> run_monte_carlo(const Scenario& s, const ParamValues& base,
                                         const std::vector<long long>& seeds, const Shard& shard,
                                         const MonteCarloOptions& options) {
  const ParamTable& table = s.params();
  if (!table.find("sim.seed")) {
    return Error{"--seeds: scenario '" + s.name() + "' has no simulator seed (sim.seed)"};
  }
  MonteCarloPart part;
  part.scenario = s.name();
  part.seeds = seeds;
  std::sort(part.seeds.begin(), part.seeds.end());
  part.seeds.erase(std::unique(part.seeds.begin(), part.seeds.end()), part.seeds.end());
  part.shard = shard;
  part.values = base;
  part.values.erase("sim.seed");  // the one value that differs between the runs
  std::vector<long long> mine;
  for (std::size_t i = 0; i < part.seeds.size(); ++i) {
    if (!in_shard(i, shard)) continue;
    const long long seed = part.seeds[i];
    if (auto st = table.check("sim.seed", static_cast<double>(seed)); !st) {
      return Error{"--seeds: " + st.error()};
    }
    mine.push_back(seed);
  }
  if (auto st = table.check(base); !st) return st.err();

  // Each seed's outcome is folded into the part as soon as every seed before it is folded: the
  // sums are in seed order whatever the threads did, the fold runs beside the runs instead of
  // after them, and a seed's per-step series is freed at once (memory O(threads), not O(seeds)).
  std::vector<std::optional<Expected<SeedOutcome>>> results(mine.size());
  std::vector<std::atomic<bool>> ready(mine.size());
  std::atomic<std::size_t> next{0}, done{0};
  std::atomic<bool> failed{false};
  std::mutex fold_mutex;
  std::size_t folded = 0;  // guarded by fold_mutex
  std::optional<Error> first_error;
  auto fold = [&] {  // fold_mutex held
    for (; folded < mine.size() && ready[folded].load(std::memory_order_acquire); ++folded) {
      auto& r = *results[folded];
      if (!r) {
        first_error = r.err();
        failed = true;
        return;
      }
      SeedOutcome& o = *r;
      if (!o.run.stopped()) accumulate(part, o.series);
      part.runs.push_back(std::move(o.run));
      results[folded].reset();
    }
  };
  auto worker = [&] {
    for (;;) {
      const std::size_t i = next.fetch_add(1);
      if (i >= mine.size() || failed) return;
      if (options.cancel && options.cancel->load()) return;
      results[i] = run_seed(s, base, mine[i], options.keep_results, options.cancel);
      ready[i].store(true, std::memory_order_release);
      if (std::unique_lock lock(fold_mutex, std::try_to_lock); lock) fold();
      const std::size_t n = done.fetch_add(1) + 1;
      if (options.progress) options.progress(n, mine.size());
    }
  };
  const auto threads =
      std::min<std::size_t>(static_cast<std::size_t>(worker_count(options.threads)),
                            std::max<std::size_t>(mine.size(), 1));
  {
    std::vector<std::jthread> pool;
    for (std::size_t k = 1; k < threads; ++k)
      pool.emplace_back(worker);
    worker();
  }
  if (!first_error) fold();  // what finished while another thread was folding
  if (options.cancel && options.cancel->load()) return failure("cancelled");
  if (first_error) return *first_error;
  if (folded < mine.size()) return failure("cancelled");
  return part;
}

MonteCarloSummary summarize_monte_carlo(const MonteCarloPart& part, double alpha) {
  MonteCarloSummary s;
  s.scenario = part.scenario;
  s.t = part.t;
  std::map<std::string, std::vector<double>> values;
  for (const auto& r : part.runs) {
    if (r.stopped()) {
      SeedRun stop;
      stop.seed = r.seed;
      stop.error = r.error;
      s.stopped.push_back(std::move(stop));
      continue;
    }
    ++s.completed;
    for (const auto& [k, v] : r.metrics)
      values[k].push_back(v);
    for (const auto& [k, why] : r.undefined)
      s.undefined.emplace(k, why);
  }
  s.seeds = part.runs.size();
  for (const auto& [k, v] : values) {
    s.undefined.erase(k);
    MetricSummary m;
    m.n = v.size();
    double sum = 0.0;
    for (double x : v)
      sum += x;
    m.mean = sum / static_cast<double>(m.n);
    double ss = 0.0;
    for (double x : v)
      ss += (x - m.mean) * (x - m.mean);
    m.sd = m.n > 1 ? std::sqrt(ss / static_cast<double>(m.n - 1)) : 0.0;
    m.min = *std::min_element(v.begin(), v.end());
    m.max = *std::max_element(v.begin(), v.end());
    s.metrics[k] = m;
  }
  if (part.nees) s.nees = consistency(*part.nees, alpha);
  if (part.error && part.variance) {
    ErrorBand b;
    b.state = part.error->name;
    b.label = part.error->label;
    b.unit = part.error_unit;
    const StepSums& e = *part.error;
    const std::size_t steps = e.sum.size();
    b.mean.assign(steps, kNaN);
    b.sd.assign(steps, kNaN);
    b.filter_sigma.assign(steps, kNaN);
    for (std::size_t k = 0; k < steps; ++k) {
      const auto n = static_cast<double>(e.count[k]);
      if (e.count[k] == 0) continue;
      b.mean[k] = e.sum[k] / n;
      if (e.count[k] > 1) {
        const double var = (e.sum_sq[k] - n * b.mean[k] * b.mean[k]) / (n - 1.0);
        b.sd[k] = std::sqrt(std::max(0.0, var));
      }
      const StepSums& p = *part.variance;
      if (k < p.count.size() && p.count[k] > 0) {
        b.filter_sigma[k] = std::sqrt(std::max(0.0, p.sum[k] / static_cast<double>(p.count[k])));
      }
    }
    s.error = std::move(b);
  }
  for (const auto& n : part.nis)
    s.nis.push_back(consistency(n, alpha));
  return s;
}

Expected<Metrics> mean_metrics_over_seeds(const Scenario& s, const ParamValues& values,
                                          const std::vector<long long>& seeds,
                                          const MonteCarloOptions& options) {
  auto part = run_monte_carlo(s, values, seeds, {}, options);
  if (!part) return part.err();
  const MonteCarloSummary sum = summarize_monte_carlo(*part);
  if (sum.completed == 0 && !sum.stopped.empty()) {
    return failure("seed " + std::to_string(sum.stopped.front().seed) + ": " +
                   sum.stopped.front().error);
  }
  Metrics m;
  for (const auto& [k, v] : sum.metrics)
    m[k] = v.mean;
  return m;
}

Expected<SweepResult> sweep_over_seeds(const Scenario& s, const ParamValues& base,
                                       const std::vector<SweepAxis>& axes,
                                       const std::vector<long long>& seeds,
                                       const MonteCarloOptions& options) {
  SweepResult r;
  r.axes = axes;
  std::vector<std::vector<double>> values;
  std::size_t points = 1;
  for (const auto& ax : axes) {
    values.push_back(ax.values());
    points *= values.back().size();
  }
  for (std::size_t i = 0; i < points; ++i) {
    // Row-major: the last axis fastest.
    std::vector<double> point(axes.size());
    ParamValues v = base;
    std::size_t rest = i;
    for (std::size_t k = axes.size(); k-- > 0;) {
      point[k] = values[k][rest % values[k].size()];
      rest /= values[k].size();
      v[axes[k].key] = point[k];
    }
    auto m = mean_metrics_over_seeds(s, v, seeds, options);
    if (!m && m.exit_code() != kExitFailed) return m.err();
    if (options.cancel && options.cancel->load()) return failure("cancelled");
    r.points.push_back(std::move(point));
    r.metrics.push_back(m ? *m : Metrics{});
    r.errors.push_back(m ? std::string() : m.error());
  }
  return r;
}

}  // namespace kfw
