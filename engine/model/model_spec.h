// A state-space model declared in a preset's "model" block (version 1 or 2), parsed and validated:
// every expression compiled and classified, every size checked, Jacobians derived. The format is
// documented in presets/models/README.md. Immutable once built; runs share it.
#pragma once

#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <utility>
#include <vector>

#include "core/expected.h"
#include "core/limits.h"
#include "core/param_spec.h"
#include "filter/angle.h"
#include "model/expression.h"
#include "model/model_stat_metrics.h"
#include "model/plots/model_plots.h"

namespace kfw::model {

struct ModesSpec;       // model/imm/imm_spec.h
struct ControllerSpec;  // model/loop/loop_spec.h

// The model format this build reads up to; a version-1 file loads unchanged (version 2 adds
// sub-expressions and the continuous nonlinear process).
inline constexpr int kModelVersion = 2;
inline constexpr int kMaxChannelSize =
    limits::kMaxChannelSize;  // components of one measurement channel

// A matrix of expressions, row-major, with the key that names it in messages.
struct MatrixSpec {
  std::string key;  // "model.process.F"
  int rows = 0, cols = 0;
  std::vector<Expr> e;
  const Expr& at(int i, int j) const { return e[static_cast<std::size_t>(i * cols + j)]; }
  Dep dep() const;  // the latest class of any entry
  bool empty() const { return e.empty(); }
};

struct StateSpec {
  std::string name, unit, label;
  Angle angle = Angle::kNone;
};

// noise_param of an input (version 2, model_noise.h): the parameter its noise sets, the
// variance v of the column's noise, or √v when `sigma` ("as": "sigma"). Empty: none.
struct InputNoise {
  std::string param;
  bool sigma = false;
};

// A known signal u: its column (same name) in data; in simulation, the `sim` expression of t.
// `age` (version 2): the name of a symbol whose value is the time since the input's last sample
// (s): at t[k−1] in the process, at t[k] in a channel; from the first row before any sample; 0 in
// simulation, where every input is sampled each step. Seed 004's heading at mid-interval.
struct InputSpec {
  std::string name, unit, label;
  Expr sim;
  InputNoise noise;
  std::string age;
};

// One component of a measurement channel: a role that binds to the column of the same name.
struct RoleSpec {
  std::string name, unit;
  Angle angle = Angle::kNone;
};

// A world's named noise source (version 2, world only): a symbol whose value the simulation
// draws from its own stream "noise.NAME" (world/model_world_noise.h).
enum class NoiseKind {
  kWhite,        // a new draw at every step of the sim.dt grid
  kHeld,         // a new draw every `hold` seconds (windows [i·hold, (i+1)·hold)), or once
  kRandomWalk,   // 0 at t = 0, then + sigma·√dt·n per step (sigma in unit/√s)
  kGaussMarkov,  // first order, stationary: std sigma, correlation time tau
};
struct NoiseSourceSpec {
  std::string name, unit, description;
  NoiseKind kind = NoiseKind::kWhite;
  bool uniform = false;           // white, held: uniform on [min, max) instead of N(0, sigma²)
  Expr sigma, tau, hold, lo, hi;  // parameters only; hold 0: drawn once per run
  bool held_once = false;         // held without a `hold`
  int slot = -1;
};

// A world's sensor clock: ticks t₀ = offset, tᵢ₊₁ = tᵢ + max(period + jitter·n, period/10),
// rounded to `resolution` (0: not rounded); jitter from the stream "clock.NAME". Sensors naming
// the same clock sample at the same instants.
struct ClockSpec {
  std::string name;
  Expr period, offset, jitter, resolution;  // parameters only
};

// What a world's sensor adds to a channel (world only).
struct SensorSpec {
  int clock = -1;  // an index into ModelSpec::clocks, or -1: the sim.dt grid (and `every`)
  // Or (issue 27) a choice parameter's value selects the clock: `clock_choice` is the parameter
  // (as the world's symbol), `clock_by_choice` the clock per choice index.
  Expr clock_choice;
  std::vector<int> clock_by_choice;
  Expr dropout;  // the probability that a sample is lost (stream "dropout.NAME"); "0": none
  // Outliers: ±size added to `count` samples drawn without replacement from the samples of the
  // sensors of one group (stream "outliers.GROUP"), or to each sample with probability `rate`.
  bool outliers = false, outlier_count = true;
  Expr outlier_amount, outlier_size;
  std::string outlier_group, outlier_column;  // the column of each sample's offset (optional)
  // Impulsive noise (issue 30, seed 003's lost contact): a burst starts at a sample outside one
  // with probability `impulse_rate` (one uniform per sample, stream "dropout.NAME"), lasts
  // 1 + ⌊ln u / ln(1 − 1/burst)⌋ samples (u from "burst.NAME"; mean `impulse_burst`), and each
  // sample in it reads a uniform value on [lo, hi) per role ("impulse.NAME") instead of h + v.
  // `impulse_flag`: a column written 0 at an impulsive sample, 1 at a clean one (optional).
  bool impulses = false;
  Expr impulse_rate, impulse_burst, impulse_lo, impulse_hi;
  std::string impulse_flag;
};

// A filter channel's missing-sample flag (issue 30, seed 003's detection circuit): a sample is
// missing — the update not applied, counted in flagged.NAME — where the column reads exactly
// `equals`, while `when` is not 0 (both parameters only). Empty column: no flag.
struct MissingSpec {
  std::string column;
  Expr equals, when;
  bool on() const { return !column.empty(); }
};

// A world state held within [lo, hi] (issue 30: the beam's end stops), after every grid step and
// RK4 sub-step; at a limit the state `rate` (−1: none) is set to 0 where it points further out.
struct StateLimitSpec {
  int state = -1, rate = -1;
  Expr lo, hi;  // parameters only
};

// A world event (issue 30): the run ends at the first row where `when` is positive (the ball
// leaves the beam), reported as event.NAME_at_s; with `ends` false it is only reported (a warning
// at its first row: the beam beyond the small-angle range).
struct EventSpec {
  std::string name, label;
  Expr when;
  bool ends = true;
};

struct ChannelSpec {
  std::string name, label;
  std::vector<RoleSpec> roles;  // the columns read
  // Pre-processing (version 2, issue 28; presets/models/README.md "Pre-processed measurements"):
  // the filter's components z_i, expressions of the roles' columns (`column_slots`), inputs,
  // parameters and t, named and given units in `comps`. Without `z`, comps are the roles.
  std::vector<RoleSpec> comps;
  std::vector<Expr> z;
  std::vector<int> column_slots;  // per role: its symbol (kMeasuredSymbol) when `z` is declared
  bool linear = true;
  std::vector<Expr> h;  // nonlinear: z = h(x, u, t) + v
  MatrixSpec H;         // linear: z = H x + v; nonlinear: ∂h/∂x (symbolic)
  MatrixSpec R;
  int every = 1;            // update on rows k with k % every == 0 ...
  std::string every_param;  // ... or every = this parameter's value
  double gate = 0.0;        // χ² gate probability; 0: no gate
  Expr gate_sigma;  // or (version 2, scalar channels) |y| > gate_sigma·√S: a distance gate
  std::string outlier_column;  // version 2: the column marking known outliers (non-zero)
  MissingSpec missing;         // issue 30: samples the sensor flags as missing
  SensorSpec sensor;           // a world's sensor: its clock, dropouts and outliers
  // noise_param (version 2, model_noise.h): per role, the parameter its noise sets (empty:
  // none); `noise_shared`: one parameter for every role. Empty: the channel links nothing.
  std::vector<std::string> noise_params;
  bool noise_shared = false;
  int size() const { return static_cast<int>(comps.size()); }  // the filter's components
  bool preprocessed() const { return !z.empty(); }
  bool has_gate() const { return gate > 0.0 || !gate_sigma.text.empty(); }
};

// A group of scalar channels updated together (version 2, model_groups.cpp; seed 004's AS / SC /
// SI). `each`: every member updates on its own when it arrives, as without the group. `stacked`
// and `sequential`: an instant closes when every member has a new sample since the last instant
// (or a member's sample repeats before that: another member dropped out), and the members'
// samples are applied there, at the filter's state of that row: in one update with the members'
// R on the diagonal and `cross` between members (stacked), or one after the other in the group's
// order (sequential). Each member is gated on its own S_ii.
enum class GroupScheme { kEach, kStacked, kSequential };
struct GroupSpec {
  std::string name;
  std::vector<int> members;  // channel indices, in the group's order
  Expr cross;                // the noise covariance between two members (parameters only)
  GroupScheme scheme = GroupScheme::kEach;  // fixed, unless ...
  std::string scheme_param;                 // ... a choice parameter selects it:
  std::vector<GroupScheme> by_choice;       // per choice index
};

enum class ProcessForm {
  kLinear,      // x_k = F x_{k−1} + B u_{k−1} + w, w ~ N(0, Q)
  kContinuous,  // ẋ = A x + B u + G w, E[w wᵀ] = Qc δ: discretised exactly (Van Loan) per dt
  kNonlinear,   // x_k = f(x_{k−1}, u_{k−1}, dt, t) + w
  kContinuousNonlinear,  // ẋ = f(x, u, t) + G w: RK4 for the mean, Van Loan of (A(x), G Qc Gᵀ)
};

struct ProcessSpec {
  ProcessForm form = ProcessForm::kLinear;
  MatrixSpec F;         // linear: F; nonlinear: ∂f/∂x (symbolic); continuous: empty
  MatrixSpec B;         // linear: n × inputs (may be empty)
  MatrixSpec Q;         // linear and nonlinear
  std::vector<Expr> f;  // nonlinear: f; continuous nonlinear: ẋ
  MatrixSpec A, Bc, G, Qc;  // continuous (parameters only); continuous nonlinear: A = ∂ẋ/∂x, G, Qc
  Expr substep;             // continuous nonlinear: the longest RK4 sub-step, s (0: one per dt)
  // Continuous nonlinear whose ẋ is affine in states and inputs with parameter-only
  // coefficients (A and Bu = ∂ẋ/∂u of parameters, no t): RK4 runs its stages as matrix products.
  bool affine = false;
  MatrixSpec Bu;
};

// A derived quantity (model_derived.h): a scalar of parameters and dt, or a series per step.
struct DerivedSpec {
  std::string name, label, unit, description;
  Expr e;
  bool grid = false;  // reads a grid axis's parameter: its IMM estimate at each step
  bool series() const { return grid || e.dep > Dep::kDt; }
  bool live() const { return grid || (e.uses & kStateSymbol) != 0; }  // reads the run's output
};

// x0[i]: an expression of the parameters, or the first finite sample of a column (then `value`
// is used when the column has none, and in simulation), or (version 2, issue 28) a component of a
// channel's first sample ("CHANNEL.COMPONENT"): the filter then starts at that sample's row, which
// the channel does not also apply as an update.
struct InitialSpec {
  Expr value;
  std::string first_column;
  int first_channel = -1, first_component = -1;
};

struct ModelSpec {
  std::string path;
  int version = 1;
  Symbols symbols;
  int dt_slot = -1, t_slot = -1;
  std::vector<int> param_slots;         // the parameters usable in expressions, by slot
  std::vector<std::string> param_keys;  // each one's key (a world's symbol X reads sim.X)
  std::vector<int> state_slots, input_slots;
  std::vector<int> input_age_slots;  // per input: its age symbol, or -1
  std::vector<StateSpec> states;
  std::vector<InputSpec> inputs;
  ProcessSpec process;
  std::vector<ChannelSpec> channels;  // in the order of their names
  std::vector<GroupSpec> groups;      // channel groups (version 2), in the order of their names
  std::vector<InitialSpec> x0;
  int start_channel = -1;  // the channel whose first sample starts the filter (x0), or -1
  MatrixSpec P0;
  std::vector<std::string> truth;  // per state: its truth column, or empty
  // The states whose RMSE is `rmse`: one, or several (then the Euclidean RMSE,
  // sqrt(mean Σ err_i²)).
  std::vector<std::string> primary;
  std::string filter;  // the default filter: kf, ekf or ukf
  // The parameter that is the simulation's step (version 2, "sim": {"dt": "sim.Ts"}): a seed
  // preset keeps its own key, and no sim.dt is gained.
  std::string sim_dt_key = "sim.dt";
  // The world block (version 2): what generates the data in simulation, a model of its own whose
  // channels are the sensors writing the columns this model reads; null: the model simulates
  // itself.
  std::shared_ptr<const ModelSpec> world;
  std::vector<DerivedSpec> derived;  // in the order of their names
  // Named statistics of the run's series (version 2, "metrics"), in the order of their names.
  std::vector<StatMetricSpec> stat_metrics;
  // Grid axes over names the preset does not declare (imm_spec.h): symbols the modes set.
  std::vector<std::string> mode_params;
  Expr metrics_from;  // model.metrics_from (s, parameters only); empty text: the whole run
  // The plot blocks the file asks for (version 2, model_plots.h), in the file's order.
  std::vector<PlotBlockSpec> plots;
  std::vector<std::string> first_panels;  // model.first_panels: shown first, in this order
  std::vector<int> truth_slots;           // per state: its truth column's symbol, or -1
  // Per role of every channel, in channel order (ModelResult::z's): its symbol in derived
  // quantities (kMeasuredSymbol), or -1.
  std::vector<int> measured_slots;
  // World only: the named noise sources, the sensor clocks, and truth columns written from
  // sub-expressions ({column, expression}).
  bool world_block = false;  // this is a world (parsed with parse_model(..., world = true))
  std::vector<NoiseSourceSpec> noise;
  std::vector<ClockSpec> clocks;
  std::vector<std::pair<std::string, Expr>> truth_exprs;
  std::vector<StateLimitSpec> limits;  // world only (issue 30): states held within bounds
  std::vector<EventSpec> events;       // world only (issue 30): conditions that end the run
  // The controller that closes the loop (issue 30, model/loop/loop_spec.h); null: open loop.
  std::shared_ptr<const ControllerSpec> controller;
  // Columns of a closed loop that derived series read (the reference, the controller's outputs,
  // the noise-free responses): {symbol slot, column}.
  std::vector<std::pair<int, std::string>> loop_columns;
  // The modes of an IMM over the model (version 2, issue 28; model/imm/imm_spec.h); null: one
  // filter.
  std::shared_ptr<const ModesSpec> modes;
  // The grid axes' parameters (model.modes.grid[a].param) as symbols, in axis order: in a derived
  // series each stands for its axis's IMM estimate at the step.
  std::vector<int> grid_param_slots;
  std::vector<int> grid_truth_slots;  // each axis's truth column (kTruthSymbol), or -1

  int n() const { return static_cast<int>(states.size()); }
  // F or A and H in every channel: the KF applies, and a steady state may exist.
  bool linear() const;
  // linear(), and so is every mode's model: the KF runs the IMM's modes.
  bool linear_modes() const;
  // The mean moves by f or by RK4 of ẋ (not by F x + B u).
  bool nonlinear_process() const {
    return process.form == ProcessForm::kNonlinear ||
           process.form == ProcessForm::kContinuousNonlinear;
  }
  // Q is evaluated at the state x_{k−1|k−1} (a Q of states, or Van Loan at A(x)).
  bool process_noise_at_state() const {
    return process.form == ProcessForm::kContinuousNonlinear || process.Q.dep() == Dep::kState;
  }
  // Linear, and F, B, Q, H, R depend on nothing but parameters and dt: the DARE applies.
  bool time_invariant() const;
  int state_index(const std::string& name) const;  // -1 when unknown
};

// Parses the "model" block. `params` is the scenario's parameter table (keys that are identifiers
// are symbols of the expressions). Errors read "PATH: model.KEY...: what".
// A world block (`world` true) also sees each parameter sim.X as the symbol X, and may not hold
// a world of its own.
Expected<ModelSpec> parse_model(const nlohmann::json& model, const ParamTable& params,
                                const std::string& path, bool world = false);

// The filters a model can run: kf (linear only), ekf, ukf.
std::vector<std::string> filter_choices(const ModelSpec& spec);

}  // namespace kfw::model
