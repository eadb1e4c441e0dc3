#include "model/model_filter.h"

#include <cmath>
#include <sstream>

#include "model/model_filter_detail.h"
#include "model/model_steady.h"
#include "model/world/model_world_noise.h"

namespace kfw::model {

std::size_t ModelResult::cov_index(std::size_t i, std::size_t j) const {
  if (i > j) std::swap(i, j);
  const std::size_t n = x.size();
  return i * (2 * n - i + 1) / 2 + (j - i);
}

std::vector<TableColumn> ModelResult::table_view() const {
  std::vector<TableColumn> d;
  const std::size_t rows = t.size();
  auto put = [&](std::string name, const std::vector<double>& v) {
    if (v.size() >= rows) {
      d.push_back(TableColumn{std::move(name), v.data(), {}, {}});
    } else {  // a shorter series reads as missing past its end
      d.push_back(TableColumn{std::move(name),
                              nullptr,
                              [&v](std::size_t k) { return k < v.size() ? v[k] : kNoSample; },
                              {}});
    }
  };
  put("t", t);
  const std::size_t n = x.size();
  for (std::size_t i = 0; i < n; ++i)
    put("x." + state_keys[i], x[i]);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i; j < n; ++j) {
      put(i == j ? "P." + state_keys[i] : "P." + state_keys[i] + "." + state_keys[j],
          P[cov_index(i, j)]);
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!truth[i].empty()) put("truth." + state_keys[i], truth[i]);
  }
  for (std::size_t r = 0; r < role_names.size(); ++r)
    put(role_names[r], z[r]);
  for (std::size_t q = 0; q < derived.size(); ++q)
    put("derived." + derived_names[q], derived[q]);
  for (const auto& c : chans) {
    for (std::size_t j = 0; j < c.roles.size(); ++j) {
      put("y." + c.roles[j], c.y[j]);
      put("S." + c.roles[j], c.S[j]);
    }
    put("nis." + c.name, c.nis);
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = 0; j < c.roles.size(); ++j)
        put("K." + state_keys[i] + "." + c.roles[j], c.K[i * c.roles.size() + j]);
    }
  }
  if (nees_dof > 0) put("nees", nees);
  for (const auto& [name, v] : loop_columns)
    put(name, v);
  if (imm) {
    for (std::size_t j = 0; j < imm->modes(); ++j) {
      const ImmSeries* series = &*imm;
      d.push_back(TableColumn{"mu." + imm->names[j],
                              nullptr,
                              [series, j](std::size_t k) { return series->mu_at(k, j); },
                              {}});
    }
    put("imm.map", imm->map);
    for (const auto& a : imm->axes) {
      put("imm." + a.param, a.estimate);
      put("imm." + a.param + ".centre", a.centre);
    }
  }
  return d;
}

Dataset ModelResult::table() const {
  Dataset d;
  d.source = "model run (" + filter + ")";
  for (const auto& c : table_view()) {
    d.names.push_back(c.name);
    auto& v = d.columns.emplace_back(t.size());
    for (std::size_t k = 0; k < v.size(); ++k)
      v[k] = c.value(k);
  }
  return d;
}

std::vector<InnovationChannel> ModelResult::channels() const {
  std::vector<InnovationChannel> out;
  for (const auto& c : chans) {
    InnovationChannel ic;
    ic.name = c.name;
    ic.label = c.label == c.name ? std::string() : c.label;
    ic.dof = static_cast<double>(c.roles.size());
    ic.nis = c.nis;
    ic.log_det_s = c.log_det_s;
    ic.nll = c.nll;
    // y_j/√S_jj where the update was applied (NIS finite): the whole channel when scalar, else
    // each component (its whiteness is tested one by one).
    auto normalized = [&](std::size_t j) {
      std::vector<double> v(c.nis.size(), kNoSample);
      for (std::size_t k = 0; k < c.nis.size(); ++k) {
        if (std::isfinite(c.nis[k])) v[k] = c.y[j][k] / std::sqrt(c.S[j][k]);
      }
      return v;
    };
    if (c.roles.size() == 1) {
      ic.normalized = normalized(0);
    } else {
      for (std::size_t j = 0; j < c.roles.size(); ++j)
        ic.components.push_back({c.roles[j], normalized(j)});
    }
    out.push_back(std::move(ic));
  }
  return out;
}

NeesSeries ModelResult::nees_series() const {
  if (nees_dof <= 0) return {};
  NeesSeries s{nees_dof, nees, false, false};
  for (std::size_t k = 0; k < steps() && !s.error_finite; ++k) {
    bool all = true, finite = true;
    for (std::size_t i = 0; i < truth.size(); ++i) {
      if (truth[i].empty()) continue;
      all = all && std::isfinite(truth[i][k]);
      const double e = x[i][k] - truth[i][k];
      finite = finite && std::isfinite(e * e);
    }
    s.truth = s.truth || all;
    s.error_finite = all && finite;
  }
  if (!s.truth) s.error_finite = true;
  return s;
}

std::vector<StateSeries> ModelResult::states() const {
  std::vector<StateSeries> out;
  for (std::size_t i = 0; i < x.size(); ++i) {
    out.push_back({state_keys[i], state_labels[i], state_units[i], &x[i], &P[diag[i]],
                   truth[i].empty() ? nullptr : &truth[i]});
  }
  return out;
}

namespace {

// errᵀ Ps⁻¹ err for 2 or 3 states (seed 004's NEES of the position at every row), by an LDLᵀ
// written out: NaN when a pivot is not positive, as the LLT fails. Eigen's fixed-size LLT and
// solve cost ≈ 65 ns a row, 8 % of a run of seed 004's model file; this costs a tenth of that.
double nees_small(const detail::Dims<Eigen::Dynamic>::Meas& e,
                  const detail::Dims<Eigen::Dynamic>::MeasCov& P) {
  const double d1 = P(0, 0);
  if (!(d1 > 0.0)) return kNoSample;
  const double l21 = P(1, 0) / d1;
  const double d2 = P(1, 1) - l21 * P(1, 0);
  if (!(d2 > 0.0)) return kNoSample;
  const double w1 = e(0), w2 = e(1) - l21 * w1;
  double sum = w1 * w1 / d1 + w2 * w2 / d2;
  if (e.size() == 2) return sum;
  const double l31 = P(2, 0) / d1;
  const double l32 = (P(2, 1) - l31 * P(1, 0)) / d2;
  const double d3 = P(2, 2) - l31 * P(2, 0) - l32 * l32 * d2;
  if (!(d3 > 0.0)) return kNoSample;
  const double w3 = e(2) - l31 * w1 - l32 * w2;
  return sum + w3 * w3 / d3;
}

}  // namespace

double detail::Context::nees(const detail::Dims<Eigen::Dynamic>::Meas& err,
                             const detail::Dims<Eigen::Dynamic>::MeasCov& Ps) {
  if (err.size() == 2 || err.size() == 3) return nees_small(err, Ps);
  Eigen::LLT<detail::Dims<Eigen::Dynamic>::MeasCov> llt(Ps);
  if (llt.info() == Eigen::Success) return err.dot(llt.solve(err));
  return kNoSample;
}

namespace {

// Six significant digits, as the run's messages have always printed them.
std::string brief(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

// "model.measurements.pos.H" (linear) or "model.measurements.pos.h".
std::string h_key(const ChannelSpec& cs) {
  return "model.measurements." + cs.name + (cs.linear ? ".H" : ".h");
}

}  // namespace

Status detail::Context::skip(std::size_t c, std::size_t k, const std::string& why) {
  if (capture) {
    capture->applied = false;
    capture->skipped = true;
    capture->why = why;
    return Ok{};
  }
  ChannelSeries& ch = r.chans[c];
  if (ch.updates + ch.gated + ch.skipped == 0) {
    return fail(k, "channel '" + ch.name + "': its first due update cannot be applied: " + why +
                       "; the run stops here");
  }
  ++ch.skipped;
  if (first_skip[c] == data.rows) {
    first_skip[c] = k;
    first_why[c] = why;
  }
  return Ok{};
}

std::string detail::Context::zhat_not_finite(std::size_t c, Eigen::Index j, bool sigma) const {
  const ChannelSpec& cs = spec.channels[c];
  const std::string at = sigma ? " at a sigma point" : " at the prediction";
  if (cs.linear) return "ẑ = H x is not finite" + at + " (" + h_key(cs) + ")";
  const auto jj = static_cast<std::size_t>(j);
  return "ẑ: " + h_key(cs) + "[" + std::to_string(jj) + "] = \"" + cs.h[jj].text +
         "\" is not finite" + at;
}

std::string detail::Context::s_not_pd(std::size_t c, const MatX& S, bool sigma) const {
  const ChannelSpec& cs = spec.channels[c];
  const std::string what =
      sigma ? "S (the sigma points through " + h_key(cs) + ", plus R)" : "S = H P Hᵀ + R";
  const std::string keys = " (" + h_key(cs) + ", " + cs.R.key + ")";
  if (!S.allFinite()) return what + " is not finite" + keys;
  return what + " is not positive definite (smallest eigenvalue " + brief(min_eigenvalue(S)) + ")" +
         keys;
}

Status detail::Context::finish_skips() {
  for (std::size_t c = 0; c < r.chans.size(); ++c) {
    const ChannelSeries& ch = r.chans[c];
    if (ch.partial) {
      r.warnings.push_back("channel '" + ch.name + "': " + std::to_string(ch.partial) +
                           " samples with some roles missing were not applied, the first at " +
                           where(ch.first_partial));
    }
    if (!ch.skipped) continue;
    const std::string first = "the first at " + where(first_skip[c]) + ": " + first_why[c];
    if (ch.updates == 0) {
      return failure("channel '" + ch.name + "' applied no update in the whole run: " +
                     std::to_string(ch.skipped) + " skipped, " + std::to_string(ch.gated) +
                     " gated; " + first + " (a filter that skips every update is no success)");
    }
    r.warnings.push_back("channel '" + ch.name + "': " + std::to_string(ch.skipped) +
                         " updates skipped, " + first);
  }
  return Ok{};
}

Expected<FilterKind> filter_kind(const std::string& name) {
  if (name == "kf") return FilterKind::kKf;
  if (name == "ekf") return FilterKind::kEkf;
  if (name == "ukf") return FilterKind::kUkf;
  if (name == "steady") return FilterKind::kSteady;
  return Error{"unknown filter '" + name + "' (kf, ekf, ukf, steady)"};
}

namespace {

const char* kind_name(FilterKind k) {
  switch (k) {
    case FilterKind::kKf:
      return "kf";
    case FilterKind::kEkf:
      return "ekf";
    case FilterKind::kUkf:
      return "ukf";
    case FilterKind::kSteady:
      return "steady";
  }
  return "kf";
}

// The groups whose scheme waits for instants (stacked, sequential): their members and queues.
// The UKF has no stacked update of a group.
Status set_groups(detail::Context& ctx, FilterKind kind) {
  const ModelSpec& spec = ctx.spec;
  ctx.group_of.assign(spec.channels.size(), -1);
  ctx.pending.resize(spec.groups.size());
  for (std::size_t g = 0; g < spec.groups.size(); ++g) {
    const GroupScheme scheme = ctx.ev.group(g).scheme;
    if (scheme == GroupScheme::kEach) continue;
    if (scheme == GroupScheme::kStacked && kind == FilterKind::kUkf) {
      return Error{spec.path + ": model.groups." + spec.groups[g].name +
                   ": the stacked scheme runs in the kf or the ekf, not the ukf"};
    }
    for (int c : spec.groups[g].members)
      ctx.group_of[static_cast<std::size_t>(c)] = static_cast<int>(g);
    ctx.pending[g].reserve(spec.groups[g].members.size());
  }
  return Ok{};
}

template <int N>
Status dispatch(detail::Context& ctx, const VecX& x0, const MatX& P0) {
  Vec<N> x = x0;
  Covariance<N> P = P0;
  if (ctx.options.kind == FilterKind::kUkf) return detail::run_ukf<N>(ctx, x, P);
  if (ctx.options.kind == FilterKind::kSteady) return detail::run_steady<N>(ctx, x, P);
  return detail::run_kf<N>(ctx, x, P);
}

}  // namespace

namespace detail {

void init_context(Context& ctx) {
  const ModelSpec& spec = ctx.spec;
  ctx.u_held.assign(spec.inputs.size(), 0.0);
  for (int slot : spec.input_age_slots)
    ctx.any_age = ctx.any_age || slot >= 0;
  ctx.u_time.assign(spec.inputs.size(), (*ctx.data.t)[0]);
  ctx.u_age.assign(spec.inputs.size(), 0.0);
  ctx.first_skip.assign(spec.channels.size(), ctx.data.rows);
  ctx.first_why.assign(spec.channels.size(), std::string());
  ctx.set_angles();
  ctx.z_buf.assign(static_cast<std::size_t>(kMaxChannelSize), 0.0);
}

namespace {

// The dataset's columns by role (an Error names the missing column).
Status bind_columns(const ModelSpec& spec, const Dataset& d, Data& data) {
  data.source = d.source;
  data.rows = d.rows();
  auto column = [&](const std::string& name,
                    const std::string& what) -> Expected<const std::vector<double>*> {
    if (!d.has(name)) return Error{d.source + ": missing column '" + name + "' (" + what + ")"};
    return &d.col(name);
  };
  auto tc = column("t", "time");
  if (!tc) return tc.err();
  data.t = *tc;
  for (const auto& in : spec.inputs) {
    auto c = column(in.name, "input");
    if (!c) return c.err();
    data.u.push_back(*c);
  }
  for (const auto& ch : spec.channels) {
    data.z.emplace_back();
    for (const auto& r : ch.roles) {
      auto c = column(r.name, "channel " + ch.name);
      if (!c) return c.err();
      data.z.back().push_back(*c);
    }
  }
  for (const auto& col : spec.truth)
    data.truth.push_back(!col.empty() && d.has(col) ? &d.col(col) : nullptr);
  for (const auto& ch : spec.channels) {
    const std::string& col = ch.missing.column;
    data.missing.push_back(ch.missing.on() && d.has(col) ? &d.col(col) : nullptr);
  }
  return Ok{};
}

// The channels' missing flags at the run's parameters (`when` 0: off); a flag column that the
// data lack leaves every sample in, with a warning.
Status set_missing_flags(const ModelSpec& spec, const Dataset& d, Prepared& p) {
  Context& ctx = *p.ctx;
  ctx.missing_on.assign(spec.channels.size(), 0);
  ctx.missing_equals.assign(spec.channels.size(), 0.0);
  std::vector<double> vars = p.ev->vars();
  for (std::size_t c = 0; c < spec.channels.size(); ++c) {
    const MissingSpec& m = spec.channels[c].missing;
    if (!m.on()) continue;
    const std::string key = "model.measurements." + spec.channels[c].name + ".missing";
    auto when = param_value(m.when, spec, vars, key + ".when");
    if (!when) return when.err();
    auto equals = param_value(m.equals, spec, vars, key + ".equals");
    if (!equals) return equals.err();
    if (*when == 0.0) continue;
    if (!p.data.missing[c]) {
      p.r->warnings.push_back("channel '" + spec.channels[c].name + "': no column '" + m.column +
                              "' in " + d.source + ": no sample is flagged missing");
      continue;
    }
    ctx.missing_on[c] = 1;
    ctx.missing_equals[c] = *equals;
  }
  return Ok{};
}

// The result's series, sized for the data, NaN until the run fills them.
void allocate_result(const ModelSpec& spec, const Dataset& d, Context& ctx) {
  ModelResult& r = ctx.r;
  const std::size_t rows = d.rows();
  const auto un = static_cast<std::size_t>(spec.n());
  r.t = *ctx.data.t;
  for (const auto& s : spec.states) {
    r.state_keys.push_back(s.name);
    r.state_labels.push_back(s.label);
    r.state_units.push_back(s.unit);
    r.x.emplace_back(rows, kNoSample);
  }
  r.P.assign(un * (un + 1) / 2, std::vector<double>(rows, kNoSample));
  for (std::size_t i = 0; i < un; ++i)
    r.diag.push_back(r.cov_index(i, i));
  r.truth.resize(un);
  for (std::size_t i = 0; i < un; ++i) {
    if (ctx.data.truth[i]) {
      r.truth[i] = *ctx.data.truth[i];
      ctx.truth_states.push_back(static_cast<int>(i));
    }
  }
  r.nees_dof = static_cast<double>(ctx.truth_states.size());
  if (r.nees_dof > 0) r.nees.assign(rows, kNoSample);
  for (std::size_t c = 0; c < spec.channels.size(); ++c) {
    const ChannelSpec& cs = spec.channels[c];
    ChannelSeries s;
    s.name = cs.name;
    s.label = cs.label;
    const auto m = static_cast<std::size_t>(cs.size());
    ctx.z_row.push_back(r.z.size());
    for (std::size_t j = 0; j < m; ++j) {
      s.roles.push_back(cs.comps[j].name);
      s.units.push_back(cs.comps[j].unit);
      r.role_names.push_back(cs.comps[j].name);
      // A pre-processed channel's components are recorded at its updates (Context).
      if (cs.preprocessed()) {
        r.z.emplace_back(rows, kNoSample);
      } else {
        r.z.push_back(*ctx.data.z[c][j]);
      }
    }
    s.y.assign(m, std::vector<double>(rows, kNoSample));
    s.S.assign(m, std::vector<double>(rows, kNoSample));
    s.K.assign(m * un, std::vector<double>(rows, kNoSample));
    if (!cs.outlier_column.empty()) {
      if (d.has(cs.outlier_column)) {
        s.outlier = d.col(cs.outlier_column);
      } else {
        r.warnings.push_back("channel '" + cs.name + "': its outlier column '" + cs.outlier_column +
                             "' is not in the data; outliers_* leave it out");
      }
    }
    s.nis.assign(rows, kNoSample);
    s.log_det_s.assign(rows, kNoSample);
    r.chans.push_back(std::move(s));
  }
}

}  // namespace

namespace {

// Row k of column `col` is a sample a channel reading it flags missing (its missing flag in force):
// a `first` x0 skips it, as the channel does.
bool flagged_missing(const Context& ctx, const std::string& col, std::size_t k) {
  for (std::size_t c = 0; c < ctx.missing_on.size(); ++c) {
    if (!ctx.missing_on[c] || (*ctx.data.missing[c])[k] != ctx.missing_equals[c]) continue;
    for (const auto& r : ctx.spec.channels[c].roles) {
      if (r.name == col) return true;
    }
  }
  return false;
}

}  // namespace

Status steady_gain(const ModelSpec& spec, const Dataset& d, const ParamValues& values,
                   Context& ctx) {
  const std::string what = spec.path + ": filter 'steady': ";
  if (spec.modes || spec.channels.size() != 1 || !spec.groups.empty()) {
    return Error{what + "one measurement channel and no modes (this model has " +
                 std::to_string(spec.channels.size()) + " channel(s)" +
                 (spec.modes ? " and modes" : "") + "); use kf"};
  }
  auto ev = ModelEval::create(spec, values);
  if (!ev) return ev.err();
  const double dt = d.median_dt();
  if (auto st = (*ev)->check_dt(dt, "the median interval of " + d.source); !st) return st;
  auto ss = model_steady_state(spec, **ev);
  if (!ss) return Error{what + ss.error()};
  ctx.steady_K = ss->dare.K;
  return Ok{};
}

Expected<std::unique_ptr<Prepared>> prepare_run(const ModelSpec& spec, const Dataset& d,
                                                const ParamValues& values,
                                                const FilterOptions& options,
                                                const RunControl& control) {
  auto p = std::make_unique<Prepared>();
  if (auto st = bind_columns(spec, d, p->data); !st) return st.err();
  auto ev = ModelEval::create(spec, values);
  if (!ev) return ev.err();
  p->ev = std::move(*ev);
  // A Q or R that depends on dt is checked at every interval of the data as the run meets it
  // (ModelEval::set_dt_at, run_steps): an Error, exit 2, like a refusal before the run.
  p->r = std::make_shared<ModelResult>();
  p->r->filter = kind_name(options.kind);
  p->ctx = std::make_unique<Context>(
      Context{spec, *p->ev, p->data, *p->r, control, options, {}, {}, {}});
  Context& ctx = *p->ctx;
  allocate_result(spec, d, ctx);
  init_context(ctx);
  if (auto st = set_groups(ctx, options.kind); !st) return st.err();
  if (auto st = set_missing_flags(spec, d, *p); !st) return st.err();

  // x0: expressions, or the first finite sample of a column (as seed 000 starts from the first
  // angle reading).
  p->x0 = p->ev->x0;
  for (std::size_t i = 0; i < spec.x0.size(); ++i) {
    const std::string& col = spec.x0[i].first_column;
    if (col.empty() || !d.has(col)) continue;
    const auto& column = d.col(col);
    for (std::size_t k = 0; k < column.size(); ++k) {
      if (std::isfinite(column[k]) && !flagged_missing(ctx, col, k)) {
        p->x0(static_cast<Eigen::Index>(i)) = column[k];
        break;
      }
    }
  }
  // dt at the first row (for channel entries that use it): the first interval.
  const auto first = [&] { return "the interval into step 1 of " + d.source; };
  if (auto st = p->ev->set_dt_at((*p->data.t)[1] - (*p->data.t)[0], first); !st) return st.err();
  if (spec.start_channel >= 0 && !spec.modes) {
    if (auto st = start_from_channel(*p, *p->ev); !st) return st.err();
  }
  return p;
}

Status start_from_channel(Prepared& p, ModelEval& e) {
  Context& ctx = *p.ctx;
  const ModelSpec& spec = ctx.spec;
  const auto c = static_cast<std::size_t>(spec.start_channel);
  const std::string& name = spec.channels[c].name;
  const auto& t = *ctx.data.t;
  std::size_t k = 0;
  for (; k < ctx.data.rows; ++k) {
    ctx.hold_inputs(k);
    if (ctx.channel_ready(c, k)) break;
  }
  if (k == ctx.data.rows) {
    return failure(ctx.data.source + ": channel '" + name +
                   "' has no sample, and x0 starts the filter from its first one");
  }
  e.set_time(t[k]);
  ctx.set_inputs_of(e, t[k]);
  if (std::string why; !ctx.preprocess(e, c, ctx.z_buf.data(), why)) {
    return ctx.fail(k, "channel '" + name + "', whose first sample makes x0: " + why);
  }
  for (std::size_t i = 0; i < spec.x0.size(); ++i) {
    if (spec.x0[i].first_channel != static_cast<int>(c)) continue;
    p.x0(static_cast<Eigen::Index>(i)) =
        ctx.z_buf[static_cast<std::size_t>(spec.x0[i].first_component)];
  }
  ctx.start = k;
  ctx.start_channel = static_cast<int>(c);
  return Ok{};
}

Status run_prepared(Prepared& p, const ParamValues& values, const Dataset& d, LoopHook* loop) {
  const ModelSpec& spec = p.ctx->spec;
  Context& ctx = *p.ctx;
  ctx.loop = loop;
  if (ctx.options.kind == FilterKind::kSteady) {
    if (auto st = steady_gain(spec, d, values, ctx); !st) return st;
  }
  const VecX& x0 = p.x0;
  const MatX& P0 = p.ev->P0;
  const int n = spec.n();
  Status st = Ok{};
  if (spec.modes) {
    st = run_imm(p, values);
  } else {
    switch (n) {
      case 1:
        st = dispatch<1>(ctx, x0, P0);
        break;
      case 2:
        st = dispatch<2>(ctx, x0, P0);
        break;
      case 3:
        st = dispatch<3>(ctx, x0, P0);
        break;
      case 4:
        st = dispatch<4>(ctx, x0, P0);
        break;
      case 5:
        st = dispatch<5>(ctx, x0, P0);
        break;
      case 6:
        st = dispatch<6>(ctx, x0, P0);
        break;
      default:
        st = dispatch<Eigen::Dynamic>(ctx, x0, P0);
    }
  }
  return st;
}

Status finish_run(Context& ctx) {
  const ModelSpec& spec = ctx.spec;
  for (std::size_t i = 0; i < spec.inputs.size(); ++i) {
    std::size_t missing = 0;
    for (double v : *ctx.data.u[i])
      missing += std::isfinite(v) ? 0 : 1;
    if (missing) {
      ctx.r.warnings.push_back(std::to_string(missing) + " samples of input '" +
                               spec.inputs[i].name + "' missing: the previous value was held");
    }
  }
  return ctx.finish_skips();
}

}  // namespace detail

Expected<std::shared_ptr<ModelResult>> run_model_filter(const ModelSpec& spec, const Dataset& d,
                                                        const ParamValues& values,
                                                        const FilterOptions& options,
                                                        const RunControl& control) {
  if ((options.kind == FilterKind::kKf || options.kind == FilterKind::kSteady) &&
      !spec.linear_modes()) {
    return Error{spec.path + ": filter '" + kind_name(options.kind) +
                 "' needs a linear model (F or A, and H in every channel); use ekf or ukf"};
  }
  const int n = spec.n();
  if (options.kind == FilterKind::kUkf) {
    const double lambda = options.alpha * options.alpha * (n + options.kappa) - n;
    if (!(n + lambda > 0.0)) {
      return Error{"ukf.alpha, ukf.kappa: n + λ = α²(n + κ) must be positive (n = " +
                   std::to_string(n) + ")"};
    }
  }
  if (d.rows() < 2) return Error{d.source + ": need at least two rows"};
  auto p = detail::prepare_run(spec, d, values, options, control);
  if (!p) return p.err();
  if (auto st = detail::run_prepared(**p, values, d, nullptr); !st) return st.err();
  if (auto done = detail::finish_run(*(*p)->ctx); !done) return done.err();
  return (*p)->r;
}

}  // namespace kfw::model
