// The trajectory plot block: one state against another — a top view — with the estimated and
// the true track and labelled fixed points (beacons, targets) whose coordinates are expressions
// of parameters, evaluated once per run.
#include <cmath>
#include <nlohmann/json.hpp>

#include "model/expression.h"
#include "model/model_reader.h"
#include "model/model_result.h"
#include "model/model_spec.h"
#include "model/plots/model_plots.h"

namespace kfw::model {

using nlohmann::json;

namespace {

Expected<PlotLine> state_line(const detail::Reader& p, const json& j, const std::string& name,
                              const std::string& key, const ModelSpec& m) {
  auto it = j.find(name);
  if (it == j.end()) return p.error(key, "missing key '" + name + "'");
  if (!it->is_string()) return p.error(key + "." + name, "expected a state name");
  std::vector<std::string> states;
  for (const auto& s : m.states)
    states.push_back(s.name);
  return detail::plot_line(p, it->get<std::string>(), key + "." + name, m, states, "state");
}

Status parse_points(const detail::Reader& p, const json& j, const std::string& key,
                    PlotBlockSpec& out) {
  auto it = j.find("points");
  if (it == j.end()) return Ok{};
  if (!it->is_object()) {
    return p.error(key + ".points", "expected {\"NAME\": [\"x\", \"y\"], ...} (expressions)");
  }
  for (auto pt = it->begin(); pt != it->end(); ++pt) {
    const std::string at = key + ".points." + truncate_token(pt.key());
    if (!pt->is_array() || pt->size() != 2) {
      return p.error(at, "expected [x, y]: two expressions of parameters");
    }
    auto x = p.expr((*pt)[0], detail::idx(at, 0), detail::kParamsOnly, detail::kParamsOnlyWhat);
    if (!x) return x.err();
    auto y = p.expr((*pt)[1], detail::idx(at, 1), detail::kParamsOnly, detail::kParamsOnlyWhat);
    if (!y) return y.err();
    out.points.push_back({pt.key(), x->text, y->text});
  }
  return Ok{};
}

}  // namespace

Status parse_trajectory_block(const detail::Reader& p, const json& j, const std::string& key,
                              const ModelSpec& m, const ParamTable&, PlotBlockSpec& out) {
  auto x = state_line(p, j, "x", key, m);
  if (!x) return x.err();
  auto y = state_line(p, j, "y", key, m);
  if (!y) return y.err();
  if (x->key == y->key) return p.error(key + ".y", "the same state as x: draw two states");
  out.tx = *x;
  out.ty = *y;
  if (auto it = j.find("equal_scale"); it != j.end()) {
    if (!it->is_boolean()) return p.error(key + ".equal_scale", "expected true or false");
    out.equal_scale = it->get<bool>();
    if (out.equal_scale && x->unit != y->unit) {
      return p.error(key + ".equal_scale", "'" + x->key + "' is in " + quote_token(x->unit) +
                                               " and '" + y->key + "' in " + quote_token(y->unit) +
                                               ": an equal scale needs one unit");
    }
  }
  return parse_points(p, j, key, out);
}

TrajectoryData trajectory_block_data(const PlotBlockSpec& b, const ModelResult& r) {
  TrajectoryData d;
  for (std::size_t i = 0; i < r.state_keys.size(); ++i) {
    const bool truth = i < r.truth.size() && !r.truth[i].empty();
    if (r.state_keys[i] == b.tx.key) {
      d.x = &r.x[i];
      d.x_true = truth ? &r.truth[i] : nullptr;
    }
    if (r.state_keys[i] == b.ty.key) {
      d.y = &r.x[i];
      d.y_true = truth ? &r.truth[i] : nullptr;
    }
  }
  if (!d.x_true || !d.y_true) d.x_true = d.y_true = nullptr;
  for (const auto& p : r.plot_points) {
    if (p.block == b.id) d.points.push_back({p.name, p.x, p.y});
  }
  return d;
}

}  // namespace kfw::model
