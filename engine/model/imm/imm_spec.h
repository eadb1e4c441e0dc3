// The modes block of a model (version 2, issue 28; presets/models/README.md, "Modes"): an IMM over
// the model, its modes a list (parameters set, the process or a channel replaced) or the product
// grid of axes over parameters (seed 001 eq. 6), with a Markov chain and initial probabilities.
#pragma once

#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <utility>
#include <vector>

#include "core/expected.h"
#include "core/param_spec.h"
#include "core/types.h"

namespace kfw::model {

struct ModelSpec;

// A value that is a number or follows a parameter (its key).
struct ParamRef {
  std::string key;  // empty: `value`
  double value = 0.0;
  double at(const ParamValues& v) const;
};

struct ModeSpec {
  std::string name, label;
  std::vector<std::pair<std::string, ParamRef>> params;  // parameters this mode sets
  std::shared_ptr<const ModelSpec> model;  // its process or channels replaced; null: the model's
};

struct GridAxisSpec {
  std::string param, label, unit;
  std::string truth;     // the column of the parameter's true value, or empty
  ParamRef min, max, n;  // each follows a parameter (declared, or gained: grid.PARAM.min …)
};

// Mode-parameter renewal of a grid (seed 001 eq. 4; presets/models/README.md, "Renewal"): the
// whole grid moves by ΔR̄ = Kp (R̂ − R̄_centre) per row, and μ follows it by one of four readings.
enum class RenewalReading {
  kIndex,  // μ stays on the mode index (the estimate jumps with the grid)
  kSlope,  // μ shared between the moved grid points around each old value
  kRate,   // as index, with Kp per second: ΔR̄ = min(1, Kp·dt)(R̂ − R̄_centre)
  kMix,    // the move as a mode transition composed with the Markov chain, in one mixing
};
struct RenewalSpec {
  ParamRef gain, start;  // Kp (per row, or per second for `rate`), and the time it starts (s)
  RenewalReading fixed = RenewalReading::kIndex;
  std::string param;  // a choice parameter whose labels name the readings, or empty: `fixed`
  std::vector<RenewalReading> by_choice;
  RenewalReading at(const ParamValues& v) const;
};

// Per-block mode-matched filtering (presets/models/README.md, "Structure"): the states in blocks
// that F and H keep apart; mixing is done block by block (the cross-block spread terms of each
// mode's mixed prior dropped, as three axis filters would), and `approximate` drops the
// cross-block entries of Q, R and P0 too (seed 001's axis structure).
struct StructureSpec {
  std::vector<int> block_of;  // per state: its block
  bool approximate = false;
  // Per channel, per component: the block its H row reads (−1: none).
  std::vector<std::vector<int>> component_block;
};
struct StructureChoice {
  std::shared_ptr<const StructureSpec> fixed;                   // null: one block (no structure)
  std::string param;                                            // a choice parameter selecting ...
  std::vector<std::shared_ptr<const StructureSpec>> by_choice;  // ... one per label
  const StructureSpec* at(const ParamValues& v) const;
};

// One mode at a run's parameter values.
struct Mode {
  std::string name, label;
  ParamValues values;  // the run's values with the mode's set
  const ModelSpec* model = nullptr;
  std::vector<double> grid;             // per grid axis: the parameter's value in this mode ...
  std::vector<std::size_t> grid_index;  // ... and its index along the axis
};

struct ModesSpec {
  std::vector<ModeSpec> list;
  std::vector<GridAxisSpec> grid;
  ParamRef stay;                            // the uniform chain's p^{jj} ...
  std::vector<std::vector<double>> matrix;  // ... or the whole matrix (non-empty)
  std::vector<double> mu0;                  // empty: uniform
  std::shared_ptr<const RenewalSpec> renewal;
  StructureChoice structure;      // a grid's renewal; null: the grid stays
  std::vector<ParamSpec> gained;  // parameters the block adds (grid.PARAM.min, markov.stay, …)

  bool is_grid() const { return !grid.empty(); }
  // The modes at a run's values: a grid's axes checked (min ≤ max, n a whole number ≥ 1, at most
  // limits::kMaxModes modes), messages naming the keys (exit 2).
  Expected<std::vector<Mode>> modes(const ModelSpec& base, const ParamValues& v) const;
  // Each grid axis's values at v (min + i·(max − min)/(n − 1); the mid-point when n = 1).
  static std::vector<double> axis_values(double min, double max, int n);
  // A grid over a mode parameter (ModelSpec::mode_params, no slider): outside the modes — a
  // self-simulation, x0, the base evaluator — it takes its grid's centre at v.
  void set_mode_params(const ModelSpec& base, ParamValues& v) const;
};

// A grid axis's values as labels and ticks show them: the fewest decimals (0 to 10) that put every
// value within a twentieth of the axis's step (seed 001's 7 slopes on [−0.05, 0.05]: "-0.033");
// −1 where no step exists (one value) or 10 decimals are not enough, then number()'s form.
int grid_decimals(const std::vector<double>& values);
std::string grid_value_text(double v, int decimals);

namespace detail {
class Reader;
// Parses model.modes of the block `model` (its keys sorted): `base` is the model parsed so far
// (every key but modes), `params` the declared parameters.
Expected<std::shared_ptr<const ModesSpec>> parse_modes(const Reader& p, const nlohmann::json& model,
                                                       const ParamTable& params,
                                                       const ModelSpec& base);
// model.modes.structure (imm_structure.cpp): blocks checked against every mode's model.
Status parse_structure(const Reader& p, const nlohmann::json& j, const ParamTable& params,
                       const ModelSpec& base, ModesSpec& out);
}  // namespace detail

}  // namespace kfw::model
