// Fuzz harness bodies (issue 16), one per loader, shared by the libFuzzer targets
// (tests/fuzz/fuzz_main.cpp, `make fuzz`) and the corpus replay in CI
// (tests/engine/fuzz_corpus_test.cpp). Each feeds one input to the entry point the app uses and
// returns "" when the outcome is allowed — a value that satisfies the loader's promises, or an
// error with a one-line message and exit code 1 or 2 — else a description of the violation.
// Crashes, hangs and sanitizer reports are the fuzzer's to catch.
#pragma once

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <string_view>

#include "core/dataset.h"
#include "core/scenario.h"
#include "document/preset.h"
#include "document/session.h"
#include "document/workspace.h"
#include "experiment/grammar.h"
#include "experiment/monte_carlo.h"
#include "experiment/sweep_part.h"
#include "filter/covariance_check.h"
#include "model/model_result.h"
#include "model/model_scenario.h"

namespace kfw::fuzz {

// The harnesses by name: the libFuzzer target names and the corpus folders.
inline constexpr const char* kHarnesses[] = {
    "csv",        "csv_mapped", "preset",          "session",   "set",
    "model_expr", "model_file", "montecarlo_part", "sweep_part"};

// An error is allowed when it is one line, says something, and has a defined exit code.
inline std::string check_error(const Error& e, const char* what) {
  if (e.message.empty()) return std::string(what) + ": an empty error message";
  if (e.message.find('\n') != std::string::npos)
    return std::string(what) + ": a message of more than one line: " + e.message.substr(0, 200);
  if (e.message.size() > 2000)
    return std::string(what) + ": a message of " + std::to_string(e.message.size()) +
           " bytes: " + e.message.substr(0, 200);
  if (e.exit_code != kExitInvalid && e.exit_code != kExitFailed)
    return std::string(what) + ": exit code " + std::to_string(e.exit_code);
  return "";
}

// The full covariance, where a result exposes one (a model's n×n upper triangle): symmetric
// positive semi-definite at every step (filter/covariance_check.h).
inline std::string check_covariances(const RunResult& res) {
  if (const auto* m = dynamic_cast<const model::ModelResult*>(&res)) {
    const std::size_t n = m->n();
    Eigen::MatrixXd P(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
    const std::size_t steps = m->P.empty() ? 0 : m->P.front().size();
    for (std::size_t k = 0; k < steps; ++k) {
      for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = 0; j < n; ++j)
          P(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) =
              m->P[m->cov_index(i, j)][k];
      }
      if (!is_symmetric_psd(P)) return "P not PSD at step " + std::to_string(k);
    }
  }
  return "";
}

// A run's promises: finite metrics; per state, finite estimates once started and variances that
// are finite and >= 0 (the diagonal of a PSD covariance); the full covariance PSD where the result
// exposes it; NIS >= 0 (S positive definite).
inline std::string check_run(const Expected<std::shared_ptr<const RunResult>>& r) {
  if (!r) {
    // A model whose Q or R depends on dt is checked at each interval the data holds (exit 2 naming
    // the interval: the model does not hold for these data, model/model_eval.h); anything else a
    // run refuses after the data loaded is a breakdown (exit 1).
    const bool interval = r.error().find("the interval into step") != std::string::npos;
    if (r.exit_code() != kExitFailed && !(interval && r.exit_code() == kExitInvalid))
      return "a run refused its validated input: " + r.error();
    return check_error(r.err(), "run");
  }
  const RunResult& res = **r;
  for (const auto& [k, v] : res.metrics) {
    if (!std::isfinite(v)) return "metric " + k + " is not finite";
  }
  for (const auto& st : res.states()) {
    if (!st.variance) continue;
    for (double v : *st.variance) {
      if (std::isinf(v) || v < 0.0) return "variance of " + st.key + " is " + std::to_string(v);
    }
  }
  for (const auto& c : res.channels()) {
    for (double v : c.nis) {
      if (v < -1e-9 || std::isinf(v)) return "NIS of " + c.name + " is " + std::to_string(v);
    }
  }
  return check_covariances(res);
}

// The input as a file: the app's loaders read files (one file per process).
inline std::string as_file(std::string_view data, const char* ext) {
  const std::string path = "/tmp/kfw_fuzz_" + std::to_string(::getpid()) + ext;
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(data.data(), static_cast<long>(data.size()));
  return path;
}

// The seed 000 preset (presets/helicopter.json, a model file) the csv and set harnesses feed.
inline const Scenario& helicopter() {
  static const auto p = load_preset(retired_model_path("helicopter"));
  return *p->instance;
}

// Dataset CSV through load_dataset_file (the app's entry point), then a run when it loads.
inline std::string csv(std::string_view data, bool mapped) {
  Mapping m;
  if (mapped) {
    m["t"] = {"time_ms", "ms"};
    m["gyro"] = {"omega", "rad/s"};
    m["angle"] = {"roll", "", 2.0, 1.0, true};
  }
  auto d = load_dataset_file(helicopter(), as_file(data, ".csv"), m);
  if (!d) {
    if (d.exit_code() != kExitInvalid) return "a bad file did not exit 2: " + d.error();
    return check_error(d.err(), "csv");
  }
  if (d->rows() < 2 || d->rows() > 5000) return "";  // long runs: the fuzzer's time is better spent
  for (const char* col : {"t", "gyro", "angle"}) {
    if (!d->has(col)) return std::string("a loaded dataset lacks '") + col + "'";
  }
  const auto& t = d->col("t");
  for (std::size_t k = 0; k < t.size(); ++k) {
    if (!std::isfinite(t[k]) || (k && !(t[k] > t[k - 1]))) return "time not finite or increasing";
  }
  return check_run(helicopter().run(*d, helicopter().params().defaults()));
}

// Preset JSON through parse_preset; a preset that loads has every value in range and survives a
// write and a re-read unchanged.
inline std::string preset(std::string_view data) {
  auto p = parse_preset(std::string(data), "fuzz.json");
  if (!p) {
    if (p.exit_code() != kExitInvalid) return "a bad preset did not exit 2: " + p.error();
    return check_error(p.err(), "preset");
  }
  if (!p->instance) return "a loaded preset has no scenario";
  if (auto st = p->instance->params().check(p->values); !st)
    return "a loaded preset holds an invalid value: " + st.error();
  auto again = parse_preset(preset_to_json(*p), "fuzz2.json");
  if (!again) return "a loaded preset does not re-read: " + again.error();
  if (again->values != p->values) return "a preset's values changed on write and re-read";
  return "";
}

// Session JSON through parse_session; a session that loads survives a write and a re-read.
inline std::string session(std::string_view data) {
  auto s = parse_session(std::string(data), "fuzz.session.json");
  if (!s) {
    if (s.exit_code() != kExitInvalid) return "a bad session did not exit 2: " + s.error();
    return check_error(s.err(), "session");
  }
  for (const auto& [k, v] : s->values) {
    if (!std::isfinite(v)) return "a session value is not finite: " + k;
  }
  auto again = parse_session(session_to_json(*s), "fuzz2.session.json");
  if (!again) return "a loaded session does not re-read: " + again.error();
  if (again->values != s->values || again->snapshots != s->snapshots ||
      again->mapping != s->mapping)
    return "a session changed on write and re-read";
  return "";
}

// `--set KEY=VALUE` (each line an assignment) on the helicopter table, and the grid grammar of
// `sweep --param` on the same text: a value that is accepted is finite and inside its range.
inline std::string set(std::string_view data) {
  const ParamTable& table = helicopter().params();
  ParamValues values = table.defaults();
  std::istringstream in{std::string(data)};
  std::string line;
  while (std::getline(in, line)) {
    auto st = table.apply_assignment(line, values);
    if (!st) {
      if (auto e = check_error(st.err(), "--set"); !e.empty()) return e;
      if (st.exit_code() != kExitInvalid) return "--set did not exit 2: " + st.error();
    }
    if (auto c = table.check(values); !c) return "--set accepted an invalid value: " + c.error();
    auto g = parse_grid(line, "--param");
    if (!g) {
      if (auto e = check_error(g.err(), "--param"); !e.empty()) return e;
    }
  }
  return "";
}

// A model expression: the input is the measurement function h of a small nonlinear model
// (states px, vx; parameters q, r), compiled (muparser + GiNaC derivatives), simulated and run.
inline std::string model_expr(std::string_view data) {
  static const nlohmann::json base = nlohmann::json::parse(R"json({
    "format": "kfw-preset", "version": 1, "scenario": "model", "title": "fuzz",
    "parameters": {
      "q": {"value": 1, "min": 1e-6, "max": 1e6, "unit": "", "scale": "log", "label": "q"},
      "r": {"value": 1, "min": 1e-6, "max": 1e6, "unit": "", "scale": "log", "label": "r"},
      "sim.seed": {"value": 1, "min": 0, "max": 1e6, "unit": "", "scale": "integer", "label": "seed"},
      "sim.duration": {"value": 2, "min": 0.1, "max": 10, "unit": "s", "scale": "linear", "label": "d"},
      "sim.dt": {"value": 0.1, "min": 0.01, "max": 1, "unit": "s", "scale": "log", "label": "dt"}
    },
    "model": {
      "version": 1,
      "states": [{"name": "px", "unit": "m"}, {"name": "vx", "unit": "m/s"}],
      "x0": ["1", "0.5"], "P0": ["1", "1"],
      "process": {"F": [["1", "dt"], ["0", "1"]],
                  "Q": [["q*dt^3/3", "q*dt^2/2"], ["q*dt^2/2", "q*dt"]]},
      "measurements": {"z": {"roles": ["z"], "h": ["px"], "R": ["r"]}},
      "filter": "ekf"
    }
  })json");
  if (data.size() > 4096) return "";  // expressions, not documents
  nlohmann::json j = base;
  j["model"]["measurements"]["z"]["h"][0] = std::string(data);
  auto s = make_model_scenario(j, "fuzz_model.json");
  if (!s) {
    if (s.exit_code() != kExitInvalid) return "a bad model did not exit 2: " + s.error();
    return check_error(s.err(), "model");
  }
  const ParamValues p = (*s)->params().defaults();
  auto d = (*s)->simulate(p);
  if (!d) return check_error(d.err(), "simulate");
  return check_run((*s)->run(*d, p));
}

// A whole model file (issue 29): loaded as the app loads a preset; one that loads is simulated
// for at most 2 000 rows and run, and the run keeps its promises (check_run).
inline std::string model_file(std::string_view data) {
  auto p = parse_preset(std::string(data), "fuzz_model.json");
  if (!p) {
    if (p.exit_code() != kExitInvalid) return "a bad model file did not exit 2: " + p.error();
    return check_error(p.err(), "model file");
  }
  if (!p->instance || p->scenario != "model") return "";
  ParamValues v = p->values;
  const double dt = v.count("sim.dt") ? v["sim.dt"] : 0.0;
  if (v.count("sim.duration") && dt > 0.0)
    v["sim.duration"] = std::min(v["sim.duration"], 2000 * dt);
  auto d = p->instance->simulate(v);
  if (!d) return check_error(d.err(), "simulate");
  if (d->rows() > 20000) return "";
  return check_run(p->instance->run(*d, v));
}

// A Monte Carlo part (issue 29), as `merge` reads it: part_from_json validates it against the
// schema (no exception escapes, one-line errors naming the key); a part that reads summarises to
// finite numbers and survives a write and a re-read.
inline std::string montecarlo_part(std::string_view data) {
  const auto j = nlohmann::json::parse(data, nullptr, false);
  if (j.is_discarded()) return "";  // not JSON: read_json_document's, not the part's
  auto p = part_from_json(j, "fuzz_part.json");
  if (!p) {
    if (p.exit_code() != kExitInvalid) return "a bad part did not exit 2: " + p.error();
    return check_error(p.err(), "part");
  }
  auto merged = merge_montecarlo_parts({*p}, {"fuzz_part.json"});
  if (!merged) return check_error(merged.err(), "merge");
  const MonteCarloSummary s = summarize_monte_carlo(*merged);
  for (const auto& [k, m] : s.metrics) {
    if (m.n && !(std::isfinite(m.mean) && std::isfinite(m.sd)))
      return "the summary of " + k + " is not finite";
  }
  auto again = part_from_json(nlohmann::json::parse(part_to_json(*p).dump()), "again.json");
  if (!again) return "a part does not re-read: " + again.error();
  return "";
}

// A sweep part through merge's schema check and combination (experiment/sweep_part.h): a part
// that passes is read as merge's summary and --out read it — every point's coordinates as
// numbers, its value a number or null, its error a string — without a library exception.
inline std::string sweep_part(std::string_view data) {
  const auto j = nlohmann::json::parse(data, nullptr, false);
  if (j.is_discarded()) return "";  // not JSON: read_json_document's, not the part's
  auto merged = merge_sweep_documents({j}, {"fuzz_sweep.json"});
  if (!merged) {
    if (merged.exit_code() != kExitInvalid) return "a bad part did not exit 2: " + merged.error();
    return check_error(merged.err(), "merge");
  }
  const auto& axes = merged->at("axes");
  for (const auto& p : merged->at("points")) {
    if (p.at("at").size() != axes.size()) return "a point of another dimension passed";
    for (const auto& c : p.at("at"))
      if (!std::isfinite(c.get<double>())) return "a coordinate is not finite";
    if (p.contains("error")) (void)p.at("error").get<std::string>();
    if (p.contains("value") && !p.at("value").is_null()) (void)p.at("value").get<double>();
  }
  for (const auto& a : axes)
    (void)a.at("key").get<std::string>();
  return "";
}

// Dispatch by harness name (fuzz_main.cpp, the corpus replay).
inline std::string run_harness(std::string_view name, std::string_view data) {
  if (name == "csv") return csv(data, false);
  if (name == "csv_mapped") return csv(data, true);
  if (name == "preset") return preset(data);
  if (name == "session") return session(data);
  if (name == "set") return set(data);
  if (name == "model_expr") return model_expr(data);
  if (name == "model_file") return model_file(data);
  if (name == "montecarlo_part") return montecarlo_part(data);
  if (name == "sweep_part") return sweep_part(data);
  return "no harness '" + std::string(name) + "'";
}

}  // namespace kfw::fuzz
