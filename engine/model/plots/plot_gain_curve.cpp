// The gain_curve plot block: the steady-state gain entries and derived scalars of a linear
// time-invariant model at points of one parameter, drawn against a derived scalar — seed 000's
// k1(β) and p11⁻/N_θ against the tracking index β (Fig. 3), from the file's own declarations.
#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "core/suggest.h"
#include "model/model_reader.h"
#include "model/model_spec.h"
#include "model/plots/model_plots.h"

namespace kfw::model {

using nlohmann::json;

namespace {

std::string short_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// What gain() reports that a curve can draw: the gain entries and the derived scalars.
std::vector<std::string> curve_quantities(const ModelSpec& m, bool gains) {
  std::vector<std::string> out;
  for (const auto& d : m.derived) {
    if (!d.series()) out.push_back("derived." + d.name);
  }
  if (!gains) return out;
  for (const auto& s : m.states) {
    for (const auto& c : m.channels) {
      for (const auto& r : c.comps)
        out.push_back("K." + s.name + "." + r.name);
    }
  }
  return out;
}

Status parse_sweep(const detail::Reader& p, const json& j, const std::string& key,
                   const ParamTable& params, PlotBlockSpec& out) {
  auto sweep = p.string(j, "sweep", key, true);
  if (!sweep) return sweep.err();
  std::vector<std::string> continuous;
  for (const auto& s : params.specs()) {
    if ((s.scale == Scale::kLinear || s.scale == Scale::kLog) && s.min < s.max &&
        s.key.rfind("sim.", 0) != 0) {
      continuous.push_back(s.key);
    }
  }
  if (std::find(continuous.begin(), continuous.end(), *sweep) == continuous.end()) {
    return p.error(key + ".sweep",
                   unknown_message("continuous filter parameter", *sweep, continuous));
  }
  out.sweep = *sweep;
  const ParamSpec* spec = params.find(*sweep);
  if (auto it = j.find("range"); it != j.end()) {
    const bool pair =
        it->is_array() && it->size() == 2 && (*it)[0].is_number() && (*it)[1].is_number();
    if (!pair) return p.error(key + ".range", "expected [lowest, highest] of the swept parameter");
    // Within the parameter's range: a preset that narrows the range narrows the curve.
    const double lo = (*it)[0].get<double>(), hi = (*it)[1].get<double>();
    out.range_lo = std::max(lo, spec->min);
    out.range_hi = std::min(hi, spec->max);
    const bool inside = lo < hi && out.range_lo < out.range_hi;
    if (!inside || (spec->scale == Scale::kLog && out.range_lo <= 0.0)) {
      return p.error(key + ".range", "expected lowest < highest within " + *sweep + "'s range [" +
                                         short_number(spec->min) + ", " + short_number(spec->max) +
                                         "]");
    }
  }
  return Ok{};
}

Status parse_axes(const detail::Reader& p, const json& j, const std::string& key,
                  PlotBlockSpec& out) {
  if (auto it = j.find("operating_point"); it != j.end()) {
    if (!it->is_boolean()) return p.error(key + ".operating_point", "expected true or false");
    out.operating_point = it->get<bool>();
  }
  auto it = j.find("log");
  if (it == j.end()) return Ok{};
  auto axes = detail::name_list(p, *it, key + ".log");
  if (!axes) return axes.err();
  const std::vector<std::string> known = {"x", "y", "y2"};
  for (std::size_t i = 0; i < axes->size(); ++i) {
    const std::string& a = (*axes)[i];
    if (a == "x") {
      out.log_x = true;
    } else if (a == "y") {
      out.log_y = true;
    } else if (a == "y2" && !out.y2.empty()) {
      out.log_y2 = true;
    } else {
      return p.error(detail::idx(key + ".log", i),
                     a == "y2" ? std::string("no y2 to draw on a log axis")
                               : unknown_message("axis", a, known) + " (one of x, y, y2)");
    }
  }
  return Ok{};
}

}  // namespace

Status parse_gain_curve_block(const detail::Reader& p, const json& j, const std::string& key,
                              const ModelSpec& m, const ParamTable& params, PlotBlockSpec& out) {
  if (!m.time_invariant()) {
    return p.error(key + ".kind",
                   "a gain curve needs a steady state: a linear model whose F, B, Q, H and R "
                   "depend on parameters and dt only");
  }
  if (auto st = parse_sweep(p, j, key, params, out); !st) return st;
  if (auto it = j.find("x"); it != j.end()) {
    if (!it->is_string()) return p.error(key + ".x", "expected the name of a derived scalar");
    auto x = detail::plot_line(p, it->get<std::string>(), key + ".x", m, curve_quantities(m, false),
                               "derived scalar");
    if (!x) return x.err();
    out.x = *x;
  } else {
    const ParamSpec* s = params.find(out.sweep);
    out.x = {out.sweep, s->label.empty() ? s->key : s->label, s->unit};
  }
  const auto known = curve_quantities(m, true);
  for (auto [name, lines] : {std::pair{"y", &out.y}, std::pair{"y2", &out.y2}}) {
    auto it = j.find(name);
    if (it == j.end()) {
      if (lines == &out.y) return p.error(key, "missing key 'y'");
      continue;
    }
    auto names = detail::name_list(p, *it, key + "." + name);
    if (!names) return names.err();
    for (std::size_t i = 0; i < names->size(); ++i) {
      const std::string at = it->is_array() ? detail::idx(key + "." + name, i) : key + "." + name;
      auto line = detail::plot_line(p, (*names)[i], at, m, known, "quantity of the steady state");
      if (!line) return line.err();
      lines->push_back(*line);
    }
  }
  return parse_axes(p, j, key, out);
}

}  // namespace kfw::model
