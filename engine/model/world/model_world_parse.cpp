// The keys only a world block carries (version 2): "noise" (named noise sources), "clocks" (sensor
// clocks), a sensor's "clock", "dropout" and "outliers", and truth columns of sub-expressions.
// Documented in presets/models/README.md, "The world block".
#include <algorithm>
#include <nlohmann/json.hpp>

#include "model/loop/loop_spec.h"
#include "model/model_reader.h"

namespace kfw::model::detail {

namespace {

constexpr const char* kNoiseKinds = "white, held, random_walk, gauss_markov";

Expected<Expr> param_expr(const Reader& p, const json& obj, const char* name,
                          const std::string& key, const char* def) {
  auto it = obj.find(name);
  return p.expr(it == obj.end() ? json(def) : *it, key + "." + name, kParamsOnly, kParamsOnlyWhat);
}

Expected<NoiseKind> noise_kind(const Reader& p, const json& j, const std::string& key) {
  auto kind = p.string(j, "kind", key, true);
  if (!kind) return kind.err();
  static const std::pair<const char*, NoiseKind> kKinds[] = {
      {"white", NoiseKind::kWhite},
      {"held", NoiseKind::kHeld},
      {"random_walk", NoiseKind::kRandomWalk},
      {"gauss_markov", NoiseKind::kGaussMarkov}};
  for (const auto& [name, k] : kKinds) {
    if (*kind == name) return k;
  }
  return p.error(key + ".kind",
                 quote_token(*kind) + " is not a kind of noise (one of " + kNoiseKinds + ")");
}

Expected<NoiseSourceSpec> parse_source(const Reader& p, const std::string& name, const json& j) {
  const std::string key = "model.noise." + name;
  if (!j.is_object()) {
    return p.error(key, std::string("expected {\"kind\": one of ") + kNoiseKinds + ", ...}");
  }
  if (auto st = p.only_keys(
          j, key,
          {"kind", "distribution", "sigma", "min", "max", "hold", "tau", "unit", "description"});
      !st) {
    return st.err();
  }
  NoiseSourceSpec s;
  s.name = name;
  auto kind = noise_kind(p, j, key);
  if (!kind) return kind.err();
  s.kind = *kind;
  auto dist = p.string(j, "distribution", key, false, "normal");
  if (!dist) return dist.err();
  if (*dist != "normal" && *dist != "uniform") {
    return p.error(key + ".distribution", "expected \"normal\" or \"uniform\"");
  }
  s.uniform = *dist == "uniform";
  const bool white_or_held = s.kind == NoiseKind::kWhite || s.kind == NoiseKind::kHeld;
  if (s.uniform && !white_or_held) {
    return p.error(key + ".distribution", "a uniform source is white or held");
  }
  const auto need = [&](const char* k, bool wanted) -> Status {
    if (j.contains(k) == wanted) return Ok{};
    return p.error(key + (wanted ? "" : std::string(".") + k),
                   wanted ? std::string("missing key '") + k + "'" : "not used by this kind");
  };
  for (auto [k, wanted] :
       {std::pair{"sigma", !s.uniform}, std::pair{"min", s.uniform}, std::pair{"max", s.uniform},
        std::pair{"tau", s.kind == NoiseKind::kGaussMarkov}}) {
    if (auto st = need(k, wanted); !st) return st.err();
  }
  if (j.contains("hold") && s.kind != NoiseKind::kHeld) {
    return p.error(key + ".hold", "only a held source has a hold time");
  }
  for (auto [field, k, def] : {std::tuple{&s.sigma, "sigma", "0"}, std::tuple{&s.lo, "min", "0"},
                               std::tuple{&s.hi, "max", "0"}, std::tuple{&s.tau, "tau", "1"},
                               std::tuple{&s.hold, "hold", "0"}}) {
    auto e = param_expr(p, j, k, key, def);
    if (!e) return e.err();
    *field = *e;
  }
  s.held_once = s.kind == NoiseKind::kHeld && !j.contains("hold");
  for (auto [field, k] : {std::pair{&s.unit, "unit"}, std::pair{&s.description, "description"}}) {
    auto v = p.string(j, k, key, false);
    if (!v) return v.err();
    *field = *v;
  }
  return s;
}

Expected<ClockSpec> parse_clock(const Reader& p, const std::string& name, const json& j,
                                const std::string& key) {
  if (!j.is_object()) return p.error(key, "expected {\"period\": ..., \"jitter\": ...}");
  if (auto st = p.only_keys(j, key, {"period", "offset", "jitter", "resolution"}); !st) {
    return st.err();
  }
  if (!j.contains("period")) return p.error(key, "missing key 'period'");
  ClockSpec c;
  c.name = name;
  for (auto [field, k, def] :
       {std::tuple{&c.period, "period", "0"}, std::tuple{&c.offset, "offset", "0"},
        std::tuple{&c.jitter, "jitter", "0"}, std::tuple{&c.resolution, "resolution", "0"}}) {
    auto e = param_expr(p, j, k, key, def);
    if (!e) return e.err();
    *field = *e;
  }
  return c;
}

int clock_index(const ModelSpec& m, const std::string& name) {
  for (std::size_t i = 0; i < m.clocks.size(); ++i) {
    if (m.clocks[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

Status parse_outliers(const Reader& p, const json& j, const std::string& key, const ChannelSpec& c,
                      SensorSpec& s) {
  if (!j.is_object()) return p.error(key, "expected {\"count\" or \"rate\", \"size\"}");
  if (auto st = p.only_keys(j, key, {"count", "rate", "size", "group", "column"}); !st) {
    return st.err();
  }
  if (j.contains("count") == j.contains("rate")) {
    return p.error(key, "declare exactly one of count (samples) or rate (per sample)");
  }
  if (!j.contains("size")) return p.error(key, "missing key 'size'");
  s.outliers = true;
  s.outlier_count = j.contains("count");
  auto amount = param_expr(p, j, s.outlier_count ? "count" : "rate", key, "0");
  if (!amount) return amount.err();
  s.outlier_amount = *amount;
  auto size = param_expr(p, j, "size", key, "0");
  if (!size) return size.err();
  s.outlier_size = *size;
  auto group = p.string(j, "group", key, false, c.name);
  if (!group) return group.err();
  if (!is_identifier(*group)) return p.error(key + ".group", "a name (letters, digits and _)");
  s.outlier_group = *group;
  auto column = p.string(j, "column", key, false);
  if (!column) return column.err();
  s.outlier_column = *column;
  return Ok{};
}

}  // namespace

Status parse_noise_sources(const Reader& p, const json& world, ModelSpec& m) {
  auto it = world.find("noise");
  if (it == world.end()) return Ok{};
  if (!it->is_object()) return p.error("model.noise", "expected {\"NAME\": {\"kind\": ...}}");
  for (auto s = it->begin(); s != it->end(); ++s) {
    const std::string key = "model.noise." + truncate_token(s.key());
    if (!is_identifier(s.key()) || is_reserved_name(s.key())) {
      return p.error(key, "a noise source's name is a name (letters, digits and _), not reserved");
    }
    if (m.symbols.find(s.key()) >= 0) return p.error(key, "is already a symbol");
    auto source = parse_source(p, s.key(), s.value());
    if (!source) return source.err();
    // Its value changes with time: expressions that use it are evaluated every step.
    source->slot = m.symbols.add(s.key(), kTimeSymbol);
    m.noise.push_back(std::move(*source));
  }
  return Ok{};
}

Status parse_clocks(const Reader& p, const json& world, ModelSpec& m) {
  auto it = world.find("clocks");
  if (it == world.end()) return Ok{};
  if (!it->is_object()) return p.error("model.clocks", "expected {\"NAME\": {\"period\"}}");
  for (auto c = it->begin(); c != it->end(); ++c) {
    const std::string key = "model.clocks." + truncate_token(c.key());
    if (!is_identifier(c.key())) return p.error(key, "a clock's name is a name");
    auto clock = parse_clock(p, c.key(), c.value(), key);
    if (!clock) return clock.err();
    m.clocks.push_back(std::move(*clock));
  }
  return Ok{};
}

namespace {

// One clock: a declared clock's name, or an object (a clock of its own, named after the sensor).
Expected<int> sensor_clock(const Reader& p, const json& j, const std::string& key, ModelSpec& m,
                           const std::string& sensor) {
  if (j.is_string()) {
    const int clock = clock_index(m, j.get<std::string>());
    if (clock >= 0) return clock;
    std::vector<std::string> names;
    for (const auto& c : m.clocks)
      names.push_back(c.name);
    return p.error(key, unknown_message("clock", j.get<std::string>(), names) +
                            " (declare it under model.world.clocks)");
  }
  if (clock_index(m, sensor) >= 0) {
    return p.error(key, "a clock named '" + sensor + "' exists: name it");
  }
  auto clock = parse_clock(p, sensor, j, key);
  if (!clock) return clock.err();
  m.clocks.push_back(std::move(*clock));
  return static_cast<int>(m.clocks.size()) - 1;
}

// {"param": CHOICE, LABEL: clock, ...}: the clock a choice parameter selects (seed 004's
// synchronous or asynchronous sensors), every label given.
Status clock_alternatives(const Reader& p, const json& j, const std::string& key,
                          const ParamTable& params, ModelSpec& m, ChannelSpec& c) {
  auto alt = choice_alternatives(p, j, key, params, "clock");
  if (!alt) return alt.err();
  // The world reads sim.X as X.
  const std::string symbol = alt->param.rfind("sim.", 0) == 0 ? alt->param.substr(4) : alt->param;
  if (m.symbols.find(symbol) < 0) return unknown_choice_parameter(p, key, alt->param, params);
  auto e = p.expr(json(symbol), key + ".param", kParamsOnly, kParamsOnlyWhat);
  if (!e) return e.err();
  c.sensor.clock_choice = *e;
  const auto& labels = params.find(alt->param)->choices;
  for (std::size_t i = 0; i < alt->values.size(); ++i) {
    auto clock = sensor_clock(p, *alt->values[i], key + "." + labels[i], m, c.name);
    if (!clock) return clock.err();
    c.sensor.clock_by_choice.push_back(*clock);
  }
  c.sensor.clock = c.sensor.clock_by_choice.front();
  return Ok{};
}

}  // namespace

Status parse_sensor(const Reader& p, const json& j, const std::string& key,
                    const ParamTable& params, ModelSpec& m, ChannelSpec& c) {
  SensorSpec& s = c.sensor;
  s.dropout = Expr{"0", Dep::kConst, 0.0};
  if (auto it = j.find("clock"); it != j.end()) {
    if (j.contains("every")) return p.error(key + ".every", "a sensor with a clock has no every");
    if (it->is_object() && it->contains("param")) {
      if (auto st = clock_alternatives(p, *it, key + ".clock", params, m, c); !st) return st;
    } else {
      auto clock = sensor_clock(p, *it, key + ".clock", m, c.name);
      if (!clock) return clock.err();
      s.clock = *clock;
    }
  }
  if (auto it = j.find("dropout"); it != j.end()) {
    auto e = p.expr(*it, key + ".dropout", kParamsOnly, kParamsOnlyWhat);
    if (!e) return e.err();
    s.dropout = *e;
  }
  if (auto it = j.find("outliers"); it != j.end()) {
    if (auto st = parse_outliers(p, *it, key + ".outliers", c, s); !st) return st;
  }
  return parse_impulses(p, j, key, c);
}

}  // namespace kfw::model::detail
