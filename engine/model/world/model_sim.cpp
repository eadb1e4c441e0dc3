#include "model/world/model_sim.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <sstream>

#include "core/limits.h"
#include "core/random.h"
#include "filter/angle.h"
#include "model/model_eval.h"
#include "model/world/model_world_noise.h"
#include "model/world/simulation.h"

namespace kfw::model {

bool psd_sqrt(const MatX& M, MatX& L) {
  if (M.size() == 0) {
    L.resize(0, 0);
    return true;
  }
  if (!M.allFinite()) return false;
  // A diagonal covariance: each component scales its own draw, a zero variance too (a singular
  // diagonal R or Q would otherwise go to the eigen square root, which permutes the draws).
  if (MatX(M.diagonal().asDiagonal()) == M) {
    if ((M.diagonal().array() < 0.0).any()) return false;
    L = M.diagonal().cwiseSqrt().asDiagonal();
    return true;
  }
  Eigen::LLT<MatX> llt(M);
  if (llt.info() == Eigen::Success) {
    L = llt.matrixL();
    return true;
  }
  if (!is_psd(M)) return false;
  Eigen::SelfAdjointEigenSolver<MatX> es(M);
  L = es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
  return true;
}

namespace {

// The doubles a row of a run holds: the simulated dataset's columns (time, inputs, sensor
// components, truth, outlier flags) and the filter's results (x, P's upper triangle, NEES; per
// channel y, S, K, NIS, log det S).
std::size_t doubles_per_row(const ModelSpec& s) {
  const std::size_t n = s.states.size();
  std::size_t c = 2 + s.inputs.size() + 2 * n + n * (n + 1) / 2 + 1;
  for (const auto& ch : s.channels) {
    const auto m = static_cast<std::size_t>(ch.size());
    c += m + 1 + m * (2 + n) + 2;
  }
  return c;
}
// "N rows; a simulation of this model may have at most M here (...)", for messages.
std::string too_many_rows(std::size_t rows, std::size_t max_rows, const ModelSpec& s) {
  return std::to_string(rows) + " rows; a simulation of this model may have at most " +
         std::to_string(max_rows) + " here (a quarter of the " +
         limits::bytes_text(limits::memory_bytes()) + " memory limit at " +
         std::to_string(8 * doubles_per_row(s)) + " bytes a row; docs/limits.md)";
}

// Instants closer than this are one: two rows, or a row and a grid step (a tick rounded to 1 µs
// whose k·dt differs from it in the last bit).
constexpr double kSameInstant = 1e-9;

}  // namespace

namespace detail {

VecX Simulation::draw(RandomStream& r, Eigen::Index m) {
  VecX v(m);
  for (Eigen::Index i = 0; i < m; ++i)
    v(i) = quiet_ ? 0.0 : r.normal();
  return v;
}

Simulation::Simulation(const ModelSpec& spec, ModelEval& ev, double dt, std::uint64_t seed,
                       std::size_t max_rows, bool quiet)
    : max_rows_(max_rows),
      spec_(spec),
      ev_(ev),
      dt_(dt),
      seed_(seed),
      quiet_(quiet),
      vars_(ev.vars()),
      x0_(seed, "x0"),
      process_(seed, "process") {
  for (const auto& c : spec.channels) {
    channel_streams_.emplace_back(seed, "channel." + c.name);
    dropout_streams_.emplace_back(seed, "dropout." + c.name);
    burst_streams_.emplace_back(seed, "burst." + c.name);
    impulse_streams_.emplace_back(seed, "impulse." + c.name);
  }
}

Error Simulation::fail(double t, const std::string& what) const {
  std::ostringstream os;
  os << "simulation, step " << j_ << " (t = " << t << " s): " << what;
  return failure(os.str());
}

// Each sensor's clock this run: its own, or the one its choice parameter selects.
Status Simulation::select_clocks() {
  for (const auto& c : spec_.channels) {
    const SensorSpec& s = c.sensor;
    sensor_clock_.push_back(s.clock);
    if (s.clock_by_choice.empty()) continue;
    const std::string key = "model.world.measurements." + c.name + ".clock.param";
    auto v = detail::param_value(s.clock_choice, spec_, vars_, key);
    if (!v) return v.err();
    const auto n = static_cast<double>(s.clock_by_choice.size());
    if (!(*v >= 0.0 && *v < n) || *v != std::round(*v)) {
      return Error{spec_.path + ": " + key + ": " + std::to_string(*v) +
                   " is not one of the parameter's choices"};
    }
    sensor_clock_.back() = s.clock_by_choice[static_cast<std::size_t>(*v)];
  }
  return Ok{};
}

Status Simulation::prepare(double duration, std::size_t grid_rows) {
  // Inputs: their simulation expressions of t, bound to a copy of the symbols.
  u_.assign(spec_.inputs.size(), 0.0);
  for (std::size_t i = 0; i < spec_.inputs.size(); ++i)
    input_sim_.add(spec_.inputs[i].sim.text, &u_[i]);
  if (auto st = input_sim_.bind(spec_.symbols, vars_.data()); !st) return st;
  auto noise = detail::NoiseSources::create(spec_, vars_, seed_, dt_, duration, max_rows_);
  if (!noise) return noise.err();
  noise_ = std::move(*noise);
  for (const auto& c : spec_.channels) {
    auto p = detail::param_value(c.sensor.dropout, spec_, vars_,
                                 "model.world.measurements." + c.name + ".dropout");
    if (!p) return p.err();
    if (!(*p >= 0.0 && *p <= 1.0)) {
      return Error{spec_.path + ": model.world.measurements." + c.name +
                   ".dropout: expected a probability in [0, 1]"};
    }
    dropout_.push_back(*p);
  }
  if (auto st = select_clocks(); !st) return st;
  // The grid's rows (when a sensor samples on it) and the ticks of the clocks in use, merged.
  const bool grid = spec_.clocks.empty() || std::any_of(sensor_clock_.begin(), sensor_clock_.end(),
                                                        [](int c) { return c < 0; });
  std::vector<std::pair<double, long long>> times;  // (t, clock or −1 for the grid)
  if (grid) {
    for (std::size_t j = 0; j < grid_rows; ++j)
      times.emplace_back(static_cast<double>(j) * dt_, -1);
  }
  for (std::size_t c = 0; c < spec_.clocks.size(); ++c) {
    if (std::find(sensor_clock_.begin(), sensor_clock_.end(), static_cast<int>(c)) ==
        sensor_clock_.end()) {
      continue;  // no sensor samples on it this run: it adds no rows
    }
    auto ticks = detail::clock_ticks(spec_.clocks[c], spec_, vars_, seed_, duration, max_rows_);
    if (!ticks) return ticks.err();
    for (double t : *ticks)
      times.emplace_back(t, static_cast<long long>(c));
  }
  if (times.size() > max_rows_) {
    return Error{spec_.path + ": sim.duration: " + too_many_rows(times.size(), max_rows_, spec_)};
  }
  std::stable_sort(times.begin(), times.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  clock_rows_.assign(spec_.clocks.size(), {});
  for (const auto& [t, clock] : times) {
    // Instants closer than 1 ns are one row (a tick rounded to 1 ms meets the grid's k·dt).
    if (row_t_.empty() || t - row_t_.back() > kSameInstant) {
      row_t_.push_back(t);
      row_grid_.push_back(-1);
      for (auto& rows : clock_rows_)
        rows.push_back(false);
    }
    if (clock < 0) {
      row_t_.back() = t;  // a grid row keeps the grid's time, where the process stepped
      row_grid_.back() = std::llround(t / dt_);
    } else {
      clock_rows_[static_cast<std::size_t>(clock)].back() = true;
    }
  }
  if (row_t_.size() < 2) {
    return Error{spec_.path + ": model.world.clocks: the sensors' clocks tick " +
                 std::to_string(row_t_.size()) +
                 " time(s) within sim.duration; a run needs two rows (a shorter period, or a "
                 "longer duration)"};
  }
  Lr_.resize(spec_.channels.size());
  lr_valid_.assign(spec_.channels.size(), false);
  samples_.assign(spec_.channels.size(), {});
  return prepare_loop_keys();
}

void Simulation::inputs_at(double t) {
  noise_->at_time(t);
  vars_[static_cast<std::size_t>(spec_.t_slot)] = t;
  if (!quiet_) noise_->write(vars_.data());
  for (const auto& n : spec_.noise)
    ev_.set_symbol(n.slot, vars_[static_cast<std::size_t>(n.slot)]);
  input_sim_.eval();
  for (std::size_t i = 0; i < is_driven_.size(); ++i) {
    if (is_driven_[i]) u_[i] = driven_[i];
  }
}

Expected<VecX> Simulation::mean_step(double dt, double t_end) {
  const double tj = static_cast<double>(j_) * dt_;
  inputs_at(tj);
  if (auto st = ev_.set_dt(dt); !st) return fail(t_end, st.error());
  ev_.set_time(tj);
  ev_.set_inputs(u_.data());
  ev_.process_step();
  ev_.set_state(x_.data());
  if (spec_.nonlinear_process()) {
    ev_.process_f();
    return VecX(ev_.fx);
  }
  VecX next = ev_.F * x_;
  // B is optional: inputs a model's process does not read (a world's attitude signals, say).
  for (std::size_t i = 0; i < u_.size() && ev_.B.cols() > 0; ++i)
    next += ev_.B.col(static_cast<Eigen::Index>(i)) * u_[i];
  return next;
}

void Simulation::wrap_angles(VecX& x) const {
  for (int i = 0; i < spec_.n(); ++i)
    x(i) = wrap(x(i), spec_.states[static_cast<std::size_t>(i)].angle);
}

Status Simulation::grid_step() {
  // x_{j+1} = F x_j + B u_j (or f) + w, w ~ N(0, Q), with the noise sources of step j.
  const double t_next = static_cast<double>(j_ + 1) * dt_;
  auto next = mean_step(dt_, t_next);
  if (!next) return next.err();
  ev_.process_noise();
  if (!lq_valid_ || ev_.process_noise_varies()) {
    if (!psd_sqrt(ev_.Q, Lq_)) return fail(t_next, "model.process.Q is not positive semidefinite");
    lq_valid_ = true;
  }
  // A process that no noise enters (Q of zeros, or G Qc Gᵀ = 0) draws nothing: its stream feeds
  // only this noise, so the numbers it would draw are never seen.
  x_ = quiet_process_ ? std::move(*next) : VecX(*next + Lq_ * draw(process_, spec_.n()));
  apply_limits(x_);
  wrap_angles(x_);
  ++j_;
  if (!x_.allFinite()) return fail(t_next, "the simulated state is not finite");
  noise_->step(j_);
  return Ok{};
}

Status Simulation::state_at(double t) {
  while (static_cast<double>(j_ + 1) * dt_ <= t + kSameInstant) {
    if (auto st = grid_step(); !st) return st;
  }
  const double tj = static_cast<double>(j_) * dt_;
  row_x_ = x_;
  if (std::fabs(t - tj) <= kSameInstant) return Ok{};
  // Between grid steps: the mean process from t_j over t − t_j, the inputs and white noise
  // held at their values of step j.
  auto x = mean_step(t - tj, t);
  if (!x) return x.err();
  row_x_ = std::move(*x);
  apply_limits(row_x_);
  wrap_angles(row_x_);
  return Ok{};
}

Status Simulation::sample(std::size_t c, std::size_t row, double t, Dataset& d) {
  // z = h(x) + v (or H x + v), v ~ N(0, R); lost with the sensor's dropout probability.
  const ChannelSpec& cs = spec_.channels[c];
  auto& ch = ev_.channel(c);
  ev_.channel_step(c, nullptr);  // a sensor is never pre-processed
  ev_.channel_noise(c);
  VecX z;
  if (cs.linear) {
    z = ch.H * row_x_;
  } else {
    ev_.channel_h(c);
    z = ch.hx;
  }
  if (!lr_valid_[c] || ch.R_varies) {
    if (!psd_sqrt(ch.R, Lr_[c])) return fail(t, cs.R.key + " is not positive semidefinite");
    lr_valid_[c] = true;
  }
  if (!quiet_sensor_[c]) z += Lr_[c] * draw(channel_streams_[c], cs.size());
  ++sampled_[c];
  if (cs.sensor.impulses) {
    const bool hit = impulse(c, row, d);
    impulsive_[c] += hit ? 1 : 0;
    if (impulses_[c].flag_col >= 0)
      d.columns[static_cast<std::size_t>(impulses_[c].flag_col)][row] = hit ? 0.0 : 1.0;
    if (hit) {
      samples_[c].push_back({row, c});
      return Ok{};
    }
  } else if (dropout_streams_[c].uniform() < dropout_[c] && !quiet_) {
    // One uniform per sample from "dropout.NAME": below the probability, the sample is lost.
    return Ok{};
  }
  for (std::size_t i = 0; i < static_cast<std::size_t>(cs.size()); ++i) {
    d.columns[role_col_[c] + i][row] = wrap(z(static_cast<Eigen::Index>(i)), cs.roles[i].angle);
  }
  samples_[c].push_back({row, c});
  return Ok{};
}

void Simulation::set_row(double t) {
  inputs_at(t);
  ev_.set_time(t);
  ev_.set_inputs(u_.data());
  ev_.set_state(row_x_.data());
  for (int i = 0; i < spec_.n(); ++i)
    vars_[static_cast<std::size_t>(spec_.state_slots[static_cast<std::size_t>(i)])] = row_x_(i);
  for (std::size_t i = 0; i < u_.size(); ++i)
    vars_[static_cast<std::size_t>(spec_.input_slots[i])] = u_[i];
}

Status Simulation::add_outliers(Dataset& d) {
  std::map<std::string, std::vector<std::size_t>> groups;  // group -> its channels
  for (std::size_t c = 0; c < spec_.channels.size(); ++c) {
    if (spec_.channels[c].sensor.outliers)
      groups[spec_.channels[c].sensor.outlier_group].push_back(c);
  }
  for (const auto& [group, channels] : groups) {
    const SensorSpec& s = spec_.channels[channels.front()].sensor;
    const std::string key = "model.world.measurements." + spec_.channels[channels.front()].name;
    auto amount = detail::param_value(s.outlier_amount, spec_, vars_, key + ".outliers");
    if (!amount) return amount.err();
    auto size = detail::param_value(s.outlier_size, spec_, vars_, key + ".outliers.size");
    if (!size) return size.err();
    const bool whole = *amount >= 0.0 && std::floor(*amount) == *amount;
    if (s.outlier_count ? !whole : !(*amount >= 0.0 && *amount <= 1.0)) {
      return Error{spec_.path + ": " + key + ".outliers: " +
                   (s.outlier_count ? "count must be a whole number ≥ 0"
                                    : "rate must be a probability in [0, 1]")};
    }
    std::vector<detail::Sample> samples;
    for (std::size_t c : channels)
      samples.insert(samples.end(), samples_[c].begin(), samples_[c].end());
    std::sort(samples.begin(), samples.end(), [](const auto& a, const auto& b) {
      return a.row != b.row ? a.row < b.row : a.channel < b.channel;
    });
    for (std::size_t c : channels) {
      const std::string& col = spec_.channels[c].sensor.outlier_column;
      if (col.empty()) continue;
      auto& column = d.columns[static_cast<std::size_t>(d.index(col))];
      for (const auto& smp : samples_[c])
        column[smp.row] = 0.0;
    }
    for (const auto& o :
         detail::draw_outliers(std::move(samples), s.outlier_count, *amount, *size, seed_, group)) {
      const ChannelSpec& cs = spec_.channels[o.sample.channel];
      for (std::size_t i = 0; i < cs.roles.size(); ++i) {
        double& z = d.columns[role_col_[o.sample.channel] + i][o.sample.row];
        z = wrap(z + o.offset, cs.roles[i].angle);
      }
      if (!cs.sensor.outlier_column.empty()) {
        d.columns[static_cast<std::size_t>(d.index(cs.sensor.outlier_column))][o.sample.row] =
            o.offset;
      }
    }
  }
  return Ok{};
}

Status Simulation::begin(Dataset& d, const std::string& source) {
  const std::size_t rows = row_t_.size();
  d = Dataset{};
  d.source = source;
  d.add("t", rows);
  for (std::size_t r = 0; r < rows; ++r)
    d.columns[0][r] = row_t_[r];
  for (const auto& in : spec_.inputs)
    d.add(in.name, rows);
  for (const auto& c : spec_.channels) {
    role_col_.push_back(d.names.size());
    for (const auto& r : c.roles)
      d.add(r.name, rows);
  }
  for (const auto& col : spec_.truth) {
    truth_col_.push_back(d.names.size());
    if (!col.empty()) d.add(col, rows);
  }
  expr_col_ = d.names.size();
  truth_values_.assign(spec_.truth_exprs.size(), 0.0);
  for (std::size_t i = 0; i < spec_.truth_exprs.size(); ++i) {
    d.add(spec_.truth_exprs[i].first, rows);
    truth_exprs_.add(spec_.truth_exprs[i].second.text, &truth_values_[i]);
  }
  if (auto st = truth_exprs_.bind(spec_.symbols, vars_.data()); !st) return st;
  for (std::size_t c = 0; c < spec_.channels.size(); ++c) {
    const SensorSpec& s = spec_.channels[c].sensor;
    for (const std::string* col : {&s.outlier_column, &s.impulse_flag}) {
      if (!col->empty() && !d.has(*col)) d.add(*col, rows);
    }
    if (!s.impulse_flag.empty()) impulses_[c].flag_col = d.index(s.impulse_flag);
  }
  if (auto st = ev_.set_dt(dt_); !st) return fail(0.0, st.error());
  MatX L;
  if (!psd_sqrt(ev_.P0, L)) return Error{spec_.path + ": model.P0: not positive semidefinite"};
  x_ = ev_.x0 + L * draw(x0_, spec_.n());
  apply_limits(x_);
  noise_->step(0);
  return Ok{};
}

Status Simulation::row(std::size_t r, Dataset& d) {
  const double t = row_t_[r];
  if (auto st = state_at(t); !st) return st;
  set_row(t);
  for (std::size_t i = 0; i < u_.size(); ++i)
    d.columns[1 + i][r] = u_[i];
  for (std::size_t c = 0; c < spec_.channels.size(); ++c) {
    const int clock = sensor_clock_[c];
    const bool due = clock >= 0 ? clock_rows_[static_cast<std::size_t>(clock)][r]
                                : row_grid_[r] >= 0 && row_grid_[r] % ev_.channel(c).every == 0;
    if (!due) continue;
    if (auto st = sample(c, r, t, d); !st) return st;
  }
  for (int i = 0; i < spec_.n(); ++i) {
    if (!spec_.truth[static_cast<std::size_t>(i)].empty()) {
      d.columns[truth_col_[static_cast<std::size_t>(i)]][r] = row_x_(i);
    }
  }
  truth_exprs_.eval();
  for (std::size_t i = 0; i < truth_values_.size(); ++i)
    d.columns[expr_col_ + i][r] = truth_values_[i];
  return Ok{};
}

Status Simulation::finish(Dataset& d) {
  return quiet_ ? Ok{} : add_outliers(d);
}

Expected<Dataset> Simulation::run(const std::string& source) {
  Dataset d;
  if (auto st = begin(d, source); !st) return st.err();
  for (std::size_t r = 0; r < row_t_.size(); ++r) {
    if (auto st = row(r, d); !st) return st.err();
  }
  if (auto st = finish(d); !st) return st.err();
  return d;
}

void Simulation::drive(std::size_t input, double value) {
  if (driven_.size() != u_.size()) {
    driven_.assign(u_.size(), 0.0);
    is_driven_.assign(u_.size(), 0);
  }
  driven_[input] = value;
  is_driven_[input] = 1;
}

int Simulation::event_now(double t) {
  if (events_.empty()) return -1;
  events_.eval();
  int ends = -1;
  for (std::size_t e = 0; e < event_values_.size(); ++e) {
    if (!(event_values_[e] > 0.0)) continue;
    if (std::isnan(first_at_[e])) first_at_[e] = t;
    if (ends < 0 && spec_.events[e].ends) ends = static_cast<int>(e);
  }
  return ends;
}

void Simulation::apply_limits(VecX& x) const {
  if (!limits_.empty()) ModelEval::apply_limits(limits_, x);
}

// Sensor c's sample at `row` is impulsive: one uniform per sample from "dropout.NAME" (outside a
// burst, below the rate a burst starts), one per burst from "burst.NAME" for its length, one per
// role and impulsive sample from "impulse.NAME" for the reading.
bool Simulation::impulse(std::size_t c, std::size_t row, Dataset& d) {
  Impulses& im = impulses_[c];
  const double u = dropout_streams_[c].uniform();
  if (quiet_) return false;
  if (im.left == 0 && u < im.rate) {
    const double b = burst_streams_[c].uniform();
    const double extra = im.log_stay < 0.0 ? std::floor(std::log(b) / im.log_stay) : 0.0;
    im.left = 1 + static_cast<std::size_t>(std::min(extra, static_cast<double>(max_rows_)));
  }
  if (im.left == 0) return false;
  --im.left;
  const ChannelSpec& cs = spec_.channels[c];
  for (std::size_t i = 0; i < cs.roles.size(); ++i) {
    const double v = im.lo + (im.hi - im.lo) * impulse_streams_[c].uniform();
    d.columns[role_col_[c] + i][row] = wrap(v, cs.roles[i].angle);
  }
  return true;
}

// The world's closed-loop keys at the run's parameters: impulses, limits, events.
Status Simulation::prepare_loop_keys() {
  const auto zeros = [](const MatrixSpec& m) {
    return !m.empty() && std::all_of(m.e.begin(), m.e.end(), [](const Expr& e) {
      return e.dep == Dep::kConst && e.value == 0.0;
    });
  };
  const ProcessSpec& pr = spec_.process;
  const bool continuous =
      pr.form == ProcessForm::kContinuous || pr.form == ProcessForm::kContinuousNonlinear;
  quiet_process_ = continuous ? zeros(pr.Qc) || zeros(pr.G) : zeros(pr.Q);
  for (const auto& c : spec_.channels)
    quiet_sensor_.push_back(zeros(c.R));
  impulses_.assign(spec_.channels.size(), {});
  impulsive_.assign(spec_.channels.size(), 0);
  sampled_.assign(spec_.channels.size(), 0);
  for (std::size_t c = 0; c < spec_.channels.size(); ++c) {
    const SensorSpec& s = spec_.channels[c].sensor;
    if (!s.impulses) continue;
    const std::string key = "model.world.measurements." + spec_.channels[c].name + ".impulses";
    Impulses& im = impulses_[c];
    for (auto [field, e, k] :
         {std::tuple{&im.rate, &s.impulse_rate, ".rate"}, std::tuple{&im.lo, &s.impulse_lo, ".min"},
          std::tuple{&im.hi, &s.impulse_hi, ".max"}}) {
      auto v = param_value(*e, spec_, vars_, key + k);
      if (!v) return v.err();
      *field = *v;
    }
    auto burst = param_value(s.impulse_burst, spec_, vars_, key + ".burst");
    if (!burst) return burst.err();
    if (!(im.rate >= 0.0 && im.rate <= 1.0) || !(*burst >= 1.0) || !(im.lo <= im.hi)) {
      return Error{spec_.path + ": " + key +
                   ": expected a rate in [0, 1], a mean burst ≥ 1 sample and min ≤ max"};
    }
    im.log_stay = *burst > 1.0 ? std::log(1.0 - 1.0 / *burst) : 0.0;
  }
  for (const auto& l : spec_.limits) {
    const std::string key =
        "model.world.limits." + spec_.states[static_cast<std::size_t>(l.state)].name;
    auto lo = param_value(l.lo, spec_, vars_, key + ".min");
    if (!lo) return lo.err();
    auto hi = param_value(l.hi, spec_, vars_, key + ".max");
    if (!hi) return hi.err();
    if (!(*lo <= *hi)) return Error{spec_.path + ": " + key + ": min is above max"};
    limits_.push_back({l.state, l.rate, *lo, *hi});
  }
  ev_.set_limits(limits_);
  event_values_.assign(spec_.events.size(), 0.0);
  first_at_.assign(spec_.events.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t e = 0; e < spec_.events.size(); ++e)
    events_.add(spec_.events[e].when.text, &event_values_[e]);
  return events_.bind(spec_.symbols, vars_.data());
}

}  // namespace detail

namespace detail {

Expected<PreparedSimulation> prepare_simulation(const ModelSpec& spec, const ParamValues& values,
                                                const std::string& name, bool quiet) {
  for (const auto& c : spec.channels) {
    if (c.preprocessed()) {
      return Error{spec.path + ": model.measurements." + c.name +
                   ".z: a model that pre-processes its measurements cannot simulate them; "
                   "declare a world (model.world) or give data"};
    }
  }
  const double seed = param(values, "sim.seed");
  const double duration = param(values, "sim.duration");
  const std::string& dt_key = spec.sim_dt_key;
  const double dt = param(values, dt_key);
  if (!(dt > 0.0) || !(duration >= 0.0)) {
    return Error{dt_key + " must be positive and sim.duration not negative"};
  }
  // Samples at 0, dt, ... up to the duration, and at least two: a filter needs one step (a
  // duration shorter than dt, both inside their ranges, still gives a run).
  const auto rows =
      std::max<std::size_t>(static_cast<std::size_t>(std::floor(duration / dt + 1e-9)) + 1, 2);
  const std::size_t max_rows = limits::max_sim_rows(doubles_per_row(spec));
  if (rows > max_rows) {
    return Error{spec.path + ": sim.duration / " + dt_key + ": " +
                 too_many_rows(rows, max_rows, spec)};
  }
  PreparedSimulation out;
  auto evr = ModelEval::create(spec, values);
  if (!evr) return evr.err();
  out.ev = std::move(*evr);
  if (auto st = out.ev->check_dt(dt, dt_key); !st) return st.err();
  out.sim = std::make_unique<Simulation>(spec, *out.ev, dt, static_cast<std::uint64_t>(seed),
                                         max_rows, quiet);
  if (auto st = out.sim->prepare(duration, rows); !st) return st.err();
  out.source = "simulated " + name + ", seed " + std::to_string(static_cast<long long>(seed));
  return out;
}

}  // namespace detail

Expected<Dataset> simulate_model(const ModelSpec& spec, const ParamValues& values,
                                 const std::string& name) {
  auto p = detail::prepare_simulation(spec, values, name, false);
  if (!p) return p.err();
  return p->sim->run(p->source);
}

}  // namespace kfw::model
