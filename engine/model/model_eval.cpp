#include "model/model_eval.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <unordered_set>

#include "core/limits.h"
#include "core/statistics.h"
#include "filter/discretize.h"

namespace kfw::model {

namespace {

constexpr std::size_t kDtCacheSize = 64;

// Sizes a matrix to its spec (empty specs give empty matrices).
void shape(MatX& M, const MatrixSpec& s) {
  M.setZero(s.rows, s.cols);
}

// Routes one entry to when it is evaluated: a constant is written now; the others join the
// group of their class (state-dependent ones the given `state` group, or `step` when null).
// `subs` (filter groups only): a state or step entry that keeps step-level sub-expressions by
// name is placed as that text, and their slots join `subs` (evaluated once per step, before the
// step group): seed 001's R reads its corrected angles' cosines six times, computed once.
void place(const Expr& e, double* target, ExprGroup& param, ExprGroup& dt, ExprGroup& step,
           ExprGroup* state, std::vector<int>* subs = nullptr) {
  const bool kept = e.dep == Dep::kState ? state != nullptr : e.dep == Dep::kStep;
  if (kept && subs && !e.state_text.empty()) {
    (e.dep == Dep::kState ? *state : step).add(e.state_text, target);
    subs->insert(subs->end(), e.step_subs.begin(), e.step_subs.end());
    return;
  }
  switch (e.dep) {
    case Dep::kConst:
      *target = e.value;
      break;
    case Dep::kParam:
      param.add(e.text, target);
      break;
    case Dep::kDt:
      dt.add(e.text, target);
      break;
    case Dep::kStep:
      step.add(e.text, target);
      break;
    case Dep::kState:
      (state ? *state : step).add(e.text, target);
      break;
  }
}

void place_matrix(const MatrixSpec& s, MatX& M, ExprGroup& param, ExprGroup& dt, ExprGroup& step,
                  ExprGroup* state, std::vector<int>* subs = nullptr) {
  for (int i = 0; i < s.rows; ++i) {
    for (int j = 0; j < s.cols; ++j)
      place(s.at(i, j), &M(i, j), param, dt, step, state, subs);
  }
}

// The continuous forms' noise, parameters only: G (n × q, default I) and Qc.
void place_noise(const ProcessSpec& pr, int n, MatX& G, MatX& Qc, ExprGroup& param) {
  ExprGroup unused;
  if (!pr.G.empty()) {
    shape(G, pr.G);
    place_matrix(pr.G, G, param, unused, unused, nullptr);
  } else {
    G = MatX::Identity(n, n);
  }
  shape(Qc, pr.Qc);
  place_matrix(pr.Qc, Qc, param, unused, unused, nullptr);
}

Status check_psd(const MatX& M, const MatrixSpec& s, const std::string& path, bool definite) {
  const double lo = min_eigenvalue(M);
  if (!M.allFinite()) {
    return Error{path + ": " + s.key + ": not finite at the parameters' values"};
  }
  if (definite ? !(lo > 0.0) : !is_psd(M)) {
    return Error{path + ": " + s.key + ": not positive " +
                 (definite ? "definite" : "semidefinite") +
                 " at the parameters' values (smallest eigenvalue " + number(lo) + ")"};
  }
  return Ok{};
}

}  // namespace

std::string number(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}

double min_eigenvalue(const MatX& M) {
  if (M.size() == 0) return std::numeric_limits<double>::infinity();
  if (!M.allFinite()) return std::numeric_limits<double>::quiet_NaN();
  if (M.rows() == 1) return M(0, 0);
  // A diagonal matrix (the usual Q and R): its eigenvalues are its diagonal. A jittered clock
  // checks Q at every distinct interval, and the eigen-solver was 8 % of a run of seed 004.
  bool diagonal = true;
  for (Eigen::Index j = 0; j < M.cols() && diagonal; ++j) {
    for (Eigen::Index i = 0; i < M.rows(); ++i) {
      if (i != j && M(i, j) != 0.0) {
        diagonal = false;
        break;
      }
    }
  }
  if (diagonal) return M.diagonal().minCoeff();
  Eigen::SelfAdjointEigenSolver<MatX> es(M, Eigen::EigenvaluesOnly);
  return es.eigenvalues().minCoeff();
}

namespace {
// The pivots of M = L D Lᵀ (M symmetric, 2 × 2 or 3 × 3) are all positive: M is positive
// definite.
bool positive_pivots(const MatX& M) {
  const double d1 = M(0, 0);
  if (!(d1 > 0.0)) return false;
  const double l21 = M(1, 0) / d1;
  const double d2 = M(1, 1) - l21 * M(1, 0);
  if (!(d2 > 0.0)) return false;
  if (M.rows() == 2) return true;
  const double l31 = M(2, 0) / d1;
  const double l32 = (M(2, 1) - l31 * M(1, 0)) / d2;
  return M(2, 2) - l31 * M(2, 0) - l32 * l32 * d2 > 0.0;
}
}  // namespace

bool is_psd(const MatX& M) {
  if (M.size() == 0) return true;
  // A diagonal matrix in one pass (a jittered clock checks Q = q² dt I at every row).
  bool diagonal = true;
  double lo = std::numeric_limits<double>::infinity(), scale = 0.0;
  for (Eigen::Index j = 0; j < M.cols() && diagonal; ++j) {
    for (Eigen::Index i = 0; i < M.rows(); ++i) {
      const double v = M(i, j);
      if (i == j) {
        if (!std::isfinite(v)) return false;
        lo = std::min(lo, v);
        scale = std::max(scale, std::abs(v));
      } else if (v != 0.0) {
        diagonal = false;
        break;
      }
    }
  }
  if (diagonal && M.rows() == M.cols()) return lo >= -1e-12 * scale;
  if (!M.allFinite()) return false;
  if (!M.isApprox(M.transpose(), 1e-9) && (M - M.transpose()).cwiseAbs().maxCoeff() > 1e-300) {
    return false;
  }
  // Positive definite (a Cholesky factor exists): PSD without the eigen-solver, which was ~10 %
  // of an IMM whose R depends on the measurement (seed 001's, per mode and row); up to 3 × 3 by
  // the pivots of LDLᵀ written out.
  if (M.rows() <= 3 && positive_pivots(M)) return true;
  if (M.rows() > 3 && Eigen::LLT<MatX>(M).info() == Eigen::Success) return true;
  scale = M.diagonal().cwiseAbs().maxCoeff();
  // Singular but semidefinite (Q = G q Gᵀ of fewer noise inputs than states), checked at every
  // interval of a clock whose dt differs in the last bits: the pivoted LDLᵀ (|L_ij| ≤ 1, so
  // ‖Lᵀx‖ ≤ n‖x‖ and λ_min ≥ n² · min D) settles it without the eigen-solver, which was ≈ 13 %
  // of such a run.
  const Eigen::LDLT<MatX> ldlt(M);
  const double n = static_cast<double>(M.rows());
  if (ldlt.info() == Eigen::Success && ldlt.vectorD().minCoeff() >= -1e-12 * scale / (n * n)) {
    return true;
  }
  return min_eigenvalue(M) >= -1e-12 * scale;
}

Status ModelEval::StepSubs::build(const Symbols& symbols, std::vector<double>& vars) {
  std::sort(slots.begin(), slots.end());
  slots.erase(std::unique(slots.begin(), slots.end()), slots.end());
  // A sub-expression's level: 0, or one above the deepest it reads (those have lower slots).
  std::vector<std::size_t> level(slots.size(), 0);
  for (std::size_t i = 0; i < slots.size(); ++i) {
    const Expr& sub = symbols.subs[static_cast<std::size_t>(slots[i])];
    for (int d : sub.step_subs) {
      const auto at =
          std::lower_bound(slots.begin(), slots.begin() + static_cast<std::ptrdiff_t>(i), d);
      level[i] = std::max(level[i], level[static_cast<std::size_t>(at - slots.begin())] + 1);
    }
    if (level[i] >= levels.size()) levels.resize(level[i] + 1);
    const auto slot = static_cast<std::size_t>(slots[i]);
    levels[level[i]].add(sub.state_text.empty() ? sub.text : sub.state_text, &vars[slot]);
  }
  for (auto& g : levels) {
    if (auto st = g.bind(symbols, vars.data()); !st) return st;
  }
  return Ok{};
}

ModelEval::ModelEval(const ModelSpec& spec)
    : spec_(spec),
      vars_(spec.symbols.names.size(), 0.0),
      dt_(std::numeric_limits<double>::quiet_NaN()) {}

Expected<std::unique_ptr<ModelEval>> ModelEval::create(const ModelSpec& spec,
                                                       const ParamValues& values) {
  std::unique_ptr<ModelEval> ev(new ModelEval(spec));
  if (auto st = ev->bind(values); !st) return st.err();
  if (const auto& hook = expr_groups_hook()) hook(ev->groups(), spec.symbols);
  return ev;
}

std::vector<ExprGroup*> ModelEval::groups() {
  std::vector<ExprGroup*> g{&param_,   &p_dt_,    &p_step_,     &F_state_,
                            &f_state_, &Q_state_, &xdot_state_, &A_state_};
  for (auto& level : process_subs_.levels)
    g.push_back(&level);
  for (auto& c : channels_) {
    for (ExprGroup* e : {&c.dt, &c.step, &c.h, &c.H_state, &c.R_state})
      g.push_back(e);
    for (auto& level : c.subs.levels)
      g.push_back(&level);
  }
  return g;
}

void ModelEval::set_inputs(const double* u) {
  for (std::size_t i = 0; i < spec_.input_slots.size(); ++i)
    vars_[static_cast<std::size_t>(spec_.input_slots[i])] = u[i];
}

void ModelEval::set_input_ages(const double* age) {
  for (std::size_t i = 0; i < spec_.input_age_slots.size(); ++i) {
    const int slot = spec_.input_age_slots[i];
    if (slot >= 0) vars_[static_cast<std::size_t>(slot)] = age[i];
  }
}

void ModelEval::set_state(const double* x) {
  for (std::size_t i = 0; i < spec_.state_slots.size(); ++i)
    vars_[static_cast<std::size_t>(spec_.state_slots[i])] = x[i];
}

Status ModelEval::bind(const ParamValues& values) {
  const ModelSpec& s = spec_;
  const std::string& path = s.path;
  for (std::size_t i = 0; i < s.param_slots.size(); ++i) {
    auto it = values.find(s.param_keys[i]);
    if (it == values.end())
      return Error{path + ": parameter '" + s.param_keys[i] + "' has no value"};
    vars_[static_cast<std::size_t>(s.param_slots[i])] = it->second;
  }
  ExprGroup& param = param_;  // evaluated once, below (again by set_params)
  ExprGroup unused;
  const int n = s.n();

  x0.setZero(n);
  for (int i = 0; i < n; ++i)
    place(s.x0[static_cast<std::size_t>(i)].value, &x0(i), param, unused, unused, nullptr);
  shape(P0, s.P0);
  place_matrix(s.P0, P0, param, unused, unused, nullptr);

  const ProcessSpec& pr = s.process;
  if (pr.form == ProcessForm::kContinuous) {
    shape(A, pr.A);
    place_matrix(pr.A, A, param, unused, unused, nullptr);
    if (!pr.Bc.empty()) {
      shape(Bc, pr.Bc);
      place_matrix(pr.Bc, Bc, param, unused, unused, nullptr);
    }
    place_noise(pr, n, G, Qc, param);
    F.setZero(n, n);
    Q.setZero(n, n);
    if (!pr.Bc.empty()) B.setZero(n, pr.Bc.cols);
    process_dt_ = true;
  } else if (pr.form == ProcessForm::kContinuousNonlinear) {
    if (auto st = bind_continuous(param); !st) return st;
  } else {
    shape(F, pr.F);
    shape(Q, pr.Q);
    if (pr.form == ProcessForm::kLinear) {
      if (!pr.B.empty()) {
        shape(B, pr.B);
        place_matrix(pr.B, B, param, p_dt_, p_step_, nullptr);
      }
      place_matrix(pr.F, F, param, p_dt_, p_step_, nullptr);
    } else {
      fx.setZero(n);
      for (int i = 0; i < n; ++i)
        place(pr.f[static_cast<std::size_t>(i)], &fx(i), param, p_dt_, p_step_, &f_state_,
              &process_subs_.slots);
      place_matrix(pr.F, F, param, p_dt_, p_step_, &F_state_, &process_subs_.slots);
    }
    place_matrix(pr.Q, Q, param, p_dt_, p_step_, &Q_state_, &process_subs_.slots);
    q_varies_ = pr.Q.dep() >= Dep::kStep;
    process_dt_ = !p_dt_.empty();
    q_dt_ = pr.Q.dep() == Dep::kDt;
  }

  channels_.resize(s.channels.size());
  for (std::size_t c = 0; c < s.channels.size(); ++c) {
    const ChannelSpec& cs = s.channels[c];
    Channel& ch = channels_[c];
    shape(ch.H, cs.H);
    shape(ch.R, cs.R);
    if (!cs.linear) {
      ch.hx.setZero(cs.size());
      for (int i = 0; i < cs.size(); ++i)
        place(cs.h[static_cast<std::size_t>(i)], &ch.hx(i), param, ch.dt, ch.step, &ch.h,
              &ch.subs.slots);
    }
    place_matrix(cs.H, ch.H, param, ch.dt, ch.step, &ch.H_state, &ch.subs.slots);
    place_matrix(cs.R, ch.R, param, ch.dt, ch.step, &ch.R_state, &ch.subs.slots);
    if (cs.preprocessed()) {
      ch.zf.setZero(cs.size());
      ch.column_slots = cs.column_slots;
      for (int i = 0; i < cs.size(); ++i)
        place(cs.z[static_cast<std::size_t>(i)], &ch.zf(i), param, ch.dt, ch.step, nullptr,
              &ch.subs.slots);
    }
    ch.R_varies = cs.R.dep() >= Dep::kStep;
    ch.R_at_state = cs.R.dep() == Dep::kState;
    ch.R_dt = cs.R.dep() == Dep::kDt;
    r_dt_ = r_dt_ || ch.R_dt;
    ch.every = cs.every;
    if (!cs.every_param.empty()) {
      const auto it = values.find(cs.every_param);
      const double v = it == values.end() ? std::numeric_limits<double>::quiet_NaN() : it->second;
      if (!(v >= 1.0) || v != std::round(v) || v > limits::kMaxEvery) {
        return Error{path + ": model.measurements." + cs.name + ".every: parameter '" +
                     cs.every_param + "' = " + number(v) + " must be a whole number from 1 to " +
                     number(limits::kMaxEvery) + " (docs/limits.md)"};
      }
      ch.every = static_cast<int>(v);
    }
    if (cs.gate > 0.0) ch.gate_nis = chi2_quantile(cs.gate, cs.size());
    if (!cs.gate_sigma.text.empty())
      place(cs.gate_sigma, &ch.gate_sigma, param, unused, unused, nullptr);
  }
  groups_.resize(s.groups.size());
  for (std::size_t g = 0; g < s.groups.size(); ++g)
    place(s.groups[g].cross, &groups_[g].cross, param, unused, unused, nullptr);

  if (auto st = process_subs_.build(s.symbols, vars_); !st) return st;
  for (auto& ch : channels_) {
    if (auto st = ch.subs.build(s.symbols, vars_); !st) return st;
  }
  // Compile every group against the symbols, then evaluate the parameter-only entries once.
  for (ExprGroup* g :
       {&param_, &p_dt_, &p_step_, &F_state_, &f_state_, &Q_state_, &xdot_state_, &A_state_}) {
    if (auto st = g->bind(s.symbols, vars_.data()); !st) return st;
  }
  for (auto& ch : channels_) {
    for (ExprGroup* g : {&ch.dt, &ch.step, &ch.h, &ch.H_state, &ch.R_state}) {
      if (auto st = g->bind(s.symbols, vars_.data()); !st) return st;
    }
  }
  param.eval();
  if (auto st = bind_gates_and_groups(values); !st) return st;

  if (rk4_ && !(substep_ >= 0.0 && std::isfinite(substep_))) {
    return Error{path + ": model.process.substep: " + number(substep_) +
                 " at the parameters' values; expected a sub-step ≥ 0 s (0: one RK4 step per "
                 "interval)"};
  }
  if (auto st = check_psd(P0, s.P0, path, false); !st) return st;
  if (pr.form == ProcessForm::kContinuous || rk4_) {
    if (auto st = check_psd(Qc, pr.Qc, path, false); !st) return st;
  } else if (pr.Q.dep() <= Dep::kParam) {
    if (auto st = check_psd(Q, pr.Q, path, false); !st) return st;
  }
  for (std::size_t c = 0; c < s.channels.size(); ++c) {
    if (s.channels[c].R.dep() <= Dep::kParam) {
      if (auto st = check_psd(channels_[c].R, s.channels[c].R, path, false); !st) return st;
    }
  }
  return Ok{};
}

Status ModelEval::bind_continuous(ExprGroup& param) {
  const ProcessSpec& pr = spec_.process;
  const int n = spec_.n();
  rk4_ = true;
  q_varies_ = true;  // Q follows A(x): refactorised every step in simulation
  ExprGroup unused;
  // ẋ and A are evaluated at each RK4 stage's state and time: entries of t, inputs or states
  // all join the stage groups.
  xdot_.setZero(n);
  for (int i = 0; i < n; ++i)
    place(pr.f[static_cast<std::size_t>(i)], &xdot_(i), param, unused, xdot_state_, &xdot_state_);
  shape(A, pr.A);
  place_matrix(pr.A, A, param, unused, A_state_, &A_state_);
  if (pr.affine) {
    shape(Bu_, pr.Bu);
    place_matrix(pr.Bu, Bu_, param, unused, unused, nullptr);
  }
  place_noise(pr, n, G, Qc, param);
  place(pr.substep, &substep_, param, unused, unused, nullptr);
  fx.setZero(n);
  F.setZero(n, n);
  Q.setZero(n, n);
  return Ok{};
}

Status ModelEval::check_dt(double dt, const std::string& where) {
  return check_at(dt, [&] { return where; });
}

Status ModelEval::check_at(double dt, const std::function<std::string()>& where) {
  const auto at = [&] { return " at dt = " + number(dt) + " s (" + where() + ")"; };
  if (auto st = eval_dt(dt, false); !st) return Error{st.error() + at()};
  // A cached interval whose matrices were checked (an irregular time column repeats a few
  // intervals: seed 001's 0.05 s takes 11 values over 1 200 rows), unless an R depends on dt.
  if (hit_ && hit_->checked && !r_dt_) return Ok{};
  const MatX* M = nullptr;
  if (const MatrixSpec* s = noise_not_psd(M)) {
    if (!M->allFinite()) return Error{spec_.path + ": " + s->key + ": not finite" + at()};
    return Error{spec_.path + ": " + s->key + ": not positive semidefinite" + at() +
                 " (smallest eigenvalue " + number(min_eigenvalue(*M)) + ")"};
  }
  if (hit_) hit_->checked = true;
  return Ok{};
}

const MatrixSpec* ModelEval::noise_not_psd(const MatX*& M) const {
  const ProcessSpec& pr = spec_.process;
  if ((pr.form == ProcessForm::kContinuous || q_dt_) && !is_psd(Q)) {
    M = &Q;
    return pr.form == ProcessForm::kContinuous ? &pr.Qc : &pr.Q;
  }
  for (std::size_t c = 0; c < channels_.size(); ++c) {
    if (channels_[c].R_dt && !is_psd(channels_[c].R)) {
      M = &channels_[c].R;
      return &spec_.channels[c].R;
    }
  }
  return nullptr;
}

bool ModelEval::process_reads(int slot) {
  if (process_slots_.empty()) {
    process_slots_.assign(spec_.symbols.names.size(), 0);
    const ProcessSpec& pr = spec_.process;
    const auto mark = [&](const Expr& e) {
      for (int used : symbols_used(e.text, spec_.symbols))
        process_slots_[static_cast<std::size_t>(used)] = 1;
    };
    for (const MatrixSpec* m : {&pr.F, &pr.B, &pr.Q, &pr.A, &pr.Bc, &pr.G, &pr.Qc}) {
      for (const Expr& e : m->e)
        mark(e);
    }
    for (const Expr& e : pr.f)
      mark(e);
    mark(pr.substep);
  }
  return process_slots_[static_cast<std::size_t>(slot)] != 0;
}

Status ModelEval::set_params(const std::vector<std::pair<int, double>>& values) {
  bool process = false;
  for (const auto& [slot, v] : values) {
    vars_[static_cast<std::size_t>(slot)] = v;
    process = process || process_reads(slot);
  }
  param_.eval();
  c_ready_ = false;
  if (process) {
    process_source_ = nullptr;  // this mode's process moved away from the source's
    cache_.clear();
    hit_ = nullptr;
    evict_ = 0;
    dt_ = std::numeric_limits<double>::quiet_NaN();  // what depends on dt: at the next set_dt
  } else {
    for (auto& ch : channels_)  // the process keeps its matrices (and its cache)
      ch.dt.eval();
  }
  const ModelSpec& s = spec_;
  const ProcessSpec& pr = s.process;
  if (pr.form == ProcessForm::kContinuous || rk4_) {
    if (auto st = check_psd(Qc, pr.Qc, s.path, false); !st) return st;
  } else if (pr.Q.dep() <= Dep::kParam) {
    if (auto st = check_psd(Q, pr.Q, s.path, false); !st) return st;
  }
  for (std::size_t c = 0; c < s.channels.size(); ++c) {
    if (s.channels[c].R.dep() <= Dep::kParam) {
      if (auto st = check_psd(channels_[c].R, s.channels[c].R, s.path, false); !st) return st;
    }
  }
  return Ok{};
}

Status ModelEval::eval_dt(double dt, bool check_q) {
  if (dt == dt_) return Ok{};
  hit_ = nullptr;
  dt_ = dt;
  vars_[static_cast<std::size_t>(spec_.dt_slot)] = dt;
  for (auto& ch : channels_)
    ch.dt.eval();
  if (rk4_) return set_rk4_steps(dt);
  if (!process_dt_) return Ok{};
  const ProcessSpec& pr = spec_.process;
  if (pr.form != ProcessForm::kContinuous) {
    // A few expressions: evaluated, not cached (a jittered clock's intervals all differ, and
    // copying the matrices into the cache cost more than the expressions).
    p_dt_.eval();
    if (check_q && q_dt_ && !is_psd(Q)) {
      return Error{"model.process.Q is not positive semidefinite at dt = " + number(dt) +
                   " (smallest eigenvalue " + number(min_eigenvalue(Q)) + ")"};
    }
    return Ok{};
  }
  for (auto& e : cache_) {
    if (e.dt == dt) {
      F = e.F;
      B = e.B;
      Q = e.Q;
      fx = e.fx;
      hit_ = &e;
      return Ok{};
    }
  }
  if (process_source_) {
    for (const auto& e : process_source_->cache_) {
      if (e.dt != dt) continue;
      F = e.F;
      B = e.B;
      Q = e.Q;
      fx = e.fx;
      remember(e);
      return Ok{};
    }
  }
  auto d = van_loan(A, Bc, G, Qc, dt);
  if (!d) return Error{spec_.path + ": model.process: " + d.error()};
  F = d->F;
  Q = d->Q;
  if (B.size()) B = d->Gamma;
  if (check_q) {
    if (!is_psd(Q)) {
      return Error{"model.process.Q is not positive semidefinite at dt = " + number(dt) +
                   " (smallest eigenvalue " + number(min_eigenvalue(Q)) + ")"};
    }
  }
  remember(DtEntry{dt, F, B, Q, fx, check_q});
  return Ok{};
}

void ModelEval::remember(DtEntry e) {
  if (cache_.size() < kDtCacheSize) {
    cache_.reserve(kDtCacheSize);  // hit_ points into it
    cache_.push_back(std::move(e));
    hit_ = &cache_.back();
  } else {
    cache_[evict_] = std::move(e);
    hit_ = &cache_[evict_];
    evict_ = (evict_ + 1) % kDtCacheSize;
  }
}

bool ModelEval::share_process(ModelEval& source) {
  if (&source.spec_ != &spec_ || spec_.process.form != ProcessForm::kContinuous) return false;
  for (std::size_t slot = 0; slot < vars_.size(); ++slot) {
    if (process_reads(static_cast<int>(slot)) && vars_[slot] != source.vars_[slot]) return false;
  }
  process_source_ = &source;
  return true;
}

}  // namespace kfw::model
