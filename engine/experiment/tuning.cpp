#include "experiment/tuning.h"

#include <nlopt.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <sstream>

#include "core/suggest.h"
#include "experiment/parallel.h"

namespace kfw {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// What NLopt sees for a point that cannot be evaluated (a run that stopped, an undefined metric).
constexpr double kUnusable = 1e30;
// The scale check: an objective that changes by less than this fraction of its change under a
// shape change of the same size (one key moved alone) cannot tell the common scale of its group
// (a start-up transient with a fixed P0 is what is left; a scale-dependent objective such as the
// NLL changes about as much under either).
constexpr double kScaleChangeTol = 0.05;
// A result this close to a bound (in the search coordinate, 0…1) sits on it.
constexpr double kBoundTol = 1e-3;

double metric_or_nan(const Metrics& m, const std::string& key) {
  auto it = m.find(key);
  return it == m.end() ? kNaN : it->second;
}

// One evaluation: every log run at the same values.
struct Eval {
  double f = kInf;      // aggregate badness (inf: not usable)
  double value = kNaN;  // aggregated metric
  double nis = kNaN;    // NIS mean / dof, mean over the logs
  std::vector<Metrics> metrics;
  std::vector<double> values;  // the metric per log
};

class Tuner {
 public:
  Tuner(const Scenario& s, const std::vector<TuneLog>& logs, const std::vector<SearchParam>& params,
        const TuneObjective& obj, const TuneOptions& opt)
      : s_(s), logs_(logs), params_(params), obj_(obj), opt_(opt) {}

  bool stopped() const {
    return evals_.load() >= opt_.budget || (opt_.cancel && opt_.cancel->load());
  }
  int evaluations() const { return evals_.load(); }

  // Search coordinate u in [0, 1] <-> value (log10-mapped for log scales).
  double to_value(std::size_t i, double u) const {
    const auto& p = params_[i];
    u = std::clamp(u, 0.0, 1.0);
    double v = p.log ? std::pow(10.0, std::log10(p.lo) + u * (std::log10(p.hi) - std::log10(p.lo)))
                     : p.lo + u * (p.hi - p.lo);
    if (s_.params().find(p.key)->scale == Scale::kInteger) v = std::round(v);
    return std::clamp(v, p.lo, p.hi);
  }
  double to_u(std::size_t i, double v) const {
    const auto& p = params_[i];
    if (p.log && v <= 0) return 0.0;
    const double u =
        p.log ? (std::log10(v) - std::log10(p.lo)) / (std::log10(p.hi) - std::log10(p.lo))
              : (v - p.lo) / (p.hi - p.lo);
    return std::clamp(u, 0.0, 1.0);
  }
  ParamValues values_at(const ParamValues& base, const std::vector<double>& u) const {
    ParamValues v = base;
    for (std::size_t i = 0; i < params_.size(); ++i)
      v[params_[i].key] = to_value(i, u[i]);
    return v;
  }

  // Runs every log at `v` (in parallel) and aggregates. `penalised`: rmse+nis as one number.
  Eval evaluate(const ParamValues& v, bool penalised) {
    ++evals_;
    Eval e;
    const std::size_t n = logs_.size();
    e.metrics.resize(n);
    e.values.assign(n, kNaN);
    std::vector<char> ok(n, 0);
    parallel_for(n, opt_.threads, [&](std::size_t i) {
      ParamValues vi = v;
      for (const auto& [k, x] : logs_[i].fixed)
        vi[k] = x;
      auto r = s_.run(*logs_[i].data, vi);
      if (!r) return;
      e.metrics[i] = (*r)->metrics;
      ok[i] = 1;
    });
    double sum_b = 0.0, worst_b = -kInf, sum_v = 0.0, sum_nis = 0.0;
    bool usable = true;
    for (std::size_t i = 0; i < n; ++i) {
      if (!ok[i]) {
        usable = false;
        continue;
      }
      e.values[i] = metric_or_nan(e.metrics[i], obj_.spec.key);
      const double b = penalised ? obj_.badness(e.metrics[i]) : badness(obj_.spec, e.values[i]);
      if (!std::isfinite(b)) usable = false;
      sum_b += b;
      sum_v += e.values[i];
      sum_nis += metric_or_nan(e.metrics[i], "nis_mean");
      if (b > worst_b) {
        worst_b = b;
        if (opt_.aggregate == Aggregate::kWorst) e.value = e.values[i];
      }
    }
    if (usable) {
      e.f = opt_.aggregate == Aggregate::kWorst ? worst_b : sum_b / static_cast<double>(n);
      if (opt_.aggregate == Aggregate::kMean) e.value = sum_v / static_cast<double>(n);
    }
    e.nis = sum_nis / static_cast<double>(n);
    report(e.f);
    return e;
  }

  void report(double f) {
    double best;
    {
      std::lock_guard<std::mutex> lock(mu_);
      if (f < best_) best_ = f;
      best = best_;
    }
    if (opt_.progress) opt_.progress(evals_.load(), best);
  }

 private:
  const Scenario& s_;
  const std::vector<TuneLog>& logs_;
  const std::vector<SearchParam>& params_;
  const TuneObjective& obj_;
  const TuneOptions& opt_;
  std::atomic<int> evals_{0};
  std::mutex mu_;
  double best_ = kInf;
};

// One NLopt run over the free coordinates; the others stay at `u`.
struct Run {
  Tuner* tuner;
  ParamValues base;
  std::vector<double> u;          // every coordinate
  std::vector<std::size_t> free;  // the ones searched
  bool penalised = false;
  int budget = 0, used = 0;
  nlopt_opt opt = nullptr;
  double best_f = kInf;
  std::vector<double> best_u;
};

double run_objective(unsigned n, const double* x, double* /*grad*/, void* data) {
  auto* r = static_cast<Run*>(data);
  if (r->used >= r->budget || r->tuner->stopped()) {
    nlopt_force_stop(r->opt);
    return kUnusable;
  }
  std::vector<double> u = r->u;
  for (unsigned i = 0; i < n; ++i)
    u[r->free[i]] = x[i];
  ++r->used;
  const Eval e = r->tuner->evaluate(r->tuner->values_at(r->base, u), r->penalised);
  if (e.f < r->best_f) {
    r->best_f = e.f;
    r->best_u = u;
  }
  return std::isfinite(e.f) ? e.f : kUnusable;
}

// Minimises over `free` from `u` with one algorithm; returns the best point seen and its value.
void optimise(Run& r, nlopt_algorithm algo, double tol) {
  const auto n = static_cast<unsigned>(r.free.size());
  r.best_u = r.u;
  if (n == 0 || r.budget <= 0) return;
  r.opt = nlopt_create(algo, n);
  std::vector<double> lo(n, 0.0), hi(n, 1.0), x(n), step(n, 0.1);
  for (unsigned i = 0; i < n; ++i)
    x[i] = r.u[r.free[i]];
  nlopt_set_lower_bounds(r.opt, lo.data());
  nlopt_set_upper_bounds(r.opt, hi.data());
  nlopt_set_min_objective(r.opt, &run_objective, &r);
  nlopt_set_maxeval(r.opt, r.budget);
  nlopt_set_ftol_rel(r.opt, tol);
  nlopt_set_xtol_abs1(r.opt, 1e-7);
  nlopt_set_initial_step(r.opt, step.data());
  double f = 0.0;
  nlopt_optimize(r.opt, x.data(), &f);  // the best point is tracked in run_objective
  nlopt_destroy(r.opt);
  r.opt = nullptr;
}

nlopt_algorithm local_algorithm(TuneMethod m, std::size_t n) {
  // NLopt's BOBYQA needs two or more dimensions; Sbplx does one.
  if (m == TuneMethod::kSbplx || n < 2) return NLOPT_LN_SBPLX;
  return NLOPT_LN_BOBYQA;
}

}  // namespace

const char* tune_method_name(TuneMethod m) {
  switch (m) {
    case TuneMethod::kBobyqa:
      return "bobyqa";
    case TuneMethod::kSbplx:
      return "sbplx";
    case TuneMethod::kDirect:
      return "direct";
    case TuneMethod::kCrs:
      return "crs";
  }
  return "bobyqa";
}

std::vector<std::string> tune_method_names() {
  return {"bobyqa", "sbplx", "direct", "crs"};
}

Expected<TuneMethod> parse_tune_method(std::string_view name) {
  for (auto m : {TuneMethod::kBobyqa, TuneMethod::kSbplx, TuneMethod::kDirect, TuneMethod::kCrs}) {
    if (name == tune_method_name(m)) return m;
  }
  return Error{"--method: " + unknown_message("method", std::string(name), tune_method_names())};
}

Expected<Aggregate> parse_aggregate(std::string_view name) {
  if (name == "mean") return Aggregate::kMean;
  if (name == "worst") return Aggregate::kWorst;
  return Error{"--aggregate: " +
               unknown_message("aggregate", std::string(name), {"mean", "worst"})};
}

const char* aggregate_name(Aggregate a) {
  return a == Aggregate::kWorst ? "worst" : "mean";
}

double TuneObjective::badness(const Metrics& m) const {
  const double b = kfw::badness(spec, metric_or_nan(m, spec.key));
  if (!combined()) return b;
  const double l = std::log(metric_or_nan(m, "nis_mean"));
  if (with_log_nis) return b + std::abs(l);
  return b * (1.0 + l * l);
}

std::vector<std::string> objective_names(const Scenario& s, const RunResult* probe) {
  std::vector<std::string> names;
  for (const auto& c : combined_objectives())
    names.emplace_back(c.name);
  names.emplace_back("nis");
  for (const auto& k : metric_keys(s, probe)) {
    if (describe_metric(s, k, probe).direction != Direction::kNone) names.push_back(k);
  }
  return names;
}

Expected<TuneObjective> make_objective(const Scenario& s, const std::string& name,
                                       const RunResult* probe) {
  TuneObjective o;
  o.name = name;
  std::string key = name;
  if (name == kRmseNis) {
    key = "rmse";
    o.with_nis = true;
  } else if (name == kRmseAnis) {
    key = "rmse";
    o.with_log_nis = true;
  } else if (name == "nis") {
    key = "nis_mean";
  }
  const auto names = objective_names(s, probe);
  if (std::find(names.begin(), names.end(), name) == names.end()) {
    if (is_declared_metric(s, key) && !probe) {
      // A pattern key (nis_mean.<channel>) is only known once a run names its channels.
    } else {
      return Error{"--objective: " + unknown_message("objective", name, names)};
    }
  }
  o.spec = describe_metric(s, key, probe);
  if (o.spec.direction == Direction::kNone) {
    return Error{"--objective: '" + key + "' is informational: it has no better direction"};
  }
  return o;
}

Expected<TuneResult> tune(const Scenario& s, const std::vector<TuneLog>& logs,
                          const ParamValues& start, const std::vector<SearchParam>& params,
                          const TuneObjective& objective, const TuneOptions& options) {
  if (params.empty()) return Error{"tune: no parameters to search"};
  if (logs.empty()) return Error{"tune: no dataset"};
  const ParamTable& table = s.params();
  for (const auto& p : params) {
    const ParamSpec* spec = table.find(p.key);
    if (!spec) return Error{"tune: unknown parameter '" + p.key + "'"};
    if (spec->scale == Scale::kChoice || spec->scale == Scale::kToggle) {
      return Error{"tune: parameter '" + p.key + "' is not continuous"};
    }
    if (!(p.lo < p.hi) || (p.log && p.lo <= 0)) {
      return Error{"tune: bad bounds for '" + p.key + "' (need lo < hi" +
                   (p.log ? ", lo > 0 on a log scale)" : ")")};
    }
  }
  Tuner tuner(s, logs, params, objective, options);
  const std::size_t dim = params.size();
  std::vector<double> u(dim);
  for (std::size_t i = 0; i < dim; ++i)
    u[i] = tuner.to_u(i, param(start, params[i].key));

  TuneResult out;
  // Scale groups: the selected keys sharing a scale_group (two or more).
  std::map<std::string, std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < dim; ++i) {
    if (!params[i].scale_group.empty()) groups[params[i].scale_group].push_back(i);
  }
  // The scale check of one group at `at`: the objective there, with every member ×up and ÷down
  // (up to 10, inside the bounds), and with the first member alone moved as far (a shape
  // change, for comparison). Undetermined: scaling moves the objective by less than a twentieth
  // of what that shape change does (what is left is a start-up transient with a fixed P0).
  auto check = [&](const std::vector<std::size_t>& members, const std::vector<double>& at,
                   ScaleReport& rep) {
    const ParamValues v0 = tuner.values_at(start, at);
    double up = 10.0, down = 10.0;
    for (auto i : members) {
      const double v = v0.at(params[i].key);
      if (v > 0) {
        up = std::min(up, params[i].hi / v);
        down = std::min(down, v / params[i].lo);
      }
    }
    std::vector<ParamValues> pts = {v0, v0, v0, v0};
    for (auto i : members) {
      pts[1][params[i].key] *= up;
      pts[2][params[i].key] /= down;
    }
    const auto& lead = params[members.front()].key;
    pts[3][lead] = up >= down ? v0.at(lead) * up : v0.at(lead) / down;
    std::vector<Eval> ev(4);
    // rmse+anis judges the scale itself (its NIS term); rmse+nis leaves it to consistency.
    const bool whole = objective.with_log_nis;
    parallel_for(4, options.threads, [&](std::size_t k) { ev[k] = tuner.evaluate(pts[k], whole); });
    auto rel = [&](std::size_t k) {
      if (!std::isfinite(ev[0].f) || !std::isfinite(ev[k].f)) return 0.0;
      return std::abs(ev[k].f - ev[0].f) / std::max(std::abs(ev[0].f), 1e-300);
    };
    rep.change = std::max(rel(1), rel(2));
    rep.shape_change = rel(3);
    rep.determined = !(std::isfinite(ev[0].f) && std::max(up, down) > 1.5 &&
                       rep.change <= std::max(kScaleChangeTol * rep.shape_change, 1e-12));
  };
  std::vector<std::vector<std::size_t>> resolve;  // groups whose scale consistency sets
  std::vector<std::vector<std::size_t>> checked;  // the others, checked again at the result
  for (const auto& [name, members] : groups) {
    if (members.size() < 2) continue;
    ScaleReport rep;
    rep.group = name;
    for (auto i : members)
      rep.keys.push_back(params[i].key);
    check(members, u, rep);
    if (!rep.determined || objective.with_nis) {
      resolve.push_back(members);
    } else {
      checked.push_back(members);
    }
    out.scales.push_back(rep);
  }
  // The scale of a group by consistency: a secant search in ln c for ln(NIS mean / dof) = 0.
  auto set_scale = [&](const std::vector<std::size_t>& members) {
    ScaleReport* rep = nullptr;
    for (auto& r : out.scales) {
      if (r.keys.front() == params[members.front()].key) rep = &r;
    }
    const ParamValues v0 = tuner.values_at(start, u);
    double xmin = -kInf, xmax = kInf;
    for (auto i : members) {
      const double v = v0.at(params[i].key);
      xmin = std::max(xmin, std::log(params[i].lo / v));
      xmax = std::min(xmax, std::log(params[i].hi / v));
    }
    auto nis_at = [&](double x) {
      ParamValues v = v0;
      for (auto i : members)
        v[params[i].key] *= std::exp(x);
      return std::log(tuner.evaluate(v, false).nis);
    };
    double x0 = 0.0, g0 = nis_at(0.0);
    if (!std::isfinite(g0)) {
      rep->note = "nis_mean is undefined: the scale cannot be set by consistency";
      return;
    }
    double x1 = std::clamp(g0, xmin, xmax), g1 = nis_at(x1);
    for (int it = 0; it < 8 && std::isfinite(g1) && std::abs(g1) > 1e-4 && x1 != x0; ++it) {
      const double x2 = std::clamp(x1 - g1 * (x1 - x0) / (g1 - g0), xmin, xmax);
      x0 = x1;
      g0 = g1;
      x1 = x2;
      if (x1 == x0) break;
      g1 = nis_at(x1);
    }
    if (!std::isfinite(g1)) x1 = 0.0;
    for (auto i : members)
      u[i] = tuner.to_u(i, v0.at(params[i].key) * std::exp(x1));
    rep->by_consistency = true;
    rep->factor *= std::exp(x1);
    if (x1 <= xmin || x1 >= xmax) rep->note = "the consistent scale lies beyond a bound";
  };
  // With groups to set by consistency, hold each group's first key (the anchor) and search the
  // rest (the shape), then scale the group; twice, so the shape sees the final scale.
  std::vector<char> anchored(dim, 0);
  for (const auto& g : resolve)
    anchored[g.front()] = 1;
  const bool penalised = (objective.with_nis && resolve.empty()) || objective.with_log_nis;
  const int rounds = resolve.empty() ? 1 : 2;
  const int reserve_per_round = 10 * static_cast<int>(resolve.size());
  std::vector<std::string> methods;
  for (int round = 0; round < rounds && !tuner.stopped(); ++round) {
    std::vector<std::size_t> free;
    for (std::size_t i = 0; i < dim; ++i) {
      if (!anchored[i]) free.push_back(i);
    }
    const int left = options.budget - tuner.evaluations() - reserve_per_round * (rounds - round) -
                     14 * static_cast<int>(checked.size()) - 1;
    const int budget = round + 1 < rounds ? left * 2 / 3 : left;
    const ParamValues base = start;
    if (options.method == TuneMethod::kDirect || options.method == TuneMethod::kCrs) {
      // A global search over the box, then a local polish from its best point.
      Run g{&tuner, base, u, free, penalised, budget * 7 / 10};
      nlopt_srand(12345);  // CRS draws random points: the same run every time
      optimise(g, options.method == TuneMethod::kDirect ? NLOPT_GN_DIRECT_L : NLOPT_GN_CRS2_LM,
               options.tol);
      Run l{&tuner, base, g.best_u, free, penalised, budget - g.used};
      optimise(l, local_algorithm(TuneMethod::kBobyqa, free.size()), options.tol);
      u = l.best_f <= g.best_f ? l.best_u : g.best_u;
      methods.push_back(std::string(tune_method_name(options.method)) + "+" +
                        (free.size() < 2 ? "sbplx" : "bobyqa"));
    } else {
      // Two local starts at once (the start values and the middle of the box), on every core.
      std::vector<Run> runs(2);
      for (std::size_t k = 0; k < 2; ++k) {
        std::vector<double> u0 = u;
        if (k == 1 && round == 0) {
          for (auto i : free)
            u0[i] = 0.5;
        }
        runs[k] = Run{&tuner, base, u0, free, penalised, round == 0 ? budget / 2 : budget / 2};
      }
      const std::size_t starts = round == 0 ? 2 : 1;
      if (starts == 1) runs[0].budget = budget;
      parallel_for(starts, options.threads, [&](std::size_t k) {
        optimise(runs[k], local_algorithm(options.method, free.size()), options.tol);
      });
      std::size_t best = 0;
      for (std::size_t k = 1; k < starts; ++k) {
        if (runs[k].best_f < runs[best].best_f) best = k;
      }
      u = runs[best].best_u;
      methods.push_back(free.size() < 2 && options.method == TuneMethod::kBobyqa
                            ? "sbplx"
                            : tune_method_name(options.method));
    }
    for (const auto& members : resolve)
      set_scale(members);
  }
  // A scale the objective told at the start may be one it cannot tell at the optimum.
  for (const auto& members : checked) {
    if (tuner.stopped() && options.cancel && options.cancel->load()) break;
    ScaleReport* rep = nullptr;
    for (auto& r : out.scales) {
      if (r.keys.front() == params[members.front()].key) rep = &r;
    }
    check(members, u, *rep);
    if (!rep->determined) set_scale(members);
  }
  out.method = methods.empty() ? tune_method_name(options.method) : methods.back();
  out.cancelled = options.cancel && options.cancel->load();
  // The result, run once more for its per-log report.
  out.best = tuner.values_at(start, u);
  const Eval e = tuner.evaluate(out.best, penalised);
  out.evaluations = tuner.evaluations();
  if (!std::isfinite(e.f)) {
    return failure("tune: no evaluation produced a finite objective (is '" + objective.spec.key +
                   "' defined on every dataset?)");
  }
  out.objective = e.f;
  out.value = e.value;
  out.metrics = e.metrics.front();
  for (std::size_t i = 0; i < logs.size(); ++i)
    out.logs.push_back({logs[i].name, e.metrics[i], e.values[i]});
  for (auto& r : out.scales)
    r.nis_mean = e.nis;
  for (std::size_t i = 0; i < dim; ++i) {
    if (u[i] < kBoundTol || u[i] > 1.0 - kBoundTol) out.at_bound.push_back(params[i].key);
  }
  if (objective.combined() && !out.cancelled) {
    const Eval e0 = tuner.evaluate(start, penalised);
    if (std::isfinite(e0.value) && std::isfinite(e.value)) {
      out.trade_off =
          TradeOff{objective.spec.key, objective.spec.direction, e0.value, e.value, e0.nis, e.nis};
    }
  }
  return out;
}

double TradeOff::cost() const {
  if (!(std::abs(start_value) > 0.0)) return 0.0;
  const double change = (best_value - start_value) / std::abs(start_value);
  return direction == Direction::kHigher ? -change : change;
}

bool TradeOff::costly() const {
  return cost() > 0.10;
}

std::string TradeOff::message() const {
  std::ostringstream os;
  os.precision(4);
  os << "meeting the consistency target costs " << std::lround(100.0 * cost()) << " % of " << metric
     << " against the start: start " << metric << " " << start_value << " (NIS mean/dof "
     << start_nis << "), tuned " << metric << " " << best_value << " (NIS mean/dof " << best_nis
     << "); if " << metric << " matters more, keep the start's values or tune for " << metric
     << " alone";
  return os.str();
}

Expected<SearchParam> search_param(const Preset& preset, const std::string& key) {
  const ParamTable& table = preset.instance->params();
  std::vector<std::string> tunable;
  for (const auto& spec : table.specs()) {
    auto m = preset.meta.find(spec.key);
    if (m != preset.meta.end() && m->second.tunable) tunable.push_back(spec.key);
  }
  const ParamSpec* spec = table.find(key);
  if (!spec) return Error{unknown_message("parameter", key, tunable)};
  auto m = preset.meta.find(key);
  if (m == preset.meta.end() || !m->second.tunable ||
      (spec->scale != Scale::kLinear && spec->scale != Scale::kLog &&
       spec->scale != Scale::kInteger)) {
    std::string list;
    for (const auto& k : tunable)
      list += (list.empty() ? "" : ", ") + k;
    return Error{"'" + key + "' is not tunable in this preset (tunable: " +
                 (list.empty() ? "none" : list) + ")"};
  }
  SearchParam p{key, spec->min, spec->max, spec->scale == Scale::kLog, m->second.scale_group};
  if (auto r = preset.ranges.find(key); r != preset.ranges.end()) {
    p.lo = r->second.first;
    p.hi = r->second.second;
  }
  return p;
}

std::vector<SearchParam> default_search(const Preset& preset) {
  std::vector<SearchParam> out;
  for (const auto& spec : preset.instance->params().specs()) {
    if (auto p = search_param(preset, spec.key)) out.push_back(*p);
  }
  return out;
}

std::string no_tunable_message(const Preset& preset) {
  const std::string file = preset.path.empty() ? std::string("this preset") : preset.path;
  std::string msg = file + " marks no parameter tunable";
  if (!preset.model.is_null()) {
    // A model file that says nothing is tuned over its Q and R: this one opted out, or has none.
    bool says = false;
    if (preset.parameters_block.is_object()) {
      for (const auto& e : preset.parameters_block)
        says = says || (e.is_object() && e.contains("tunable"));
    }
    msg += says ? " (its entries say \"tunable\": false)"
                : " and its Q and R use no continuous parameter";
  }
  std::vector<std::string> keys;
  for (const auto& spec : preset.instance->params().specs()) {
    const bool filter_setting = spec.key.rfind("ukf.", 0) == 0;
    if ((spec.scale == Scale::kLinear || spec.scale == Scale::kLog) && !is_sim_key(spec.key) &&
        !filter_setting)
      keys.push_back(spec.key);
  }
  msg +=
      ": add \"tunable\": true to the entries of the parameters the tuner may change (the "
      "noise levels in Q and R)";
  if (!keys.empty()) {
    msg += "; its continuous parameters: ";
    for (std::size_t i = 0; i < keys.size() && i < 8; ++i)
      msg += (i ? ", " : "") + keys[i];
    if (keys.size() > 8) msg += ", …";
  }
  return msg;
}

DefaultObjective default_objective(const Preset& preset, const RunResult& probe,
                                   const std::vector<SearchParam>& params) {
  if (!preset.default_objective.empty()) {
    return {preset.default_objective, "declared by the preset (default_objective)"};
  }
  const bool truth = probe.metrics.count("rmse") > 0;
  const bool nis = probe.metrics.count("nis_mean") > 0;
  std::map<std::string, int> groups;
  bool grouped = false;
  for (const auto& p : params) {
    if (!p.scale_group.empty()) grouped |= ++groups[p.scale_group] >= 2;
  }
  if (truth && nis && grouped) {
    return {kRmseNis, "truth and a scale group: RMSE, the group's scale set by NIS consistency"};
  }
  if (truth && nis) {
    return {kRmseAnis, "truth and no scale group: RMSE + |ln(NIS mean / dof)|"};
  }
  if (truth) return {"rmse", "truth and no innovations: RMSE"};
  return {"nll", "no truth: the mean innovation NLL over all channels"};
}

}  // namespace kfw
