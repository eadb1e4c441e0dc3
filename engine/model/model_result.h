// The per-step output of a model run: estimates, covariance, per-channel innovations, S, NIS and
// gains, NEES against the mapped truth. Plots and metrics read it; nothing reaches back.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/scenario.h"

namespace kfw::model {

struct ChannelSeries {
  std::string name, label;
  std::vector<std::string> roles, units;
  // [component][step]: the innovation y = z − ẑ (angles wrapped) and S's diagonal; NaN where the
  // channel did not update (a gated update keeps y and S, its NIS is NaN).
  std::vector<std::vector<double>> y, S;
  std::vector<double> nis, log_det_s;               // per step; NaN where no update
  std::vector<std::vector<double>> K;               // [state · m + component][step]
  std::size_t updates = 0, gated = 0, skipped = 0;  // skipped: S not positive definite
  std::size_t flagged = 0;  // samples the channel's missing flag took out (ChannelSpec::missing)
  // Rows where some of the channel's roles had a value and others none (not applied: a warning).
  std::size_t partial = 0, first_partial = 0;
  std::vector<std::size_t> gated_rows;  // the rows of the gated samples
  std::vector<double> outlier;          // the channel's outlier column (ChannelSpec), or empty
  // An IMM's: −log c per step, the mixture's likelihood of the channel's sample (NaN: none);
  // empty in a plain run, whose NLL comes from log det S and NIS.
  std::vector<double> nll;
};

// An IMM's outputs (model/imm/, presets/models/README.md "Modes"): the modes, their probabilities
// per step, the most probable mode, and each grid axis's μ-weighted estimate.
struct ImmSeries {
  std::vector<std::string> names, labels;  // per mode
  std::vector<float> mu;                   // [step · modes + mode]
  std::vector<double> map;                 // per step: the index of the most probable mode
  struct Axis {
    std::string param, label, unit;
    std::size_t n = 1;             // grid points (mode j's index along the axis: see values)
    std::vector<double> values;    // per mode: the parameter's value
    std::vector<double> estimate;  // per step: Σ_j μ^j (mode j's value at that step)
    // Per step: the grid's centre (min + max)/2, moved by renewal; mode j's value at step k is
    // values[j] + centre[k] − centre[0].
    std::vector<double> centre;
    std::vector<double> truth;  // per step, from the axis's truth column; empty: none
  };
  std::vector<Axis> axes;
  std::size_t modes() const { return names.size(); }
  double mu_at(std::size_t k, std::size_t j) const { return mu[k * modes() + j]; }
};

struct ModelResult final : RunResult {
  std::string filter;  // kf, ekf, ukf
  std::vector<std::string> state_keys, state_labels, state_units;
  std::vector<std::vector<double>> x;      // [state][step]: post-update, else the prediction
  std::vector<std::vector<double>> P;      // [upper-triangle entry][step], row by row
  std::vector<std::size_t> diag;           // P[diag[i]] is the variance of state i
  std::vector<std::vector<double>> truth;  // [state][step]; empty where no truth column
  std::vector<std::string> role_names;     // the measurement columns as read, for table()
  std::vector<std::vector<double>> z;      // [role][step]
  std::vector<ChannelSeries> chans;
  std::vector<std::string> derived_names;    // the series of model.derived, by name
  std::vector<std::vector<double>> derived;  // [quantity][step]
  // The fixed points of the trajectory plot blocks at the run's values (model_plots.h).
  struct PlotPoint {
    std::string block, name;
    double x = 0.0, y = 0.0;
  };
  std::vector<PlotPoint> plot_points;
  // The design matrices of the covariance plot blocks at the run's values, by block id.
  std::vector<std::pair<std::string, std::vector<double>>> plot_matrices;
  std::vector<double> nees;  // over the states with truth; NaN where a truth value is missing
  double nees_dof = 0.0;
  std::optional<ImmSeries> imm;  // a model with modes
  // A closed loop (issue 30): its columns beside the filter's (the reference, the controller's
  // outputs, the noise-free responses) and the event that ended it (name, label, time).
  std::vector<std::pair<std::string, std::vector<double>>> loop_columns;
  struct LoopEvent {
    std::string name, label;
    double t = 0.0;
  };
  std::optional<LoopEvent> event;

  // Index of P(i, j), i ≤ j, in P.
  std::size_t cov_index(std::size_t i, std::size_t j) const;
  std::size_t n() const { return x.size(); }

  Dataset table() const override;
  std::vector<TableColumn> table_view() const override;
  std::vector<InnovationChannel> channels() const override;
  NeesSeries nees_series() const override;
  std::vector<StateSeries> states() const override;
};

}  // namespace kfw::model
