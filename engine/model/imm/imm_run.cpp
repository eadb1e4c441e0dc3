// The IMM over a model's modes (presets/models/README.md, "Modes"; seed 001, Table 2): one model
// filter per mode (model_filters.h, each with its own evaluator at the mode's values and a
// context that keeps its updates instead of recording them), mixed, predicted, updated channel by
// channel with the mode probabilities updated after each channel, and combined at every row.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include "core/limits.h"
#include "filter/imm.h"
#include "filter/imm_grid.h"
#include "model/imm/imm_blocks.h"
#include "model/imm/imm_spec.h"
#include "model/model_filters.h"

namespace kfw::model::detail {

namespace {

constexpr double kNegInf = -std::numeric_limits<double>::infinity();
const double kLog2Pi = std::log(2.0 * std::numbers::pi);

// Renewal at a run's values (RenewalSpec): off when Kp is 0 or the model has no renewal.
struct RenewalRun {
  bool on = false;
  double kp = 0.0, start = 0.0;
  RenewalReading reading = RenewalReading::kIndex;
};

// A block filter (imm_blocks.h) is mixed block by block; its block size, or 1 for others.
template <class F>
struct BlockOf {
  static constexpr int value = 1;
};
template <int B>
struct BlockOf<BlockKalman<B>> {
  static constexpr int value = B;
};
template <class F>
constexpr bool kIsBlock = requires {
  F::kBlockSize;
};

// One mode: its evaluator, its context and the filter over them.
template <class Filter>
struct ModeRun {
  std::unique_ptr<ModelEval> ev;
  std::unique_ptr<Context> ctx;
  Context::Capture cap;
  std::unique_ptr<Filter> f;
};

template <int N, class Filter>
class Imm {
 public:
  Imm(Prepared& p, const ModesSpec& ms, std::vector<Mode> modes, MarkovChain chain,
      RenewalRun renewal, const StructureSpec* structure)
      : p_(p),
        main_(*p.ctx),
        ms_(ms),
        modes_(std::move(modes)),
        chain_(std::move(chain)),
        ren_(renewal),
        st_(structure) {}

  Status setup() {
    const std::size_t r = modes_.size(), rows = main_.data.rows;
    if (rows > limits::kMaxModeValues / r) {
      return Error{main_.spec.path + ": model.modes: " + std::to_string(rows) + " rows × " +
                   std::to_string(r) + " modes of probabilities: more than the limit of " +
                   std::to_string(limits::kMaxModeValues) + " values (docs/limits.md)"};
    }
    const auto& t = *main_.data.t;
    const auto first = [&] { return "the interval into step 1 of " + main_.data.source; };
    for (const Mode& m : modes_) {
      auto ev = ModelEval::create(*m.model, m.values);
      if (!ev) return Error{ev.error() + " (in mode '" + m.name + "')"};
      if (auto st = (*ev)->set_dt_at(t[1] - t[0], first); !st) {
        return Error{st.error() + " (in mode '" + m.name + "')"};
      }
      auto run = std::make_unique<ModeRun<Filter>>();
      run->ev = std::move(*ev);
      run->ctx = std::make_unique<Context>(Context{
          *m.model, *run->ev, main_.data, main_.r, main_.control, main_.options, {}, {}, {}});
      init_context(*run->ctx);
      run->ctx->group_of.assign(m.model->channels.size(), -1);
      run->ctx->capture = &run->cap;
      if constexpr (kIsBlock<Filter>) {
        run->f.reset(new Filter(*run->ctx, *st_, p_.x0, p_.ev->P0));
      } else {
        run->f.reset(new Filter{*run->ctx, Vec<N>(p_.x0), Covariance<N>(p_.ev->P0)});
      }
      if constexpr (requires { run->f->Z; }) {
        for (const auto& cs : m.model->channels)
          run->f->Z.push_back(MatX::Zero(cs.size(), run->f->ns));
      }
      if (!runs_.empty()) run->ev->share_process(*runs_.front()->ev);
      runs_.push_back(std::move(run));
    }
    log_mu_ = VecX::Constant(static_cast<Eigen::Index>(r), -std::log(static_cast<double>(r)));
    for (std::size_t j = 0; j < ms_.mu0.size(); ++j)
      log_mu_(static_cast<Eigen::Index>(j)) = std::log(ms_.mu0[j]);
    ImmSeries& s = *(main_.r.imm = ImmSeries{});
    for (const Mode& m : modes_) {
      s.names.push_back(m.name);
      s.labels.push_back(m.label);
    }
    s.mu.assign(rows * r, std::numeric_limits<float>::quiet_NaN());
    s.map.assign(rows, kNoSample);
    for (std::size_t a = 0; a < ms_.grid.size(); ++a) {
      const GridAxisSpec& g = ms_.grid[a];
      ImmSeries::Axis axis;
      axis.param = g.param;
      axis.label = g.label;
      axis.unit = g.unit;
      axis.estimate.assign(rows, kNoSample);
      for (const Mode& m : modes_) {
        axis.values.push_back(m.grid[a]);
        axis.n = std::max(axis.n, m.grid_index[a] + 1);
      }
      axis.centre.assign(rows, kNoSample);
      s.axes.push_back(std::move(axis));
    }
    for (auto& c : main_.r.chans)
      c.nll.assign(rows, kNoSample);
    set_grid();
    set_structure();
    return Ok{};
  }

  Status run() {
    const auto& t = *main_.data.t;
    for (auto& m : runs_) {  // the inputs held before the first row (x0 from a channel)
      for (std::size_t k = 0; k < main_.start; ++k)
        m->ctx->hold_inputs(k);
    }
    for (std::size_t k = main_.start; k < main_.data.rows; ++k) {
      if (k > main_.start) {
        if (auto st = predict(k, t); !st) return st;
      }
      for (auto& m : runs_)
        m->ctx->hold_inputs(k);
      bool row_set = false;
      for (std::size_t c = 0; c < main_.spec.channels.size(); ++c) {
        if (!main_.channel_ready(c, k)) continue;
        if (k == main_.start && static_cast<int>(c) == main_.start_channel) continue;
        if (!row_set) {
          for (auto& m : runs_) {
            m->ev->set_time(t[k]);
            m->ctx->set_inputs(t[k]);
          }
          row_set = true;
        }
        if (auto st = update(c, k); !st) return st;
      }
      record(k);
      if ((k & 0xFFF) == 0xFFF && main_.control.cancelled()) return Error{"cancelled"};
    }
    if (mode_skips_ > 0) {
      main_.r.warnings.push_back(std::to_string(mode_skips_) +
                                 " mode updates could not be applied (the first at " +
                                 main_.where(first_mode_skip_) + ": " + first_mode_why_ +
                                 "); those modes took probability 0 there");
    }
    return Ok{};
  }

 private:
  // Mixing from μ_{k−1}, then each mode's prediction to row k; μ becomes c̄.
  Status predict(std::size_t k, const std::vector<double>& t) {
    if (ren_.on) {
      if (auto st = renew(k, t[k] - t[k - 1]); !st) return st;
    }
    for (std::size_t j = 0; j < runs_.size(); ++j) {
      auto& m = runs_[j];
      const auto where = [&] {
        return "the interval into step " + std::to_string(k) + " of " + main_.data.source;
      };
      if (auto st = m->ev->set_dt_at(t[k] - t[k - 1], where); !st) {
        // Under renewal the moved grid broke it: a breakdown (exit 1), not a refusal.
        const std::string what = st.error() + " (in mode '" + modes_[j].name + "')";
        return ren_.on ? main_.fail(k, "the moved grid (renewal): " + what) : Status(Error{what});
      }
      m->ev->set_time(t[k - 1]);
      m->ctx->set_inputs(t[k - 1]);
      m->ev->process_step();
    }
    const ImmMixing w = imm_mixing(moved_ ? *moved_ : chain_, log_mu_);
    moved_.reset();
    if constexpr (kIsBlock<Filter>) {
      mix_blocks(w);
      for (auto& m : runs_) {
        if (auto st = m->f->predict(k); !st) return st;
      }
    } else {
      gather();
      imm_mix(w, g_, mixed_);
      for (std::size_t j = 0; j < runs_.size(); ++j) {
        runs_[j]->f->x = mixed_[j].x;
        runs_[j]->f->P = mixed_[j].P;
        if (st_) {
          drop_cross(runs_[j]->f->P);  // mixing block by block
          if (st_->approximate) drop_cross(runs_[j]->ev->Q);
        }
        if (auto st = runs_[j]->f->predict(k); !st) return st;
      }
    }
    log_mu_ = w.log_c_bar;
    return Ok{};
  }

  // Channel c at row k in every mode; μ ← Λ μ / c.
  Status update(std::size_t c, std::size_t k) {
    const std::size_t r = runs_.size();
    VecX ll(static_cast<Eigen::Index>(r));
    std::string why;
    for (std::size_t j = 0; j < r; ++j) {
      ModeRun<Filter>& m = *runs_[j];
      std::copy(main_.z_buf.begin(), main_.z_buf.end(), m.ctx->z_buf.begin());
      m.cap.applied = m.cap.skipped = false;
      if (!m.ctx->preprocess(*m.ev, c, m.ctx->z_buf.data(), m.cap.why)) {
        ll(static_cast<Eigen::Index>(j)) = kNegInf;
        if (why.empty()) why = m.cap.why;
        continue;
      }
      if constexpr (!kIsBlock<Filter>) {
        if (st_ && st_->approximate) drop_cross(m.ev->channel(c).R, c);
      }
      if (auto st = m.f->update(c, k); !st) return st;
      const auto jj = static_cast<Eigen::Index>(j);
      if (m.cap.applied) {
        ll(jj) = -0.5 * (static_cast<double>(m.cap.m) * kLog2Pi + m.cap.log_det_s + m.cap.nis);
      } else {
        ll(jj) = kNegInf;
        if (why.empty()) why = m.cap.why.empty() ? "no mode could apply it" : m.cap.why;
      }
    }
    const ImmProbabilities pr = imm_update_probabilities(log_mu_, ll);
    if (!pr.ok) return main_.skip(c, k, "in no mode: " + why);
    for (std::size_t j = 0; j < r; ++j) {
      if (std::isfinite(ll(static_cast<Eigen::Index>(j)))) continue;
      if (mode_skips_++ == 0) {
        first_mode_skip_ = k;
        first_mode_why_ = "channel '" + main_.spec.channels[c].name + "' in mode '" +
                          modes_[j].name + "': " + runs_[j]->cap.why;
      }
    }
    log_mu_ = pr.log_mu;
    Eigen::Index best = 0;
    for (Eigen::Index j = 1; j < log_mu_.size(); ++j) {
      if (log_mu_(j) > log_mu_(best)) best = j;
    }
    record_channel(c, k, runs_[static_cast<std::size_t>(best)]->cap, -pr.log_c);
    return Ok{};
  }

  // The MAP mode's update of channel c at row k as the channel's, and the mixture's NLL term.
  void record_channel(std::size_t c, std::size_t k, const Context::Capture& cap, double nll) {
    ChannelSeries& ch = main_.r.chans[c];
    ++ch.updates;
    for (std::size_t j = 0; j < cap.m; ++j) {
      ch.y[j][k] = cap.y[j];
      ch.S[j][k] = cap.S[j];
    }
    ch.nis[k] = cap.nis;
    ch.log_det_s[k] = cap.log_det_s;
    ch.nll[k] = nll;
    if (main_.spec.channels[c].preprocessed()) {  // the MAP mode's components
      for (std::size_t j = 0; j < cap.m; ++j)
        main_.r.z[main_.z_row[c] + j][k] = cap.z[j];
    }
    for (std::size_t e = 0; e < cap.K.size() && e < ch.K.size(); ++e)
      ch.K[e][k] = cap.K[e];
  }

  // The grid's centre and offsets per axis, and each axis's parameter slot (a grid's modes
  // share the model's symbols).
  void set_grid() {
    const ModelSpec& spec = main_.spec;
    for (std::size_t a = 0; a < ms_.grid.size(); ++a) {
      std::size_t n = 1;
      for (const Mode& m : modes_)
        n = std::max(n, m.grid_index[a] + 1);
      std::vector<double> values(n, 0.0);
      for (const Mode& m : modes_)
        values[m.grid_index[a]] = m.grid[a];
      const double c = 0.5 * (values.front() + values.back());
      centre_.push_back(c);
      est_.push_back(c);
      off_.emplace_back();
      for (double v : values)
        off_.back().push_back(v - c);
      int slot = -1;
      for (std::size_t i = 0; i < spec.param_keys.size(); ++i) {
        if (spec.param_keys[i] == ms_.grid[a].param) slot = spec.param_slots[i];
      }
      slot_.push_back(slot);
    }
    if (ren_.reading == RenewalReading::kMix) chain_matrix_ = chain_.matrix();
  }

  // The state pairs in different blocks, and per channel the component pairs; P0 block-diagonal.
  void set_structure() {
    if constexpr (!kIsBlock<Filter>) {  // a block filter holds the blocks alone
      if (!st_) return;
      const auto n = st_->block_of.size();
      for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t k = 0; k < n; ++k) {
          if (st_->block_of[i] != st_->block_of[k]) cross_.emplace_back(i, k);
        }
      }
      for (const auto& blocks : st_->component_block) {
        cross_R_.emplace_back();
        for (std::size_t a = 0; a < blocks.size(); ++a) {
          for (std::size_t b = 0; b < blocks.size(); ++b) {
            if (blocks[a] != blocks[b]) cross_R_.back().emplace_back(a, b);
          }
        }
      }
      for (auto& m : runs_)
        drop_cross(m->f->P);
    }
  }
  template <class M>
  void drop_cross(M& P) const {
    for (const auto& [i, k] : cross_)
      P(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)) = 0.0;
  }
  void drop_cross(MatX& R, std::size_t c) const {
    if (c >= cross_R_.size()) return;
    for (const auto& [a, b] : cross_R_[c])
      R(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)) = 0.0;
  }

  // Seed 001 eq. 4 before the prediction into row k: the grid moves by
  // d = gain (R̂_{k−1} − centre_{k−1}) per axis, μ follows by the reading, and every mode's
  // parameters take their moved values.
  Status renew(std::size_t k, double dt) {
    elapsed_ += dt;
    const double kp = elapsed_ < ren_.start ? 0.0 : ren_.kp;
    const double gain = ren_.reading == RenewalReading::kRate ? std::min(1.0, kp * dt) : kp;
    std::vector<double> d(centre_.size());
    bool moves = false;
    for (std::size_t a = 0; a < d.size(); ++a) {
      d[a] = gain * (est_[a] - centre_[a]);
      moves = moves || d[a] != 0.0;
    }
    if (!moves) return Ok{};
    if (ren_.reading == RenewalReading::kSlope) {
      const VecX moved = grid_remap(imm_probabilities(log_mu_), off_, d);
      log_mu_ = moved.array().max(1e-300).log().matrix();
    } else if (ren_.reading == RenewalReading::kMix) {
      auto moved = MarkovChain::dense(grid_shift_transition(off_, d) * chain_matrix_);
      if (!moved) return main_.fail(k, "the moved grid (renewal, mix): " + moved.error());
      moved_ = std::move(*moved);
    }
    for (std::size_t a = 0; a < d.size(); ++a)
      centre_[a] += d[a];
    std::vector<std::pair<int, double>> set(centre_.size());
    for (std::size_t j = 0; j < runs_.size(); ++j) {
      for (std::size_t a = 0; a < centre_.size(); ++a)
        set[a] = {slot_[a], centre_[a] + off_[a][modes_[j].grid_index[a]]};
      if (auto st = runs_[j]->ev->set_params(set); !st) {
        return main_.fail(k, "the moved grid (renewal): " + st.error());
      }
    }
    return Ok{};
  }

  void gather() {
    g_.resize(runs_.size());
    for (std::size_t j = 0; j < runs_.size(); ++j) {
      if constexpr (kIsBlock<Filter>) {
        const auto n = static_cast<Eigen::Index>(main_.spec.n());
        if (g_[j].x.size() != n) {
          g_[j].x.setZero(n);
          g_[j].P.setZero(n, n);  // the entries between blocks stay 0
        }
        runs_[j]->f->full(g_[j].x, g_[j].P);
      } else {
        g_[j].x = runs_[j]->f->x;
        g_[j].P = runs_[j]->f->P;
      }
    }
  }

  // Block filters: each block mixed over the modes (the spread terms between blocks dropped).
  void mix_blocks(const ImmMixing& w) {
    constexpr int B = BlockOf<Filter>::value;
    const std::size_t r = runs_.size(), blocks = runs_.front()->f->x.size();
    gb_.resize(r);
    for (std::size_t b = 0; b < blocks; ++b) {
      for (std::size_t j = 0; j < r; ++j) {
        gb_[j].x = runs_[j]->f->x[b];
        gb_[j].P = runs_[j]->f->P[b];
      }
      imm_mix<B>(w, gb_, mb_);
      for (std::size_t j = 0; j < r; ++j) {
        runs_[j]->f->x[b] = mb_[j].x;
        runs_[j]->f->P[b] = mb_[j].P;
      }
    }
  }

  // The combination at row k, μ, the MAP mode and the grid's estimates.
  void record(std::size_t k) {
    gather();
    const VecX mu = imm_probabilities(log_mu_);
    Gaussian<N> c = imm_combine(g_, mu);
    main_.wrap_states(c.x);
    main_.record_state(k, c.x, c.P);
    ImmSeries& s = *main_.r.imm;
    const std::size_t r = runs_.size();
    Eigen::Index best = 0;
    for (std::size_t j = 0; j < r; ++j) {
      const auto jj = static_cast<Eigen::Index>(j);
      s.mu[k * r + j] = static_cast<float>(mu(jj));
      if (mu(jj) > mu(best)) best = jj;
    }
    s.map[k] = static_cast<double>(best);
    for (std::size_t a = 0; a < s.axes.size(); ++a) {
      double e = 0.0;
      for (std::size_t j = 0; j < r; ++j)
        e += mu(static_cast<Eigen::Index>(j)) * (centre_[a] + off_[a][modes_[j].grid_index[a]]);
      s.axes[a].estimate[k] = e;
      s.axes[a].centre[k] = centre_[a];
      est_[a] = e;
    }
  }

  Prepared& p_;
  Context& main_;
  const ModesSpec& ms_;
  std::vector<Mode> modes_;
  MarkovChain chain_;
  std::vector<std::unique_ptr<ModeRun<Filter>>> runs_;
  VecX log_mu_;
  std::vector<Gaussian<N>> g_, mixed_;
  std::vector<Gaussian<BlockOf<Filter>::value>> gb_, mb_;  // block filters: one block
  RenewalRun ren_;
  const StructureSpec* st_;                                                // blocks, or null
  std::vector<std::pair<std::size_t, std::size_t>> cross_;                 // states
  std::vector<std::vector<std::pair<std::size_t, std::size_t>>> cross_R_;  // per channel
  std::vector<std::vector<double>> off_;  // per grid axis: the offsets from the centre
  std::vector<double> centre_, est_;      // per grid axis: the centre, the last estimate
  std::vector<int> slot_;                 // per grid axis: its parameter's symbol
  double elapsed_ = 0.0;
  MatX chain_matrix_;
  std::optional<MarkovChain> moved_;  // this row's chain under the mix reading
  std::size_t mode_skips_ = 0, first_mode_skip_ = 0;
  std::string first_mode_why_;
};

template <int N, class Filter>
Status run_with(Prepared& p, std::vector<Mode> modes, MarkovChain chain, RenewalRun ren,
                const StructureSpec* structure) {
  Imm<N, Filter> imm(p, *p.ctx->spec.modes, std::move(modes), std::move(chain), ren, structure);
  if (auto st = imm.setup(); !st) return st;
  return imm.run();
}

template <int N>
Status run_sized(Prepared& p, std::vector<Mode> modes, MarkovChain chain, RenewalRun ren,
                 const StructureSpec* structure) {
  if (p.ctx->options.kind == FilterKind::kUkf) {
    return run_with<N, UnscentedFilter<N>>(p, std::move(modes), std::move(chain), ren, structure);
  }
  return run_with<N, KalmanFilter<N>>(p, std::move(modes), std::move(chain), ren, structure);
}

// The block filters apply: the Kalman filter (or the EKF, which is the KF on a linear model) of
// linear modes whose Q and R do not depend on the states.
bool blocks_apply(const Prepared& p, const std::vector<Mode>& modes) {
  if (p.ctx->options.kind == FilterKind::kUkf) return false;
  const auto linear = [](const ModelSpec& m) {
    if (m.nonlinear_process() || m.process_noise_at_state()) return false;
    for (const auto& c : m.channels) {
      if (!c.linear || c.R.dep() == Dep::kState) return false;
    }
    return true;
  };
  if (!linear(p.ctx->spec)) return false;
  for (const Mode& m : modes) {
    if (m.model && !linear(*m.model)) return false;
  }
  return true;
}

// x0 from a channel's first sample, evaluated with each grid axis at its centre (seed 001
// converts the first measurement with the grid's centre slope); a list's at the run's values.
Status start_at_centre(Prepared& p, const ModesSpec& ms, const std::vector<Mode>& modes,
                       const ParamValues& values) {
  const ModelSpec& spec = p.ctx->spec;
  if (spec.start_channel < 0) return Ok{};
  if (ms.grid.empty()) return start_from_channel(p, *p.ev);
  ParamValues centre = values;
  for (std::size_t a = 0; a < ms.grid.size(); ++a) {
    double lo = modes.front().grid[a], hi = lo;
    for (const Mode& m : modes) {
      lo = std::min(lo, m.grid[a]);
      hi = std::max(hi, m.grid[a]);
    }
    centre[ms.grid[a].param] = 0.5 * (lo + hi);
  }
  auto ev = ModelEval::create(spec, centre);
  if (!ev) return ev.err();
  const auto& t = *p.data.t;
  const auto first = [&] { return "the interval into step 1 of " + p.data.source; };
  if (auto st = (*ev)->set_dt_at(t[1] - t[0], first); !st) return st;
  return start_from_channel(p, **ev);
}

// Equal ends with several values on an axis (a slider passing through equality, say) make
// identical modes: the run is valid, but the grid cannot tell the values apart.
void warn_equal_ends(const ModesSpec& ms, const ParamValues& v, std::vector<std::string>& out) {
  for (const GridAxisSpec& a : ms.grid) {
    const double lo = a.min.at(v), hi = a.max.at(v), n = a.n.at(v);
    if (lo != hi || n <= 1.0) continue;
    out.push_back(a.min.key + " = " + a.max.key + " = " + number(lo) + " with " + a.n.key + " = " +
                  number(n) + ": the " + number(n) + " values of " + a.param +
                  " are the same, so its estimate cannot move");
  }
}

}  // namespace

Status run_imm(Prepared& p, const ParamValues& values) {
  const ModelSpec& spec = p.ctx->spec;
  const ModesSpec& ms = *spec.modes;
  auto modes = ms.modes(spec, values);
  if (!modes) return modes.err();
  warn_equal_ends(ms, values, p.ctx->r.warnings);
  if (auto st = start_at_centre(p, ms, *modes, values); !st) return st;
  const int r = static_cast<int>(modes->size());
  Expected<MarkovChain> chain = Error{""};
  if (ms.matrix.empty()) {
    chain = MarkovChain::uniform(r, ms.stay.at(values));
    if (!chain) {
      return Error{spec.path + ": " +
                   (ms.stay.key.empty() ? "model.modes.markov.stay" : ms.stay.key) +
                   " must be in (0, 1], got " + number(ms.stay.at(values))};
    }
  } else {
    MatX P(r, r);
    for (int i = 0; i < r; ++i) {
      for (int j = 0; j < r; ++j)
        P(i, j) = ms.matrix[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
    }
    chain = MarkovChain::dense(P);
    if (!chain) return Error{spec.path + ": model.modes.markov.matrix: " + chain.error()};
  }
  RenewalRun ren;
  if (ms.renewal) {
    ren.kp = ms.renewal->gain.at(values);
    ren.start = ms.renewal->start.at(values);
    ren.reading = ms.renewal->at(values);
    ren.on = ren.kp != 0.0;
    if (!(ren.kp >= 0.0 && ren.kp <= 1.0) || !std::isfinite(ren.start)) {
      return Error{spec.path + ": " + ms.renewal->gain.key + " must be in [0, 1] and " +
                   ms.renewal->start.key + " finite"};
    }
  }
  const StructureSpec* st = ms.structure.at(values);
  if (st && blocks_apply(p, *modes)) {  // one small filter per block and mode
    switch (equal_block_size(*st)) {
      case 2:
        return run_with<Eigen::Dynamic, BlockKalman<2>>(p, std::move(*modes), std::move(*chain),
                                                        ren, st);
      case 3:
        return run_with<Eigen::Dynamic, BlockKalman<3>>(p, std::move(*modes), std::move(*chain),
                                                        ren, st);
      default:
        break;
    }
  }
  switch (spec.n()) {
    case 1:
      return run_sized<1>(p, std::move(*modes), std::move(*chain), ren, st);
    case 2:
      return run_sized<2>(p, std::move(*modes), std::move(*chain), ren, st);
    case 3:
      return run_sized<3>(p, std::move(*modes), std::move(*chain), ren, st);
    case 4:
      return run_sized<4>(p, std::move(*modes), std::move(*chain), ren, st);
    case 5:
      return run_sized<5>(p, std::move(*modes), std::move(*chain), ren, st);
    case 6:
      return run_sized<6>(p, std::move(*modes), std::move(*chain), ren, st);
    default:
      return run_sized<Eigen::Dynamic>(p, std::move(*modes), std::move(*chain), ren, st);
  }
}

}  // namespace kfw::model::detail
