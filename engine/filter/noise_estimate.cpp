#include "filter/noise_estimate.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>

#include "filter/spectrum.h"

namespace kfw {

namespace {

std::string number(double v) {
  std::ostringstream os;
  os.precision(6);
  os << v;
  return os.str();
}

// Welch segments of 1024 samples, as before this command was generic; a shorter column: the
// largest power of two that leaves at least three half-overlapping segments (32 at least).
std::size_t segment_for(std::size_t n) {
  if (n >= 1024) return 1024;
  std::size_t s = 32;
  while (4 * s <= n)
    s *= 2;
  return s;
}

// The column's finite samples (gaps closed up) and its rate: the data's when it has no gap,
// else 1 / the median interval between its samples.
Expected<NoiseColumn> measure(const Dataset& d, const std::string& name, double fs_data) {
  if (!d.has(name)) return Error{d.source + ": no column '" + name + "' to measure"};
  const auto& x = d.col(name);
  const auto& t = d.col("t");
  std::vector<double> v, dt;
  double last = std::nan("");
  for (std::size_t k = 0; k < x.size(); ++k) {
    if (!std::isfinite(x[k])) continue;
    v.push_back(x[k]);
    if (std::isfinite(last) && std::isfinite(t[k])) dt.push_back(t[k] - last);
    last = t[k];
  }
  NoiseColumn c;
  c.name = name;
  c.samples = v.size();
  const std::string where = d.source + ": column '" + name + "': ";
  if (v.size() < kNoiseMinSamples) {
    return Error{where + "PSD: need at least " + std::to_string(kNoiseMinSamples) +
                 " samples, have " + std::to_string(v.size())};
  }
  c.fs_hz = fs_data;
  if (v.size() != x.size()) {
    if (dt.empty()) return Error{where + "no finite times"};
    auto mid = dt.begin() + static_cast<std::ptrdiff_t>(dt.size() / 2);
    std::nth_element(dt.begin(), mid, dt.end());
    c.fs_hz = 1.0 / *mid;
  }
  auto var = white_noise_variance(v, c.fs_hz, kNoiseBandFraction, segment_for(v.size()));
  if (!var) return Error{where + var.error()};
  c.variance = *var;
  return c;
}

// `needed` within the parameter's range; a note when it had to move.
void clamp_to_range(NoiseSuggestion& s, const ParamSpec& spec, std::vector<std::string>& notes) {
  s.value = std::clamp(s.needed, spec.min, spec.max);
  s.clamped = s.value != s.needed;
  if (!s.clamped) return;
  const bool below = s.needed < spec.min;
  notes.push_back(s.param + ": the measured noise asks for " + number(s.needed) + ", " +
                  (below ? "below" : "above") + " its range [" + number(spec.min) + ", " +
                  number(spec.max) + "]; " + s.param + "_suggested is its " +
                  (below ? "minimum" : "maximum") + " (widen the range to use it)");
}

}  // namespace

Status check_noise_links(const Scenario& s, const std::string& path) {
  if (!s.noise_links().empty()) return Ok{};
  const std::string who = path.empty() ? "scenario '" + s.name() + "'" : path;
  return Error{who +
               ": no column's noise is linked to a parameter: add \"noise_param\" to a channel "
               "(model.measurements.NAME.noise_param) or an input (model.inputs[i].noise_param) "
               "of a version-2 model block (presets/models/README.md, \"Noise links\")"};
}

Expected<NoiseEstimate> estimate_noise(const Scenario& s, const Dataset& d, const ParamValues& p) {
  const auto links = s.noise_links();
  if (links.empty()) return check_noise_links(s, "").err();
  const double dt = d.median_dt();
  if (!(dt > 0.0)) return Error{d.source + ": no sample interval (fewer than two rows?)"};
  NoiseEstimate e;
  e.fs_hz = 1.0 / dt;
  for (const auto& link : links) {
    const ParamSpec* spec = s.params().find(link.param);
    if (!spec) return Error{"noise link: unknown parameter '" + link.param + "'"};
    NoiseSuggestion sg;
    sg.param = link.param;
    std::vector<double> variances;
    for (const auto& col : link.columns) {
      auto c = measure(d, col, e.fs_hz);
      if (!c) return c.err();
      variances.push_back(c->variance);
      sg.columns.push_back(std::move(*c));
    }
    auto needed = link.value(variances, p, dt);
    if (!needed) return needed.err();
    if (!std::isfinite(*needed)) {
      return failure((link.declared.empty() ? link.param : link.declared) +
                     ": the measured noise gives no finite value of '" + link.param + "'");
    }
    sg.needed = *needed;
    clamp_to_range(sg, *spec, e.notes);
    e.suggestions.push_back(std::move(sg));
  }
  return e;
}

std::string noise_to_json(const NoiseEstimate& e) {
  nlohmann::ordered_json j;
  j["fs_hz"] = e.fs_hz;
  j["band"] = kNoiseBand;
  for (const auto& s : e.suggestions) {
    j[s.param + "_suggested"] = s.value;
    for (const auto& c : s.columns) {
      j["sigma_" + c.name] = std::sqrt(c.variance);
      if (c.fs_hz != e.fs_hz) j["fs_hz_" + c.name] = c.fs_hz;
    }
  }
  if (!e.notes.empty()) j["notes"] = e.notes;
  return j.dump(2);
}

}  // namespace kfw
