// Issue 27 — the generic noise command (filter/noise_estimate.h) and the model key `noise_param`
// (model/model_noise.h): the helicopter's output as its own command gave it, the mapping from a
// measured variance to a parameter (R = σ², (kσ)², R itself, an input's σ), the recovery of a
// simulated noise over seeds, and the refusals with file and key.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "core/scenario.h"
#include "document/preset.h"
#include "document/workspace.h"
#include "filter/noise_estimate.h"
#include "filter/spectrum.h"
#include "model/model_scenario.h"

// A namespace of its own: in a unity batch, helper names stay apart from the neighbours'.
namespace kfw::model_world_noise {
namespace {

using OJson = nlohmann::ordered_json;

const std::string kFile = "models/noise.json";
const std::string kHeliFile = KFW_SOURCE_DIR "/presets/helicopter.json";
const std::string kHeliLog = KFW_SOURCE_DIR "/data/helicopter.csv";

// |a − b| ≤ tol · |b| (every value here is positive).
void expect_close(double a, double b, double tol, const std::string& what) {
  EXPECT_LE(std::abs(a - b), tol * std::abs(b)) << what << ": " << a << " vs " << b;
}

// A random walk x seen by the channel `pos` (column z) with R = `r`; 600 s at 10 Hz.
OJson walk_model(const std::string& r = "sigma^2") {
  auto j = OJson::parse(R"({
    "format": "kfw-preset", "version": 2, "scenario": "model",
    "parameters": {
      "q": {"value": 1e-4, "min": 1e-8, "max": 1, "scale": "log"},
      "sigma": {"value": 2.0, "min": 0.001, "max": 100, "scale": "log"},
      "m": {"value": 1, "min": 1, "max": 10, "scale": "integer"},
      "sim.dt": {"value": 0.1, "min": 0.001, "max": 1, "scale": "log"},
      "sim.duration": {"value": 600, "min": 1, "max": 10000}
    },
    "model": {
      "version": 2,
      "states": ["x"],
      "x0": ["0"], "P0": ["1"],
      "process": {"F": [["1"]], "Q": [["q*dt"]]},
      "measurements": {
        "pos": {"roles": ["z"], "H": [["1"]], "R": ["sigma^2"], "noise_param": "sigma"}
      }
    }
  })");
  j["model"]["measurements"]["pos"]["R"] = OJson::array({r});
  return j;
}

std::shared_ptr<const Scenario> scenario(const OJson& j) {
  auto s = make_model_scenario(j, kFile);
  EXPECT_TRUE(s.ok()) << s.error();
  return s.ok() ? std::shared_ptr<const Scenario>(std::move(*s)) : nullptr;
}

std::string refusal(const OJson& j) {
  auto s = make_model_scenario(j, kFile);
  EXPECT_FALSE(s.ok());
  if (s.ok()) return "";
  EXPECT_EQ(s.err().exit_code, kExitInvalid) << s.error();
  return s.error();
}

struct NoiseRun {
  Dataset data;
  NoiseEstimate e;
};

// Simulates the scenario at seed `seed` and estimates its noise.
NoiseRun simulate_and_estimate(const Scenario& s, int seed, const ParamValues& over = {}) {
  auto v = s.params().defaults();
  v["sim.seed"] = seed;
  for (const auto& [k, x] : over)
    v[k] = x;
  auto d = s.simulate(v);
  EXPECT_TRUE(d.ok()) << d.error();
  if (!d.ok()) return {};
  auto e = estimate_noise(s, *d, v);
  EXPECT_TRUE(e.ok()) << e.error();
  return {*d, e.ok() ? *e : NoiseEstimate{}};
}

// The variance the helicopter's own command read (before issue 27): the whole column, the data's
// rate, 1024-sample segments, above half of Nyquist.
double old_variance(const Dataset& d, const std::string& col) {
  return *white_noise_variance(d.col(col), 1.0 / d.median_dt(), 0.5);
}

// ---- The helicopter: the same keys, in the same order, with the same values

void expect_old_helicopter_output(const Dataset& d, const std::string& json) {
  const auto j = OJson::parse(json);
  std::vector<std::string> keys;
  for (const auto& [k, x] : j.items())
    keys.push_back(k);
  EXPECT_EQ(keys, (std::vector<std::string>{"fs_hz", "band", "Q_suggested", "sigma_gyro",
                                            "R_suggested", "sigma_angle"}));
  EXPECT_EQ(j["band"], "above half of Nyquist");
  EXPECT_EQ(j["fs_hz"].get<double>(), 1.0 / d.median_dt());
  const double vq = old_variance(d, "gyro"), vr = old_variance(d, "angle");
  expect_close(j["Q_suggested"].get<double>(), vq, 1e-12, "Q");
  expect_close(j["R_suggested"].get<double>(), vr, 1e-12, "R");
  expect_close(j["sigma_gyro"].get<double>(), std::sqrt(vq), 1e-12, "sigma_gyro");
  expect_close(j["sigma_angle"].get<double>(), std::sqrt(vr), 1e-12, "sigma_angle");
}

// The seed preset (presets/helicopter.json, the retired built-in's model file) on its log and on
// a simulated log of another length.
TEST(ModelWorldNoise, TheHelicopterGivesWhatItsOwnCommandGaveOnItsLog) {
  auto preset = load_preset(kHeliFile);
  ASSERT_TRUE(preset.ok()) << preset.error();
  const Scenario& heli = *preset->instance;
  auto d = load_dataset_file(heli, kHeliLog);
  ASSERT_TRUE(d.ok()) << d.error();
  auto e = estimate_noise(heli, *d, preset->values);
  ASSERT_TRUE(e.ok()) << e.error();
  expect_old_helicopter_output(*d, noise_to_json(*e));
  EXPECT_TRUE(e->notes.empty());
  auto v = preset->values;
  v["sim.duration"] = 77;
  v["sim.seed"] = 5;
  auto sim = heli.simulate(v);
  ASSERT_TRUE(sim.ok()) << sim.error();
  auto es = estimate_noise(heli, *sim, v);
  ASSERT_TRUE(es.ok()) << es.error();
  expect_old_helicopter_output(*sim, noise_to_json(*es));
}

// The noise command over the file's links (gyro -> Q, angle -> R) prints what the built-in's
// declaration printed, on the world's own simulation (moved from ModelWorldHelicopter, issue 30:
// the built-in's output is now computed from the data, expect_old_helicopter_output).
TEST(ModelWorldNoise, TheNoiseCommandGivesTheBuiltInsSuggestions) {
  auto preset = load_preset(kHeliFile);
  ASSERT_TRUE(preset.ok()) << preset.error();
  const Scenario& heli = *preset->instance;
  ParamValues v = preset->values;
  v["sim.duration"] = 60;
  auto d = heli.simulate(v);
  ASSERT_TRUE(d.ok()) << d.error();
  auto e = estimate_noise(heli, *d, v);
  ASSERT_TRUE(e.ok()) << e.error();
  expect_old_helicopter_output(*d, noise_to_json(*e));
}

TEST(ModelWorldNoise, TheHelicopterModelFileLinksTheSameColumnsToTheSameParameters) {
  auto preset = load_preset(KFW_SOURCE_DIR "/presets/models/helicopter_indirect.json");
  ASSERT_TRUE(preset.ok()) << preset.error();
  const Scenario& file = *preset->instance;
  auto d = load_dataset_file(file, kHeliLog);
  ASSERT_TRUE(d.ok()) << d.error();
  auto e = estimate_noise(file, *d, preset->values);
  ASSERT_TRUE(e.ok()) << e.error();
  // R is solved from R[0][0] = "R" (a root find in log10), Q is the gyro's variance itself.
  expect_old_helicopter_output(*d, noise_to_json(*e));
}

// ---- The mapping from the measured variance to the parameter

TEST(ModelWorldNoise, ASigmaSquaredChannelSuggestsTheSquareRootOfTheMeasuredVariance) {
  auto s = scenario(walk_model("sigma^2"));
  ASSERT_TRUE(s);
  const NoiseRun r = simulate_and_estimate(*s, 3);
  ASSERT_EQ(r.e.suggestions.size(), 1u);
  const auto& sg = r.e.suggestions[0];
  EXPECT_EQ(sg.param, "sigma");
  const double v = old_variance(r.data, "z");
  EXPECT_EQ(sg.columns[0].variance, v);
  expect_close(sg.value, std::sqrt(v), 1e-12, "sigma");
  const auto j = OJson::parse(noise_to_json(r.e));
  expect_close(j["sigma_suggested"].get<double>(), j["sigma_z"].get<double>(), 1e-12, "json");
}

TEST(ModelWorldNoise, ScaledSigmaDtDependentAndPlainVarianceChannelsAreSolved) {
  struct Case {
    std::string r;
    double (*expected)(double v, double dt);
  };
  const std::vector<Case> cases = {
      {"(3*sigma)^2", [](double v, double) { return std::sqrt(v) / 3.0; }},
      {"sigma^2/dt", [](double v, double dt) { return std::sqrt(v * dt); }},
      {"sigma", [](double v, double) { return v; }},
      {"0.5 + sigma^2", [](double v, double) { return std::sqrt(v - 0.5); }},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.r);
    auto s = scenario(walk_model(c.r));
    ASSERT_TRUE(s);
    const NoiseRun r = simulate_and_estimate(*s, 2);
    ASSERT_EQ(r.e.suggestions.size(), 1u);
    const double v = old_variance(r.data, "z");
    expect_close(r.e.suggestions[0].value, c.expected(v, r.data.median_dt()), 1e-12, "sigma");
  }
}

TEST(ModelWorldNoise, TheSuggestionRecoversTheSimulatedNoiseOverSeeds) {
  // σ = 2 simulated, 6000 samples per seed: each seed within 5 %, the mean over ten within 1.5 %.
  auto s = scenario(walk_model());
  ASSERT_TRUE(s);
  double sum = 0.0;
  for (int seed = 1; seed <= 10; ++seed) {
    const NoiseRun r = simulate_and_estimate(*s, seed);
    ASSERT_EQ(r.e.suggestions.size(), 1u);
    const double sigma = r.e.suggestions[0].value;
    expect_close(sigma, 2.0, 0.05, "seed " + std::to_string(seed));
    sum += sigma;
  }
  expect_close(sum / 10.0, 2.0, 0.015, "mean over seeds 1..10");
}

// A world writes a noisy gyro (σ_u) that the filter reads as its input u, and a position whose
// channel updates every m-th row: the input's σ ("as": "sigma") and the channel's σ come back.
// At m = 3 over 1800 s (6000 position samples), seeds 1..5: each within 5 %.
OJson world_model() {
  auto j = walk_model();
  j["parameters"]["sigma_u"] = {{"value", 0.3}, {"min", 1e-4}, {"max", 10}, {"scale", "log"}};
  j["model"]["inputs"] = OJson::parse(R"([{"name": "u",
                                           "noise_param": {"key": "sigma_u", "as": "sigma"}}])");
  j["model"]["process"] =
      OJson::parse(R"({"F": [["1"]], "B": [["dt"]], "Q": [["sigma_u^2*dt^2"]]})");
  j["model"]["measurements"]["pos"]["every"] = "m";
  j["model"]["world"] = OJson::parse(R"json({
    "states": ["x"], "inputs": [{"name": "rate", "sim": "sin(0.05*t)"}],
    "x0": ["0"], "P0": ["0"],
    "process": {"F": [["1"]], "B": [["dt"]], "Q": [["0"]]},
    "measurements": {
      "gyro": {"roles": ["u"], "h": ["rate"], "R": ["sigma_u^2"]},
      "pos": {"roles": ["z"], "H": [["1"]], "R": ["sigma^2"], "every": "m"}
    }
  })json");
  return j;
}

TEST(ModelWorldNoise, AnInputsSigmaAndAChannelAtItsOwnRateAreRecovered) {
  auto s = scenario(world_model());
  ASSERT_TRUE(s);
  for (int seed = 1; seed <= 5; ++seed) {
    SCOPED_TRACE(seed);
    const NoiseRun r = simulate_and_estimate(*s, seed, {{"m", 3}, {"sim.duration", 1800}});
    ASSERT_EQ(r.e.suggestions.size(), 2u);
    EXPECT_EQ(r.e.suggestions[0].param, "sigma_u");  // inputs first
    expect_close(r.e.suggestions[0].value, 0.3, 0.05, "sigma_u");
    expect_close(r.e.suggestions[0].value, std::sqrt(old_variance(r.data, "u")), 1e-12, "exact");
    const auto& pos = r.e.suggestions[1];
    std::size_t n = 0;
    for (double z : r.data.col("z"))
      n += std::isfinite(z) ? 1 : 0;
    EXPECT_EQ(pos.columns[0].samples, n);  // every third row
    EXPECT_NEAR(static_cast<double>(n), r.data.rows() / 3.0, 1.0);
    EXPECT_NEAR(pos.columns[0].fs_hz, 10.0 / 3.0, 1e-9);
    expect_close(pos.value, 2.0, 0.05, "sigma");
    const auto j = OJson::parse(noise_to_json(r.e));
    EXPECT_NEAR(j["fs_hz_z"].get<double>(), 10.0 / 3.0, 1e-9);
    EXPECT_FALSE(j.contains("fs_hz_u"));
  }
}

// Two roles: one parameter for both (the mean variance) or one each.
OJson plane_model(const OJson& noise_param) {
  auto j = walk_model();
  j["parameters"]["sy"] = {{"value", 0.5}, {"min", 1e-3}, {"max", 100}, {"scale", "log"}};
  j["model"]["states"] = OJson::array({"x", "y"});
  j["model"]["x0"] = OJson::array({"0", "0"});
  j["model"]["P0"] = OJson::array({"1", "1"});
  j["model"]["process"] =
      OJson::parse(R"({"F": [["1", "0"], ["0", "1"]], "Q": [["q*dt", "0"], ["0", "q*dt"]]})");
  j["model"]["measurements"]["pos"] = {{"roles", OJson::array({"zx", "zy"})},
                                       {"H", OJson::parse(R"([["1", "0"], ["0", "1"]])")},
                                       {"R", OJson::array({"sigma^2", "sy^2"})},
                                       {"noise_param", noise_param}};
  return j;
}

TEST(ModelWorldNoise, AVectorChannelNamesOneParameterForAllRolesOrOnePerRole) {
  auto per_role = scenario(plane_model(OJson::array({"sigma", "sy"})));
  ASSERT_TRUE(per_role);
  const NoiseRun r = simulate_and_estimate(*per_role, 4);
  ASSERT_EQ(r.e.suggestions.size(), 2u);
  expect_close(r.e.suggestions[0].value, std::sqrt(old_variance(r.data, "zx")), 1e-12, "sigma");
  expect_close(r.e.suggestions[1].value, std::sqrt(old_variance(r.data, "zy")), 1e-12, "sy");
  // One name for both roles: R_xx + R_yy = v_x + v_y, here σ² = the roles' mean variance when
  // both are σ² (sy = σ in the data).
  auto shared = plane_model("sigma");
  shared["model"]["measurements"]["pos"]["R"] = OJson::array({"sigma^2", "sigma^2"});
  auto s = scenario(shared);
  ASSERT_TRUE(s);
  const NoiseRun b = simulate_and_estimate(*s, 4);
  ASSERT_EQ(b.e.suggestions.size(), 1u);
  ASSERT_EQ(b.e.suggestions[0].columns.size(), 2u);
  const double mean = 0.5 * (old_variance(b.data, "zx") + old_variance(b.data, "zy"));
  expect_close(b.e.suggestions[0].value, std::sqrt(mean), 1e-12, "shared sigma");
  const auto j = OJson::parse(noise_to_json(b.e));
  EXPECT_TRUE(j.contains("sigma_zx") && j.contains("sigma_zy")) << j.dump();
}

// ---- The range: a value outside it is clamped and said; no value at all is a failure

TEST(ModelWorldNoise, AValueOutsideTheRangeIsClampedAndSaid) {
  auto j = walk_model();
  j["parameters"]["sigma"]["max"] = 1.0;
  j["parameters"]["sigma"]["value"] = 0.5;
  auto narrow = scenario(j);
  auto wide = scenario(walk_model());
  ASSERT_TRUE(narrow && wide);
  auto v = wide->params().defaults();
  auto d = wide->simulate(v);  // σ = 2
  ASSERT_TRUE(d.ok()) << d.error();
  auto e = estimate_noise(*narrow, *d, narrow->params().defaults());
  ASSERT_TRUE(e.ok()) << e.error();
  const auto& sg = e->suggestions[0];
  EXPECT_TRUE(sg.clamped);
  EXPECT_EQ(sg.value, 1.0);
  expect_close(sg.needed, std::sqrt(old_variance(*d, "z")), 1e-12, "needed");
  ASSERT_EQ(e->notes.size(), 1u);
  std::ostringstream needed;
  needed.precision(6);
  needed << sg.needed;
  EXPECT_NE(e->notes[0].find("sigma: the measured noise asks for " + needed.str() + ", "),
            std::string::npos)
      << e->notes[0];
  EXPECT_NE(e->notes[0].find("above its range [0.001, 1]"), std::string::npos) << e->notes[0];
  EXPECT_TRUE(OJson::parse(noise_to_json(*e)).contains("notes"));
}

TEST(ModelWorldNoise, ARThatCannotEqualTheMeasuredVarianceFailsNamingTheKey) {
  auto wide = scenario(walk_model());
  auto offset = scenario(walk_model("100 + sigma^2"));
  ASSERT_TRUE(wide && offset);
  auto d = wide->simulate(wide->params().defaults());  // variance ≈ 4 < 100
  ASSERT_TRUE(d.ok()) << d.error();
  auto e = estimate_noise(*offset, *d, offset->params().defaults());
  ASSERT_FALSE(e.ok());
  EXPECT_EQ(e.exit_code(), kExitFailed);
  EXPECT_NE(e.error().find("models/noise.json: model.measurements.pos.noise_param: no value of "
                           "'sigma' gives R[0][0] = "),
            std::string::npos)
      << e.error();
}

// ---- Refusals when the file loads: file and key, exit 2

TEST(ModelWorldNoise, AnUnknownParameterIsRefusedWithTheNearestName) {
  auto j = walk_model();
  j["model"]["measurements"]["pos"]["noise_param"] = "sigmma";
  EXPECT_EQ(refusal(j),
            "models/noise.json: model.measurements.pos.noise_param: unknown parameter 'sigmma' "
            "(did you mean 'sigma'?)");
  auto w = world_model();
  w["model"]["inputs"][0]["noise_param"] = {{"key", "sigma_w"}, {"as", "sigma"}};
  EXPECT_EQ(refusal(w),
            "models/noise.json: model.inputs[0].noise_param: unknown parameter 'sigma_w' (did "
            "you mean 'sigma_u'?)");
}

TEST(ModelWorldNoise, AVersionOneFileIsRefusedAVersionTwoKey) {
  auto j = walk_model();
  j["model"]["version"] = 1;
  EXPECT_EQ(refusal(j),
            "models/noise.json: model.measurements.pos.noise_param: a version-2 key: set "
            "\"version\": 2");
  auto w = world_model();
  w["model"].erase("world");
  w["model"]["measurements"]["pos"].erase("noise_param");
  w["model"]["version"] = 1;
  EXPECT_EQ(refusal(w),
            "models/noise.json: model.inputs[0].noise_param: a version-2 key: set \"version\": 2");
}

TEST(ModelWorldNoise, ARThatDoesNotDependOnTheParameterIsRefused) {
  auto j = walk_model("4");
  EXPECT_EQ(refusal(j),
            "models/noise.json: model.measurements.pos.noise_param: model.measurements.pos.R[0][0] "
            "= \"4\" does not depend on 'sigma': name the parameter its noise sets");
  auto q = walk_model("sigma^2");
  q["model"]["measurements"]["pos"]["noise_param"] = "q";
  EXPECT_NE(refusal(q).find("R[0][0] = \"sigma^2\" does not depend on 'q'"), std::string::npos);
  // A dependence that cancels is none (GiNaC's derivative).
  EXPECT_NE(refusal(walk_model("4 + sigma - sigma")).find("does not depend on 'sigma'"),
            std::string::npos);
  auto per_role = plane_model(OJson::array({"sigma", "sigma_x"}));
  per_role["parameters"]["sigma_x"] = per_role["parameters"]["sy"];
  EXPECT_NE(refusal(per_role).find("model.measurements.pos.noise_param[1]: "
                                   "model.measurements.pos.R[1][1] = \"sy^2\" does not depend on "
                                   "'sigma_x'"),
            std::string::npos);
}

TEST(ModelWorldNoise, OtherMisusesAreRefusedWithTheKey) {
  auto state_r = walk_model("sigma^2*(1 + x^2)");
  EXPECT_NE(refusal(state_r).find("R[0][0] = \"sigma^2*(1 + x^2)\" depends on states, inputs or "
                                  "t"),
            std::string::npos);
  auto integer = walk_model("sigma^2*m");
  integer["model"]["measurements"]["pos"]["noise_param"] = "m";
  EXPECT_NE(refusal(integer).find("noise_param: 'm' is not a continuous parameter"),
            std::string::npos);
  auto twice = plane_model(OJson::array({"sigma", "sigma"}));
  EXPECT_NE(refusal(twice).find("model.measurements.pos.noise_param[1]: 'sigma' is already set "
                                "by model.measurements.pos.noise_param[0]"),
            std::string::npos);
  EXPECT_NE(refusal(plane_model(OJson::array({"sigma"})))
                .find("noise_param: expected a parameter name, or a "
                      "list of 2"),
            std::string::npos);
  auto as = world_model();
  as["model"]["inputs"][0]["noise_param"]["as"] = "std";
  EXPECT_NE(refusal(as).find("model.inputs[0].noise_param.as: 'std' is not one of variance, sigma"),
            std::string::npos);
  auto in_world = world_model();
  in_world["model"]["world"]["measurements"]["pos"]["noise_param"] = "sigma";
  EXPECT_NE(refusal(in_world).find("model.world.measurements.pos.noise_param: a world's sensor "
                                   "sets no parameter"),
            std::string::npos);
}

TEST(ModelWorldNoise, AModelThatLinksNothingSaysWhichKeyToAdd) {
  auto j = walk_model();
  j["model"]["measurements"]["pos"].erase("noise_param");
  auto s = scenario(j);
  ASSERT_TRUE(s);
  EXPECT_TRUE(s->noise_links().empty());
  auto st = check_noise_links(*s, kFile);
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.exit_code(), kExitInvalid);
  EXPECT_NE(st.error().find("models/noise.json: no column's noise is linked to a parameter: add "
                            "\"noise_param\" to a channel (model.measurements.NAME.noise_param)"),
            std::string::npos)
      << st.error();
}

}  // namespace
}  // namespace kfw::model_world_noise
