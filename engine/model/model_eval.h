// The per-run values of a model's matrices. Entries that depend only on parameters are evaluated
// once, here; those that depend on dt when dt changes (the process matrices from a small cache
// keyed by dt, so an irregular clock that repeats its intervals costs a lookup); those that depend
// on t or inputs once per step; those that depend on states at each linearisation or sigma point.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/expected.h"
#include "core/param_spec.h"
#include "core/types.h"
#include "model/model_spec.h"

namespace kfw::model {

// A number in messages: 10 significant digits, no trailing zeros ("0.02", "1e+08").
std::string number(double v);

// Smallest eigenvalue of a symmetric matrix (NaN when it holds NaN).
double min_eigenvalue(const MatX& M);
// M is symmetric positive semidefinite to rounding (eigenvalues ≥ −1e-12 · scale).
bool is_psd(const MatX& M);

class ModelEval {
 public:
  // Binds the parameters, evaluates what depends on them only and checks P0, Q, R and Qc when
  // they depend on parameters only (an Error, exit 2, naming the key). `every` parameters must
  // hold whole numbers ≥ 1.
  static Expected<std::unique_ptr<ModelEval>> create(const ModelSpec& spec,
                                                     const ParamValues& values);
  ModelEval(const ModelEval&) = delete;
  ModelEval& operator=(const ModelEval&) = delete;

  const ModelSpec& spec() const { return spec_; }
  int n() const { return spec_.n(); }

  void set_time(double t) { vars_[static_cast<std::size_t>(spec_.t_slot)] = t; }
  // A symbol of its own (a world's noise source) by slot.
  void set_symbol(int slot, double v) { vars_[static_cast<std::size_t>(slot)] = v; }
  void set_inputs(const double* u);
  // The inputs' ages (InputSpec::age), per input; entries without an age symbol are ignored.
  void set_input_ages(const double* age);
  void set_state(const double* x);
  // Makes dt current: re-evaluates what depends on it when it differs from the last value.
  // Fails (message without the step) when the discretisation fails or Q is not PSD there.
  Status set_dt(double dt) {
    if (dt == dt_) return Ok{};
    return eval_dt(dt, true);
  }
  // A Q or R that depends on dt must be PSD at every interval a run meets. check_dt: at one dt
  // (`where` names it, e.g. "sim.dt"); set_dt_at: set_dt for the filter's interval into a row of
  // a dataset, checked there (`where()` names it: "the interval into step 7 of log.csv"). An
  // Error (exit 2: the model does not hold for the data) names the file, the key and the dt.
  Status check_dt(double dt, const std::string& where);
  template <class Where>
  Status set_dt_at(double dt, const Where& where) {
    if (dt == dt_) return Ok{};
    return check_at(dt, where);
  }

  // Moves parameters during a run (an IMM's grid under renewal): each slot's value set, what
  // depends on parameters re-evaluated now and what depends on dt at the next set_dt (the
  // process's only when it reads a slot moved: seed 001's slopes move the measurement alone). A
  // Q, Qc or R of parameters only that is then not PSD is an Error naming the key.
  Status set_params(const std::vector<std::pair<int, double>>& values);

  // An IMM's modes that share the process (the same model, the same value of every parameter
  // the process reads): this evaluator takes its discretisations from `source`'s cache when
  // there (seed 001's 49 modes: one Van Loan per interval instead of 49). False: not shared.
  bool share_process(ModelEval& source);

  // The process at the current symbols. step: entries of t and inputs (once per step);
  // f / f_jacobian / noise: what depends on states, at the state set by set_state: fx = f(x) (or
  // the RK4 step of ẋ over dt), F = ∂fx/∂x, Q (or Van Loan of A(x), G Qc Gᵀ over dt).
  void process_step() {
    process_subs_.eval();
    p_step_.eval();
  }
  void process_f() {
    if (rk4_) {
      rk4(false);
    } else {
      f_state_.eval();
    }
  }
  void process_f_jacobian() {
    if (rk4_) {
      rk4(true);
    } else {
      f_state_.eval();
      F_state_.eval();
    }
  }
  void process_noise() {
    if (rk4_) {
      continuous_noise();
    } else {
      Q_state_.eval();
    }
  }
  // Q depends on t, inputs or states: its definiteness is checked where it is evaluated.
  bool process_noise_varies() const { return q_varies_; }

  // A state held within [lo, hi] (a world's limits, issue 30): applied after every RK4 sub-step
  // of the continuous nonlinear process; at a limit the state `rate` (−1: none) is set to 0 where
  // it points further out.
  struct Limit {
    int state = -1, rate = -1;
    double lo = 0.0, hi = 0.0;
  };
  void set_limits(std::vector<Limit> limits) { limits_ = std::move(limits); }
  template <class V>
  static void apply_limits(const std::vector<Limit>& limits, V& x) {
    for (const Limit& l : limits) {
      double& v = x(l.state);
      if (!(v < l.lo || v > l.hi)) continue;
      v = v < l.lo ? l.lo : l.hi;
      if (l.rate >= 0 && x(l.rate) * (v < 0.0 ? -1.0 : 1.0) > 0.0) x(l.rate) = 0.0;
    }
  }

  // Step-level sub-expressions read by state entries (Expr::state_text), one group per nesting
  // level (a group writes its results after evaluating all of them).
  struct StepSubs {
    std::vector<int> slots;  // collected while placing
    std::vector<ExprGroup> levels;
    Status build(const Symbols& symbols, std::vector<double>& vars);
    void eval() {
      for (auto& g : levels)
        g.eval();
    }
  };

  struct Channel {
    MatX H;  // H, or ∂h/∂x at the state set
    MatX R;
    VecX hx;  // h(x) (nonlinear channels)
    VecX zf;  // a pre-processed channel's components at the sample (ChannelSpec::z)
    std::vector<int> column_slots;  // its columns' symbols
    int every = 1;
    double gate_nis = 0.0;    // reject when NIS exceeds this (0: no gate)
    double gate_sigma = 0.0;  // a distance gate d: gate_nis = d² (scalar channels)
    bool R_varies = false;    // R depends on t, inputs or states: checked where evaluated
    bool R_at_state = false;  // R depends on states: evaluated at each linearisation
    bool R_dt = false;        // R depends on dt (and nothing later): checked at each dt
    ExprGroup dt, step, h, H_state, R_state;
    StepSubs subs;
  };
  Channel& channel(std::size_t c) { return channels_[c]; }
  const Channel& channel(std::size_t c) const { return channels_[c]; }
  // Channel c's entries of t and inputs at its sample `z` (the columns read); a pre-processed
  // channel's columns are its symbols, and `z` becomes its components.
  void channel_step(std::size_t c, double* z) {
    Channel& ch = channels_[c];
    for (std::size_t j = 0; j < ch.column_slots.size(); ++j)
      vars_[static_cast<std::size_t>(ch.column_slots[j])] = z[j];
    ch.subs.eval();
    ch.step.eval();
    for (Eigen::Index j = 0; j < ch.zf.size(); ++j)
      z[j] = ch.zf(j);
  }
  void channel_h(std::size_t c) { channels_[c].h.eval(); }
  void channel_jacobian(std::size_t c) { channels_[c].H_state.eval(); }
  void channel_noise(std::size_t c) { channels_[c].R_state.eval(); }

  // A channel group's scheme at the parameters' values, and the noise covariance between two of
  // its members.
  struct Group {
    GroupScheme scheme = GroupScheme::kEach;
    double cross = 0.0;
  };
  const Group& group(std::size_t g) const { return groups_[g]; }

  // Current process matrices: F (or ∂f/∂x), B (n × inputs, or empty), Q; fx = f(x).
  MatX F, B, Q;
  VecX fx;
  // x0 (expressions; the caller replaces entries taken from a column) and P0.
  VecX x0;
  MatX P0;
  // The continuous form, evaluated once (parameters only).
  MatX A, Bc, G, Qc;

  double dt() const { return dt_; }
  // Every expression group, for the native path (expression.h expr_groups_hook).
  std::vector<ExprGroup*> groups();
  // Every symbol's current value, by slot.
  const std::vector<double>& vars() const { return vars_; }

 private:
  explicit ModelEval(const ModelSpec& spec);
  Status bind(const ParamValues& values);
  // After the parameters' entries are evaluated: the distance gates and the groups' schemes.
  Status bind_gates_and_groups(const ParamValues& values);
  // The continuous nonlinear form (model_continuous.cpp): its groups, the RK4 step over dt from
  // the state and time set (restored after), with the exact Jacobian of the step map when asked,
  // and Q by Van Loan at A(x).
  Status bind_continuous(ExprGroup& param);
  Status set_rk4_steps(double dt);
  void rk4(bool jacobian);
  void continuous_noise();
  bool process_reads(int slot);             // a process expression uses this symbol
  std::vector<char> process_slots_;         // per symbol, lazily: read by the process
  Status eval_dt(double dt, bool check_q);  // set_dt, Q checked on evaluation when asked
  Status check_at(double dt, const std::function<std::string()>& where);  // check_dt
  // The key of the first Q or R that depends on dt and is not PSD at the current dt, and the
  // matrix; null when none.
  const MatrixSpec* noise_not_psd(const MatX*& M) const;

  const ModelSpec& spec_;
  std::vector<double> vars_;  // sized once: the muparser groups hold pointers into it
  double dt_;
  std::vector<Channel> channels_;
  std::vector<Group> groups_;
  ExprGroup param_;  // entries of parameters only (bind, set_params)
  ExprGroup p_dt_, p_step_, F_state_, f_state_, Q_state_;
  // Step-level sub-expressions that state entries read by name (Expr::state_text): evaluated by
  // process_step (the process's) and channel_step (the channel's), before the entries.
  StepSubs process_subs_;
  ExprGroup xdot_state_, A_state_;  // continuous nonlinear: ẋ and A = ∂ẋ/∂x at the symbols
  VecX xdot_;
  double substep_ = 0.0;
  std::vector<Limit> limits_;
  // An affine ẋ (ProcessSpec::affine): ∂ẋ/∂u, and the constant c = ẋ − A x − Bu u found at the
  // first stage evaluated (reset when parameters move).
  MatX Bu_;
  VecX c_;
  bool c_ready_ = false;
  void rk4_affine();
  int rk4_steps_ = 1;
  bool rk4_ = false;  // the continuous nonlinear form
  bool q_varies_ = false;
  bool process_dt_ = false;  // the process matrices depend on dt
  bool q_dt_ = false;        // Q depends on dt (and nothing later)

  struct DtEntry {
    double dt;
    MatX F, B, Q;
    VecX fx;
    bool checked = false;  // Q found PSD at this dt (check_at, or set_dt's own check)
  };
  DtEntry* hit_ = nullptr;  // the entry the last eval_dt used or made (null: not cached)
  const ModelEval* process_source_ = nullptr;  // share_process
  void remember(DtEntry e);                    // into cache_, hit_ at it
  bool r_dt_ = false;  // some channel's R depends on dt (checked at every interval)
  std::vector<DtEntry> cache_;
  std::size_t evict_ = 0;
};

}  // namespace kfw::model
