// Plot blocks a model file asks for (version 2, "plots"): a list of blocks {"kind", "id",
// "title", kind-specific keys}, each parsed and checked when the file loads so that a view can
// draw it without knowing the model. The kinds are registered in one place, plot_kinds()
// (model_plots.cpp); each kind's keys are read in a file of its own (plot_<kind>.cpp), and its
// drawer is widgets/plots/<kind>_block.cpp. The numbers a block shows come from the engine: a
// gain curve from gain_curve_of() (experiment/gain_curve.h), a series from the run's own arrays
// (series_block_data below).
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "core/expected.h"
#include "core/param_spec.h"

namespace kfw::model {

struct ModelSpec;
struct ModelResult;

namespace detail {
class Reader;
}

// One quantity a block draws: a state ("theta", its estimate), a derived quantity
// ("derived.beta") or a steady-state gain entry ("K.theta.angle"), with the label and unit the
// file declares (a gain entry's unit is the metric's, [state]/[role]: empty here).
struct PlotLine {
  std::string key, label, unit;
};

// A fixed point of a trajectory block (a beacon, a target): its name and its coordinates, each
// an expression of parameters, checked when the file loads (the compiled text: sub-expressions
// expanded). This header stays free of the expression headers: views include it.
struct PlotPoint {
  std::string name, x, y;
};

struct PlotBlockSpec {
  std::string kind, id, title;  // title: empty when the file gives none (the drawer's default)
  // gain_curve: the steady state at points of `sweep` over its range (or `range`), drawn against
  // `x` (a derived scalar; empty: the swept parameter itself); `y` on the left axis, `y2` on the
  // right; the live operating point and a note with its numbers.
  std::string sweep;
  double range_lo = 0.0, range_hi = 0.0;  // both 0: the parameter's declared range
  PlotLine x;
  std::vector<PlotLine> y, y2;
  bool log_x = false, log_y = false, log_y2 = false, operating_point = true;
  // series: states (estimates) and derived series over time, with the replay cursor.
  std::vector<PlotLine> series;
  // trajectory: state `ty` against state `tx` (a top view: estimate and truth), and labelled
  // fixed points.
  PlotLine tx, ty;
  std::vector<PlotPoint> points;
  bool equal_scale = false;  // one unit is as many pixels on both axes (same-unit states)
  // covariance: the sample covariance of `series` (derived series) beside the declared matrix
  // `design` (n × n expressions of parameters and dt, row-major, compiled text).
  std::vector<std::string> design;
  // Samples at instants (the row where every series has a new finite value since the last
  // instant, each its latest; seed 004's verification statistics) instead of the rows where all
  // are finite; `exclude`: per series, a channel whose outlier column marks its samples (empty:
  // none), an instant holding a marked sample left out.
  bool instants = false;
  std::vector<std::string> exclude;
};

// A kind: its name, the keys it reads besides kind, id and title, and its reader.
struct PlotKind {
  std::string name;
  std::vector<std::string> keys;
  Status (*parse)(const detail::Reader& p, const nlohmann::json& j, const std::string& key,
                  const ModelSpec& m, const ParamTable& params, PlotBlockSpec& out);
};

// Every kind, in one place.
const std::vector<PlotKind>& plot_kinds();

// "plots": [{"kind": ..., "id": ..., ...}, ...] into m.plots; errors name model.plots[i].KEY.
Status parse_plots(const detail::Reader& p, const nlohmann::json& block, const ParamTable& params,
                   ModelSpec& m);

// The generic model view's panels of m, by the names `kfw --list-plots` prints, in the view's order
// (before first_panels): state.S, measured.C.R and innovation.C.R, nis.C, gain, gain_curve (a
// linear time-invariant model), mode_probabilities, mode_heatmap (two grid axes), grid.P, then
// the file's plot blocks.
std::vector<std::string> panel_names(const ModelSpec& m);
// "first_panels" (version 2, issue 28): panels to show first, in this order; each a name of
// panel_names(m), once.
Status parse_first_panels(const detail::Reader& p, const nlohmann::json& list, ModelSpec& m);

// The kinds' readers (plot_gain_curve.cpp, plot_series.cpp, plot_trajectory.cpp,
// plot_covariance.cpp).
Status parse_gain_curve_block(const detail::Reader& p, const nlohmann::json& j,
                              const std::string& key, const ModelSpec& m, const ParamTable& params,
                              PlotBlockSpec& out);
Status parse_series_block(const detail::Reader& p, const nlohmann::json& j, const std::string& key,
                          const ModelSpec& m, const ParamTable& params, PlotBlockSpec& out);
Status parse_trajectory_block(const detail::Reader& p, const nlohmann::json& j,
                              const std::string& key, const ModelSpec& m, const ParamTable& params,
                              PlotBlockSpec& out);
Status parse_covariance_block(const detail::Reader& p, const nlohmann::json& j,
                              const std::string& key, const ModelSpec& m, const ParamTable& params,
                              PlotBlockSpec& out);

// A series block's data on a run: per line, its values at the run's steps (r.t): a state's
// estimate or the run's column derived.NAME (null when the run lacks it).
struct SeriesData {
  PlotLine line;
  const std::vector<double>* y = nullptr;
};
std::vector<SeriesData> series_block_data(const PlotBlockSpec& b, const ModelResult& r);

// A trajectory block's data on a run: the estimated track (ty against tx), the true track (empty
// when either state has no truth column) and the fixed points at the run's values.
struct TrajectoryData {
  const std::vector<double>*x = nullptr, *y = nullptr;
  const std::vector<double>*x_true = nullptr, *y_true = nullptr;
  struct Point {
    std::string name;
    double x = 0.0, y = 0.0;
  };
  std::vector<Point> points;
};
TrajectoryData trajectory_block_data(const PlotBlockSpec& b, const ModelResult& r);

// The numbers of every block that depend on the run's values: trajectory points into
// r.plot_points (a point whose coordinates are not finite is left out), and each covariance
// block's design matrix (at the run's median dt) into r.plot_matrices.
Status add_plot_points(const ModelSpec& m, const ParamValues& values, double dt, ModelResult& r);

// A covariance block's data on a run: the sample covariance of its series over the steps where
// every one is finite (mean removed, divided by count − 1; NaN with fewer than two such steps)
// and the design matrix, both n × n row-major, and the series' sample means (NaN likewise).
struct CovarianceData {
  std::size_t n = 0, count = 0;
  std::size_t excluded = 0;  // instants left out for a marked sample
  std::vector<double> sample, design, mean;
};
CovarianceData covariance_block_data(const PlotBlockSpec& b, const ModelResult& r);

namespace detail {
// A list of names at `key` (one string alone is a list of one); refused when empty.
Expected<std::vector<std::string>> name_list(const Reader& p, const nlohmann::json& j,
                                             const std::string& key);
// The quantity `name` names among `known` (keys such as "derived.beta", "K.theta.angle", "x"),
// also by a derived quantity's own name ("beta"); else "unknown WHAT 'name' (did you mean ...)".
Expected<PlotLine> plot_line(const Reader& p, const std::string& name, const std::string& key,
                             const ModelSpec& m, const std::vector<std::string>& known,
                             const char* what);
}  // namespace detail

}  // namespace kfw::model
