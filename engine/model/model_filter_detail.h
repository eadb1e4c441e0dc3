// Internal to the model filters (model_filters.h, run by model_kf.cpp, model_ukf.cpp, imm/):
// fixed-size types per state count, the data columns of a run, the step loop and the per-step
// recording shared by every filter. The filter maths is the filter library's
// (filter/kalman_filter.h, filter/ekf.h, filter/ukf.h, and the one measurement update of
// filter/measurement_update.h).
#pragma once

#include <Eigen/Cholesky>
#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "core/scenario.h"
#include "filter/angle.h"
#include "filter/filter_types.h"
#include "filter/measurement_update.h"
#include "model/model_eval.h"
#include "model/model_filter.h"
#include "model/model_result.h"

namespace kfw::model::detail {

inline constexpr int kM = kMaxChannelSize;

// State-size N fixed (fast, no heap) or Eigen::Dynamic; measurement sizes up to kM, no heap.
template <int N>
using Dims = FilterDims<N, Eigen::Dynamic, kM>;

// The dataset's columns for a run, by role.
struct Data {
  std::string source;  // the dataset's, for messages
  std::size_t rows = 0;
  const std::vector<double>* t = nullptr;
  std::vector<const std::vector<double>*> u;               // per input
  std::vector<std::vector<const std::vector<double>*>> z;  // per channel, per component
  std::vector<const std::vector<double>*> truth;           // per state; null: no truth
  // Per channel: the column of its missing flag (ChannelSpec::missing), null: none.
  std::vector<const std::vector<double>*> missing;
};

// A group member's sample waiting for its instant (GroupScheme kStacked, kSequential).
struct Pending {
  std::size_t c = 0;    // the channel
  std::size_t row = 0;  // the row it arrived on (its y and S are recorded there)
  double z = 0.0;
};

// A closed loop around the filter (model/loop/closed_loop.cpp): `before` makes row k of the data
// (the world steps there; `stop` when an event ends the run before row k), `after` sees the
// filter's x and P at row k (column-major, n × n) and drives the world for the next interval.
struct LoopHook {
  virtual ~LoopHook() = default;
  virtual Status before(std::size_t k, bool& stop) = 0;
  virtual Status after(std::size_t k, const double* x, const double* P) = 0;
};

// What every filter shares: the evaluator, the data, the result being filled, inputs held.
struct Context {
  const ModelSpec& spec;
  ModelEval& ev;
  const Data& data;
  ModelResult& r;
  const RunControl& control;
  FilterOptions options;
  std::vector<double> u_held;                  // the inputs, last finite value held
  std::vector<int> truth_states;               // states with a truth column
  std::vector<double> z_buf;                   // one channel's measurement
  std::vector<Angle> state_angle;              // per state
  std::vector<std::vector<Angle>> role_angle;  // per channel, per component
  bool any_angle = false;                      // some state is an angle
  std::vector<std::size_t> first_skip{};       // per channel: the first skipped step (or rows)
  std::vector<std::string> first_why{};        // per channel: why it was skipped
  // Input ages (InputSpec::age): per input the time of its last sample, and the ages set.
  bool any_age = false;
  std::vector<double> u_time{}, u_age{};
  // Channel groups whose scheme is stacked or sequential: each channel's group (-1: none, or
  // updated on its own), and per group the samples waiting for their instant.
  std::vector<int> group_of{};
  std::vector<std::vector<Pending>> pending{};
  // The first row the filter runs (x0 from a channel's first sample: that row, whose sample of
  // `start_channel` made x0 and is not applied again), and per channel its first row in r.z.
  std::size_t start = 0;
  int start_channel = -1;
  std::vector<std::size_t> z_row{};
  // Per channel with a missing flag in force: the value that marks a sample missing.
  std::vector<char> missing_on{};
  std::vector<double> missing_equals{};
  MatX steady_K{};           // filter = steady: the fixed gain (n × m)
  LoopHook* loop = nullptr;  // a closed loop, or null
  std::size_t end = 0;       // rows run: data.rows, or the row an event stopped the loop at
  // A mode filter of an IMM (model/imm/): its update is kept here instead of recorded, and an
  // update it cannot apply is marked here instead of counted; the IMM decides. Null: a plain run.
  struct Capture {
    bool applied = false, skipped = false;
    std::string why;
    double nis = 0.0, log_det_s = 0.0;
    std::size_t m = 0;
    double y[kM] = {}, S[kM] = {};  // S's diagonal
    double z[kM] = {};              // the sample (a pre-processed channel's components)
    std::vector<double> K;          // [state · m + component]
  };
  Capture* capture = nullptr;

  // The angles of the states and channel components, from the spec.
  void set_angles() {
    for (const auto& s : spec.states) {
      state_angle.push_back(s.angle);
      any_angle = any_angle || s.angle != Angle::kNone;
    }
    role_angle.resize(spec.channels.size());
    for (std::size_t c = 0; c < spec.channels.size(); ++c) {
      for (const auto& comp : spec.channels[c].comps)
        role_angle[c].push_back(comp.angle);
    }
  }

  // What the measurement update applies to channel c: its angles and its gate.
  UpdateRules rules(std::size_t c) { return {role_angle[c], ev.channel(c).gate_nis}; }

  // Angle states wrapped to one turn.
  template <class V>
  void wrap_states(V& x) const {
    if (!any_angle) return;
    for (Eigen::Index i = 0; i < x.size(); ++i)
      x(i) = wrap(x(i), state_angle[static_cast<std::size_t>(i)]);
  }

  std::string where(std::size_t k) const {
    std::ostringstream os;
    os << "step " << k << " (t = " << (*data.t)[k] << " s)";
    return os.str();
  }
  Error fail(std::size_t k, const std::string& what) const {
    return failure(where(k) + ": " + what);
  }

  // Takes row k's inputs, holding the last finite value of a missing sample.
  void hold_inputs(std::size_t k) {
    for (std::size_t i = 0; i < u_held.size(); ++i) {
      const double v = (*data.u[i])[k];
      if (std::isfinite(v)) {
        u_held[i] = v;
        if (any_age) u_time[i] = (*data.t)[k];
      }
    }
  }
  // The inputs held, and their ages at time `now`, as the evaluator's symbols.
  void set_inputs(double now) { set_inputs_of(ev, now); }
  void set_inputs_of(ModelEval& e, double now) {
    e.set_inputs(u_held.data());
    if (!any_age) return;
    for (std::size_t i = 0; i < u_time.size(); ++i)
      u_age[i] = now - u_time[i];
    e.set_input_ages(u_age.data());
  }

  // Channel c's sample at row k (z_buf) as the filter compares it: a pre-processed channel's
  // components, from evaluator `e`. False (and `why`) when a component is not finite.
  bool preprocess(ModelEval& e, std::size_t c, double* z, std::string& why) const {
    e.channel_step(c, z);
    const ChannelSpec& cs = spec.channels[c];
    if (!cs.preprocessed()) return true;
    for (int j = 0; j < cs.size(); ++j) {
      if (std::isfinite(z[j])) continue;
      why = "its component '" + cs.comps[static_cast<std::size_t>(j)].name + "' (" +
            "model.measurements." + cs.name + ".z[" + std::to_string(j) + "]) is not finite";
      return false;
    }
    return true;
  }

  // The channel updates at row k: its clock allows and every value is present. Fills z_buf.
  bool channel_ready(std::size_t c, std::size_t k) {
    const auto& ch = ev.channel(c);
    if (k % static_cast<std::size_t>(ch.every) != 0) return false;
    const auto& cols = data.z[c];
    for (std::size_t j = 0; j < cols.size(); ++j) {
      const double v = (*cols[j])[k];
      if (!std::isfinite(v)) {
        if (cols.size() > 1) [[unlikely]]
          note_partial(c, k);
        return false;
      }
      z_buf[j] = v;
    }
    if (!missing_on.empty() && missing_on[c] && (*data.missing[c])[k] == missing_equals[c])
        [[unlikely]] {
      ++r.chans[c].flagged;
      return false;
    }
    return true;
  }

  // Row k of channel c has a value in some roles and none in others: counted (a warning after the
  // run: a sensor that lost part of a sample, seed 001's angles without their range).
  [[gnu::noinline]] void note_partial(std::size_t c, std::size_t k) {
    for (const auto* col : data.z[c]) {
      if (!std::isfinite((*col)[k])) continue;
      ChannelSeries& ch = r.chans[c];
      if (ch.partial++ == 0) ch.first_partial = k;
      return;
    }
  }

  // Stores x and P (upper triangle) at step k and the NEES over the states with truth.
  template <class V, class M>
  void record_state(std::size_t k, const V& x, const M& P) {
    const auto n = static_cast<std::size_t>(x.size());
    for (std::size_t i = 0; i < n; ++i)
      r.x[i][k] = x(static_cast<Eigen::Index>(i));
    std::size_t e = 0;
    for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(n); ++i) {
      for (Eigen::Index j = i; j < static_cast<Eigen::Index>(n); ++j)
        r.P[e++][k] = P(i, j);
    }
    if (truth_states.empty()) return;
    const auto d = static_cast<Eigen::Index>(truth_states.size());
    typename Dims<Eigen::Dynamic>::Meas err(d);
    for (Eigen::Index a = 0; a < d; ++a) {
      const int s = truth_states[static_cast<std::size_t>(a)];
      const double tv = (*data.truth[static_cast<std::size_t>(s)])[k];
      if (!std::isfinite(tv)) return;
      err(a) = wrap(x(s) - tv, spec.states[static_cast<std::size_t>(s)].angle);
    }
    if (d == 1) {
      const double v = P(truth_states[0], truth_states[0]);
      r.nees[k] = err(0) * err(0) / v;
      return;
    }
    typename Dims<Eigen::Dynamic>::MeasCov Ps(d, d);
    for (Eigen::Index a = 0; a < d; ++a) {
      for (Eigen::Index b = 0; b < d; ++b)
        Ps(a, b) =
            P(truth_states[static_cast<std::size_t>(a)], truth_states[static_cast<std::size_t>(b)]);
    }
    r.nees[k] = nees(err, Ps);
  }

  // errᵀ Ps⁻¹ err, or NaN when Ps is not positive definite. Out of line: one copy for every
  // filter and state count, and the step loops stay small enough to inline their own maths.
  static double nees(const Dims<Eigen::Dynamic>::Meas& err,
                     const Dims<Eigen::Dynamic>::MeasCov& Ps);

  // Counts channel c's update at step k by its outcome and stores its innovation and S diagonal
  // (updated or gated), NIS, log det S and gain (updated). A skipped update is skip()'s.
  template <int N, int M, int MaxM>
  void record_update(std::size_t c, std::size_t k, const MeasurementUpdate<N, M, MaxM>& u) {
    if (capture) [[unlikely]] {
      keep_update(u);
      return;
    }
    ChannelSeries& ch = r.chans[c];
    if (u.status == UpdateStatus::kSkipped) return;
    if (spec.channels[c].preprocessed()) [[unlikely]] {
      for (std::size_t j = 0; j < ch.y.size(); ++j)
        r.z[z_row[c] + j][k] = z_buf[j];
    }
    ++(u.updated() ? ch.updates : ch.gated);
    if (u.status == UpdateStatus::kGated) ch.gated_rows.push_back(k);
    const auto m = static_cast<std::size_t>(u.y.size());
    for (std::size_t j = 0; j < m; ++j) {
      const auto jj = static_cast<Eigen::Index>(j);
      ch.y[j][k] = u.y(jj);
      ch.S[j][k] = u.S(jj, jj);
    }
    ch.nis[k] = u.updated() ? u.nis : kNoSample;
    ch.log_det_s[k] = u.updated() ? u.log_det_S : kNoSample;
    if (!std::isfinite(ch.nis[k])) return;
    for (Eigen::Index i = 0; i < u.K.rows(); ++i) {
      for (Eigen::Index j = 0; j < u.K.cols(); ++j)
        ch.K[static_cast<std::size_t>(i) * m + static_cast<std::size_t>(j)][k] = u.K(i, j);
    }
  }

  template <int N, int M, int MaxM>
  [[gnu::noinline]] void keep_update(const MeasurementUpdate<N, M, MaxM>& u) {
    Capture& cap = *capture;
    cap.applied = u.updated();
    cap.m = static_cast<std::size_t>(u.y.size());
    for (Eigen::Index j = 0; j < u.y.size(); ++j) {
      cap.y[j] = u.y(j);
      cap.S[j] = u.S(j, j);
    }
    for (std::size_t j = 0; j < cap.m; ++j)
      cap.z[j] = z_buf[j];
    cap.nis = u.nis;
    cap.log_det_s = u.log_det_S;
    if (!cap.applied) return;
    cap.K.resize(static_cast<std::size_t>(u.K.rows()) * cap.m);
    for (Eigen::Index i = 0; i < u.K.rows(); ++i) {
      for (Eigen::Index j = 0; j < u.K.cols(); ++j)
        cap.K[static_cast<std::size_t>(i) * cap.m + static_cast<std::size_t>(j)] = u.K(i, j);
    }
  }

  // Channel c's update at step k could not be applied (`why`: S, or ẑ with its expression).
  // At the channel's first due update that ends the run (exit 1); later the update is counted as
  // skipped (a warning after the run, a failure when the channel applied none).
  Status skip(std::size_t c, std::size_t k, const std::string& why);
  // Why: ẑ's component j is not finite (h[j] or H named); S is not positive definite or not
  // finite (H or h, and R named). `sigma`: ẑ and S from the UKF's sigma points.
  std::string zhat_not_finite(std::size_t c, Eigen::Index j, bool sigma) const;
  std::string s_not_pd(std::size_t c, const MatX& S, bool sigma) const;
  // After the run: a channel that applied no update and skipped some fails the run (exit 1);
  // one that skipped some after its first update gets a warning.
  Status finish_skips();

  // A variance that overflows ends the run (an unstable process that no channel observes: x may
  // stay finite while P grows without bound). The diagonal goes first; checked after a
  // prediction, where P grows.
  template <class M>
  Status check_variances(std::size_t k, const M& P) const {
    for (Eigen::Index i = 0; i < P.rows(); ++i) {
      if (!std::isfinite(P(i, i))) [[unlikely]] {
        return fail(k, "the variance of '" + spec.states[static_cast<std::size_t>(i)].name +
                           "' is not finite (P overflowed: is the process unstable and the "
                           "state unobserved?); the run stops here");
      }
    }
    return Ok{};
  }

  // After a prediction or an update: the state finite (check_finite), then its variances.
  template <class V, class M>
  Status check_estimate(std::size_t k, const V& x, const M& P) const {
    if (auto st = check_finite(k, x); !st) [[unlikely]]
      return st;
    return check_variances(k, P);
  }

  // A state that stops being finite ends the run.
  template <class V>
  Status check_finite(std::size_t k, const V& x) const {
    for (Eigen::Index i = 0; i < x.size(); ++i) {
      if (!std::isfinite(x(i))) {
        return fail(k, "the state '" + spec.states[static_cast<std::size_t>(i)].name +
                           "' is not finite; the run stops here");
      }
    }
    return Ok{};
  }

  // Q or R evaluated at a state or time must stay positive semidefinite.
  Status check_noise(std::size_t k, const MatX& M, const std::string& key) const {
    if (M.rows() == 1 ? M(0, 0) >= 0.0 : is_psd(M)) return Ok{};
    std::ostringstream os;
    os << key << " lost definiteness (smallest eigenvalue " << min_eigenvalue(M)
       << "); the run stops here";
    return fail(k, os.str());
  }
  // Called only where Q (ev.process_noise_varies()) or channel c's R (R_varies) varies: a Status
  // built and destroyed per step costs the KF's hot path a few per cent.
  Status check_process_noise(std::size_t k) const {
    return check_noise(k, ev.Q, "model.process.Q");
  }
  Status check_channel_noise(std::size_t c, std::size_t k) const {
    return check_noise(k, ev.channel(c).R, spec.channels[c].R.key);
  }
};

// Applies group g's waiting samples at row k (the instant closes): one after the other through
// the filter's update (sequential), or in the filter's update_group (stacked).
template <class Filter>
Status flush_group(Context& ctx, Filter& f, std::size_t g, std::size_t k) {
  std::vector<Pending>& batch = ctx.pending[g];
  if (batch.empty()) return Ok{};
  Status st = Ok{};
  if (ctx.ev.group(g).scheme == GroupScheme::kSequential) {
    for (const Pending& q : batch) {
      ctx.z_buf[0] = q.z;
      ctx.ev.channel_step(q.c, ctx.z_buf.data());
      if (st = f.update(q.c, q.row); !st) break;
    }
  } else if constexpr (requires { f.update_group(g, batch, k); }) {
    for (const Pending& q : batch) {
      double z = q.z;  // a group's members are not pre-processed: z stays
      ctx.ev.channel_step(q.c, &z);
    }
    st = f.update_group(g, batch, k);
  }
  batch.clear();
  return st;
}

// A group member's sample at row k (in z_buf): it waits for its instant, which closes before it
// when the member already waits (another member dropped out) and after it when every member has
// a sample (seed 004's synchronisation of the ranges).
template <class Filter>
Status group_sample(Context& ctx, Filter& f, std::size_t c, std::size_t k) {
  const auto g = static_cast<std::size_t>(ctx.group_of[c]);
  auto& batch = ctx.pending[g];
  const Pending sample{c, k, ctx.z_buf[0]};  // before a sequential flush reuses z_buf
  for (const Pending& q : batch) {
    if (q.c != c) continue;
    if (auto st = flush_group(ctx, f, g, k); !st) return st;
    break;
  }
  batch.push_back(sample);
  if (batch.size() < ctx.spec.groups[g].members.size()) return Ok{};
  return flush_group(ctx, f, g, k);
}

// The recursion over the rows that every model filter runs: the process set to the interval
// before row k, then the filter's predict; each channel due at row k set, then the filter's
// update (a grouped channel's sample waits for its instant); then x and P recorded. A Filter has
// x, P, Status predict(k) and Status update(c, k), and may have update_group(g, batch, k).
template <class Filter>
Status run_steps(Context& ctx, Filter& f) {
  ModelEval& ev = ctx.ev;
  const auto& t = *ctx.data.t;
  ctx.end = ctx.data.rows;
  for (std::size_t k = ctx.start; k < ctx.data.rows; ++k) {
    if (ctx.loop) [[unlikely]] {
      bool stop = false;
      if (auto st = ctx.loop->before(k, stop); !st) return st;
      if (stop) {
        ctx.end = k;
        break;
      }
    }
    if (k > ctx.start) {
      const auto where = [&] {
        return "the interval into step " + std::to_string(k) + " of " + ctx.data.source;
      };
      if (auto st = ev.set_dt_at(t[k] - t[k - 1], where); !st) return st;
      ev.set_time(t[k - 1]);
      ctx.set_inputs(t[k - 1]);
      ev.process_step();
      if (auto st = f.predict(k); !st) return st;
    }
    ctx.hold_inputs(k);
    bool row_set = false;
    for (std::size_t c = 0; c < ctx.spec.channels.size(); ++c) {
      if (!ctx.channel_ready(c, k)) continue;
      if (k == ctx.start && static_cast<int>(c) == ctx.start_channel) continue;  // made x0
      if (!row_set) {
        ev.set_time(t[k]);
        ctx.set_inputs(t[k]);
        row_set = true;
      }
      if (ctx.group_of[c] >= 0) {
        if (auto st = group_sample(ctx, f, c, k); !st) return st;
        continue;
      }
      if (std::string why; !ctx.preprocess(ev, c, ctx.z_buf.data(), why)) {
        if (auto st = ctx.skip(c, k, why); !st) return st;
        continue;
      }
      if (auto st = f.update(c, k); !st) return st;
    }
    ctx.record_state(k, f.x, f.P);
    if (ctx.loop) [[unlikely]] {
      if (auto st = ctx.loop->after(k, f.x.data(), f.P.data()); !st) return st;
      ctx.hold_inputs(k);  // an input the controller just wrote (its output at row k)
    }
    if ((k & 0xFFF) == 0xFFF && ctx.control.cancelled()) return Error{"cancelled"};
  }
  // Samples still waiting at the end are applied (their y and S recorded; no row follows).
  for (std::size_t g = 0; g < ctx.pending.size() && ctx.end > 0; ++g) {
    if (auto st = flush_group(ctx, f, g, ctx.end - 1); !st) return st;
  }
  return Ok{};
}

// A run's setup (model_filter.cpp): the data's columns, the evaluator at the run's values, the
// result sized for the data and the context over them, and x0 (a `first` column's sample put in).
struct Prepared {
  Data data;
  std::unique_ptr<ModelEval> ev;
  std::shared_ptr<ModelResult> r;
  std::unique_ptr<Context> ctx;
  VecX x0;
};
Expected<std::unique_ptr<Prepared>> prepare_run(const ModelSpec& spec, const Dataset& d,
                                                const ParamValues& values,
                                                const FilterOptions& options,
                                                const RunControl& control);
// A context's per-run state: inputs held, ages, skips, angles, the measurement buffer.
void init_context(Context& ctx);
// After the run: warnings for missing inputs, and the skips (Context::finish_skips).
Status finish_run(Context& ctx);
// x0 from a channel's first sample (ModelSpec::start_channel): the row the filter starts at, and
// the x0 entries that read the channel's components, evaluated by `e` (the run's, or an IMM's at
// its grid's centre). A channel without a sample ends the run (exit 1).
Status start_from_channel(Prepared& p, ModelEval& e);
// The filter's run over prepared data, in a closed loop when `loop` is set (run_model_filter's
// body; the loop's rows after ctx.end are left as the preparation made them).
Status run_prepared(Prepared& p, const ParamValues& values, const Dataset& d, LoopHook* loop);
// The IMM over the modes of spec.modes (model/imm/imm_run.cpp).
Status run_imm(Prepared& p, const ParamValues& values);

template <int N>
Status run_kf(Context& ctx, Vec<N> x, Covariance<N> P);
template <int N>
Status run_ukf(Context& ctx, Vec<N> x, Covariance<N> P);
template <int N>
Status run_steady(Context& ctx, Vec<N> x, Covariance<N> P);
// filter = steady: the DARE gain at the data's median interval into ctx.steady_K (one channel).
Status steady_gain(const ModelSpec& spec, const Dataset& d, const ParamValues& values,
                   Context& ctx);

// Instantiates a filter's run for every state count dispatched on (model_filter.cpp).
#define KFW_MODEL_FILTER_SIZES(RUN)                        \
  template Status RUN<1>(Context&, Vec<1>, Covariance<1>); \
  template Status RUN<2>(Context&, Vec<2>, Covariance<2>); \
  template Status RUN<3>(Context&, Vec<3>, Covariance<3>); \
  template Status RUN<4>(Context&, Vec<4>, Covariance<4>); \
  template Status RUN<5>(Context&, Vec<5>, Covariance<5>); \
  template Status RUN<6>(Context&, Vec<6>, Covariance<6>); \
  template Status RUN<Eigen::Dynamic>(Context&, Vec<Eigen::Dynamic>, Covariance<Eigen::Dynamic>);

}  // namespace kfw::model::detail
