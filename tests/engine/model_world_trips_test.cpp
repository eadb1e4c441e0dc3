// Issue 27, model files part 2 — the newcomer trips of the engine, one section per trip; each
// test fails on the engine before the fix of its section.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "common/time_scale.h"
#include "core/scenario.h"
#include "data/json_io.h"
#include "document/preset.h"
#include "model/model_scenario.h"

namespace kfw::world_trips {
namespace {

using nlohmann::json;

const std::string kFile = "models/trips.json";

// Position and velocity, one linear channel `pos` reading column z, sim.dt = 0.1 s.
json base() {
  return json::parse(R"json({
    "format": "kfw-preset", "version": 1, "scenario": "model", "title": "trips",
    "parameters": {
      "q": {"value": 1, "min": 1e-6, "max": 1e6, "unit": "", "scale": "log", "label": "q"},
      "r": {"value": 1, "min": -10, "max": 10, "unit": "m²", "scale": "linear", "label": "r"},
      "sim.dt": {"value": 0.1, "min": 1e-3, "max": 1, "unit": "s", "scale": "log", "label": "dt"}
    },
    "model": {
      "version": 1,
      "states": [{"name": "px", "unit": "m"}, {"name": "vx", "unit": "m/s"}],
      "x0": ["0", "0"],
      "P0": ["1", "1"],
      "process": {"F": [["1", "dt"], ["0", "1"]],
                  "Q": [["q*dt^3/3", "q*dt^2/2"], ["q*dt^2/2", "q*dt"]]},
      "measurements": {"pos": {"roles": ["z"], "H": [["1", "0"]], "R": ["r"]}},
      "truth": {"px": "px_true"}
    }
  })json");
}

// A four-state model, for matrices whose rows can be short in the middle.
json four_states() {
  json j = base();
  j["model"]["states"] = {"px", "py", "vx", "vy"};
  j["model"]["x0"] = {"0", "0", "0", "0"};
  j["model"]["P0"] = {"1", "1", "1", "1"};
  j["model"]["process"] = json::parse(R"({
    "F": [["1", "0", "dt", "0"], ["0", "1", "0", "dt"], ["0", "0", "1", "0"], ["0", "0", "0", "1"]],
    "Q": ["q*dt", "q*dt", "q*dt", "q*dt"]})");
  j["model"]["measurements"]["pos"]["H"] = json::parse(R"([["1", "0", "0", "0"]])");
  return j;
}

Expected<std::unique_ptr<Scenario>> load(const json& j) {
  return make_model_scenario(j, kFile);
}

// Expects the model to be refused when it loads (exit 2), with every fragment in one line that
// starts with the file.
void expect_refused(const json& j, const std::vector<std::string>& fragments) {
  auto s = load(j);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.exit_code(), kExitInvalid) << s.error();
  EXPECT_EQ(s.error().rfind(kFile + ": ", 0), 0u) << s.error();
  EXPECT_EQ(s.error().find('\n'), std::string::npos) << s.error();
  for (const auto& f : fragments)
    EXPECT_NE(s.error().find(f), std::string::npos) << "'" << f << "' not in: " << s.error();
}

// ---- 1. A dimension message names the short row ---------------------------------------------

TEST(ModelWorldTrips, AShortRowIsNamedByItsIndex) {
  json j = four_states();
  j["model"]["process"]["F"][2] = {"0", "0", "1"};
  expect_refused(j, {"model.process.F: wrong dimensions: expected 4×4, model.process.F[2] has "
                     "3 entries"});
  j = four_states();
  j["model"]["process"]["F"][0] = {"1", "0", "dt", "0", "0"};
  expect_refused(j, {"expected 4×4, model.process.F[0] has 5 entries"});
  j = four_states();
  j["model"]["process"]["F"][1] = "1";
  expect_refused(j, {"expected 4×4, model.process.F[1] is not a row"});
  j = four_states();
  j["model"]["process"]["Q"] = json::parse(
      R"([["q", "0", "0", "0"], ["0", "q", "0", "0"], ["0", "0", "q"], ["0", "0", "0", "q"]])");
  expect_refused(j, {"model.process.Q: wrong dimensions: expected 4×4, model.process.Q[2] has 3"});
  // Every row of the same wrong length, or the wrong count of rows: said as a whole.
  j = four_states();
  j["model"]["process"]["F"] = json::parse(R"([["1", "0", "dt"], ["0", "1", "0"],
                                                ["0", "0", "1"], ["0", "0", "0"]])");
  expect_refused(j, {"expected 4×4, got 4 rows of 3"});
  j = four_states();
  j["model"]["process"]["F"].erase(3);
  expect_refused(j, {"expected 4×4, got 3 rows of 4"});
}

// ---- 2. "Did you mean" for keys and symbols -------------------------------------------------

TEST(ModelWorldTrips, AMisspeltKeySuggestsTheNearestOne) {
  json j = base();
  j["model"]["mesurements"] = j["model"]["measurements"];
  j["model"].erase("measurements");
  expect_refused(j, {"model.mesurements: unknown key (did you mean 'measurements'?)"});
  j = base();
  j["model"]["measurements"]["pos"]["gte"] = 0.99;
  expect_refused(j, {"model.measurements.pos.gte: unknown key (did you mean 'gate'?)"});
  j = base();
  j["model"]["process"]["QQ"] = j["model"]["process"]["Q"];
  expect_refused(j, {"model.process.QQ: unknown key (did you mean 'Q'?)"});
  // Nothing near: the known keys are listed.
  j = base();
  j["model"]["colour"] = "red";
  expect_refused(j, {"model.colour: unknown key (known: version, description, states"});
  j = base();
  j["model"]["truth"] = {{"pxx", "px_true"}};
  expect_refused(j, {"model.truth.pxx: unknown state (did you mean 'px'?)"});
}

TEST(ModelWorldTrips, AnUnknownSymbolSuggestsTheNearestUsableOne) {
  json j = base();
  j["model"]["measurements"]["pos"].erase("H");
  j["model"]["measurements"]["pos"]["h"] = {"sqrt(pz^2 + 1)"};
  expect_refused(j, {"model.measurements.pos.h[0]: unknown symbol 'pz' at position 6",
                     "(did you mean 'px'?)"});
  // Where only parameters may stand, a parameter is suggested, not the state of the same spelling.
  j = base();
  j["model"]["x0"][0] = "rr";
  expect_refused(j, {"model.x0[0]: unknown symbol 'rr'", "(did you mean 'r'?)"});
  j = base();
  j["model"]["process"]["F"][0][1] = "dtt";
  expect_refused(j, {"model.process.F[0][1]: unknown symbol 'dtt'", "(did you mean 'dt'?)"});
  // A function: the nearest function of the language.
  j = base();
  j["model"]["measurements"]["pos"]["R"][0] = "sqr(r^2)";
  expect_refused(j, {"unknown function 'sqr'", "(did you mean 'sqrt'?)"});
  // Nothing near: no suggestion.
  j = base();
  j["model"]["process"]["F"][0][1] = "zzzzzz";
  auto s = load(j);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().find("did you mean"), std::string::npos) << s.error();
}

// ---- 3. A Q or R that depends on dt, checked at every dt a run meets -------------------------

void expect_has(const std::string& text, const std::vector<std::string>& fragments) {
  for (const auto& f : fragments)
    EXPECT_NE(text.find(f), std::string::npos) << "'" << f << "' not in: " << text;
}

// n rows; t[k] from the intervals dt(k) (interval into row k), z = z(k), px_true = 0.
Dataset data(std::size_t n, double (*z)(std::size_t), double (*dt)(std::size_t) = nullptr) {
  Dataset d;
  d.source = "test.csv";
  auto& t = d.add("t", n);
  t[0] = 0.0;
  for (std::size_t k = 1; k < n; ++k)
    t[k] = t[k - 1] + (dt ? dt(k) : 0.1);
  auto& zc = d.add("z", n);
  for (std::size_t k = 0; k < n; ++k)
    zc[k] = z(k);
  auto& truth = d.add("px_true", n);
  std::fill(truth.begin(), truth.end(), 0.0);
  return d;
}

double zero(std::size_t) {
  return 0.0;
}

TEST(ModelWorldTrips, ADtDependentQNotPsdAtSimDtIsRefusedWhenTheFileLoads) {
  json j = base();
  j["model"]["process"]["Q"] = {"q*dt", "q*dt - 0.5"};
  expect_refused(j, {"model.process.Q: not positive semidefinite at dt = 0.1 s (sim.dt)",
                     "smallest eigenvalue -0.4"});
  j = base();
  j["model"]["measurements"]["pos"]["R"] = {"dt - 0.2"};
  expect_refused(j, {"model.measurements.pos.R: not positive semidefinite at dt = 0.1 s (sim.dt)"});
  // The continuous form's Q (Van Loan) from a PSD Qc stays accepted.
  j = base();
  j["model"]["process"] = json::parse(R"({"A": [["0", "1"], ["0", "0"]], "Qc": ["0", "q"]})");
  EXPECT_TRUE(load(j).ok());
}

TEST(ModelWorldTrips, ADtDependentQIsCheckedAtSimDtBeforeASimulation) {
  json j = base();
  j["model"]["process"]["Q"] = {"q*dt", "q*dt - 0.05"};  // PSD for dt ≥ 0.05 s
  auto s = load(j);
  ASSERT_TRUE(s.ok()) << s.error();
  ParamValues v = (*s)->params().defaults();
  v["sim.dt"] = 0.02;
  auto d = (*s)->simulate(v);
  ASSERT_FALSE(d.ok());
  EXPECT_EQ(d.exit_code(), kExitInvalid) << d.error();
  expect_has(d.error(), {kFile + ": model.process.Q: not positive semidefinite at dt = 0.02 s "
                                 "(sim.dt)"});
}

TEST(ModelWorldTrips, ADtDependentQIsCheckedAtEveryIntervalOfTheDataBeforeTheRun) {
  json j = base();
  j["model"]["process"]["Q"] = {"q*dt", "q*dt - 0.05"};
  auto s = load(j);
  ASSERT_TRUE(s.ok()) << s.error();
  const auto v = (*s)->params().defaults();
  // Intervals of 0.1 s, 0.2 s and, into row 7, 0.02 s.
  const Dataset d = data(20, zero, [](std::size_t k) { return k == 7 ? 0.02 : k % 2 ? 0.1 : 0.2; });
  auto r = (*s)->run(d, v);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.exit_code(), kExitInvalid) << r.error();
  expect_has(r.error(), {kFile + ": model.process.Q: not positive semidefinite at dt = 0.02 s",
                         "the interval into step 7 of test.csv"});
  // Without the short interval the same data runs.
  const Dataset ok = data(20, zero, [](std::size_t k) { return k % 2 ? 0.1 : 0.2; });
  EXPECT_TRUE((*s)->run(ok, v).ok());
}

TEST(ModelWorldTrips, ADtDependentRIsCheckedAtEveryIntervalOfTheDataBeforeTheRun) {
  json j = base();
  j["model"]["measurements"]["pos"]["R"] = {"dt - 0.05"};
  auto s = load(j);
  ASSERT_TRUE(s.ok()) << s.error();
  const Dataset d = data(20, zero, [](std::size_t k) { return k == 12 ? 0.03 : 0.1; });
  auto r = (*s)->run(d, (*s)->params().defaults());
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.exit_code(), kExitInvalid) << r.error();
  expect_has(r.error(), {kFile + ": model.measurements.pos.R: not positive semidefinite at dt = "
                                 "0.03 s (the interval into step 12 of test.csv)"});
}

// ---- 4. An update that cannot happen ---------------------------------------------------------

// The run of `j` on `d` with filter `filter`.
Expected<std::shared_ptr<const RunResult>> run_with(const json& j, const Dataset& d,
                                                    const std::string& filter) {
  auto s = load(j);
  if (!s) return s.err();
  ParamValues v = (*s)->params().defaults();
  if (auto st = (*s)->params().apply_assignment("filter=" + filter, v); !st) return st.err();
  return (*s)->run(d, v);
}

TEST(ModelWorldTrips, AnSThatIsNotPositiveDefiniteAtTheFirstDueUpdateStopsTheRun) {
  json j = base();
  j["parameters"]["r"]["value"] = 0;
  j["model"]["measurements"]["pos"]["H"] = json::parse(R"([["0", "0"]])");  // S = H P Hᵀ + R = 0
  const Dataset d = data(20, zero);
  for (const char* filter : {"kf", "ekf", "ukf"}) {
    SCOPED_TRACE(filter);
    auto r = run_with(j, d, filter);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.exit_code(), kExitFailed) << r.error();
    expect_has(r.error(),
               {"step 0 (t = 0 s): channel 'pos': its first due update cannot be "
                "applied",
                "not positive definite", "model.measurements.pos.H", "model.measurements.pos.R"});
  }
}

TEST(ModelWorldTrips, AMeasurementFunctionThatIsNotFiniteAtTheFirstDueUpdateStopsTheRun) {
  json j = base();
  j["model"]["measurements"]["pos"].erase("H");
  j["model"]["measurements"]["pos"]["h"] = {"sqrt(px - 5)"};  // NaN near px = 0
  const Dataset d = data(20, zero);
  for (const char* filter : {"ekf", "ukf"}) {
    SCOPED_TRACE(filter);
    auto r = run_with(j, d, filter);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.exit_code(), kExitFailed) << r.error();
    expect_has(r.error(), {"step 0 (t = 0 s): channel 'pos'",
                           "model.measurements.pos.h[0] = \"sqrt(px - 5)\" is not finite"});
  }
}

// H = 0.25 and R = 0.01 until t = 0.35 s, then both 0: S = 0 from step 4 on.
json fading_h() {
  json j = base();
  j["parameters"]["r"]["value"] = 0;
  j["model"]["measurements"]["pos"]["H"] =
      json::parse(R"j([["0.25*max(0, 0.35 - t)/(0.35 - t)", "0"]])j");
  j["model"]["measurements"]["pos"]["R"] = {"r + 0.01*max(0, 0.35 - t)/(0.35 - t)"};
  return j;
}

TEST(ModelWorldTrips, SkipsAfterASuccessfulFirstUpdateStayWarnings) {
  const Dataset d = data(20, zero);
  for (const char* filter : {"kf", "ukf"}) {
    SCOPED_TRACE(filter);
    auto r = run_with(fading_h(), d, filter);
    ASSERT_TRUE(r.ok()) << r.error();
    bool found = false;
    for (const auto& w : (*r)->warnings) {
      found =
          found || w.find("channel 'pos': 16 updates skipped, the first at step 4 (t = 0.4 s)") !=
                       std::string::npos;
    }
    EXPECT_TRUE(found) << ((*r)->warnings.empty() ? "no warning" : (*r)->warnings.front());
  }
}

TEST(ModelWorldTrips, AChannelThatAppliesNoUpdateFailsTheRun) {
  // The first due update is gated (z far off), every later one skipped: no update at all.
  json j = fading_h();
  j["model"]["measurements"]["pos"]["gate"] = 0.5;
  j["model"]["measurements"]["pos"]["H"] =
      json::parse(R"j([["max(0, 0.05 - t)/(0.05 - t)", "0"]])j");
  j["model"]["measurements"]["pos"]["R"] = {"r"};
  const Dataset d = data(20, [](std::size_t) { return 1e3; });
  for (const char* filter : {"kf", "ukf"}) {
    SCOPED_TRACE(filter);
    auto r = run_with(j, d, filter);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.exit_code(), kExitFailed) << r.error();
    expect_has(r.error(), {"channel 'pos' applied no update in the whole run: 19 skipped, 1 gated",
                           "the first at step 1 (t = 0.1 s)", "model.measurements.pos.R"});
  }
}

TEST(ModelWorldTrips, AChannelGatedEveryTimeIsADecisionNotABreakdown) {
  json j = base();
  j["model"]["measurements"]["pos"]["gate"] = 0.5;
  const Dataset d = data(20, [](std::size_t) { return 1e6; });
  for (const char* filter : {"kf", "ukf"}) {
    SCOPED_TRACE(filter);
    auto r = run_with(j, d, filter);
    ASSERT_TRUE(r.ok()) << r.error();
    EXPECT_EQ((*r)->metrics.at("gated.pos"), 20.0);
  }
}

// ---- 5. Parameters in the file's order --------------------------------------------------------

const std::string kModels = KFW_SOURCE_DIR "/presets/models/";

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

std::vector<std::string> keys(const ParamTable& t, std::size_t count) {
  std::vector<std::string> out;
  for (const auto& s : t.specs()) {
    if (out.size() < count) out.push_back(s.key);
  }
  return out;
}

TEST(ModelWorldTrips, AModelFilesParametersKeepTheFilesOrder) {
  std::string text = base().dump();
  // The parameters block in an order that is not alphabetical.
  nlohmann::ordered_json o = nlohmann::ordered_json::parse(text);
  nlohmann::ordered_json params = nlohmann::ordered_json::object();
  for (const char* k : {"r", "sim.dt", "q"})
    params[k] = o["parameters"][k];
  o["parameters"] = params;
  auto p = parse_preset(o.dump(2), kFile);
  ASSERT_TRUE(p.ok()) << p.error();
  EXPECT_EQ(keys(p->instance->params(), 3), (std::vector<std::string>{"r", "sim.dt", "q"}));
  // The standard parameters follow the declared ones.
  EXPECT_EQ(p->instance->params().specs()[3].key, "filter");
  // Written back, read again: the same order.
  auto again = parse_preset(preset_to_json(*p), kFile);
  ASSERT_TRUE(again.ok()) << again.error();
  EXPECT_EQ(keys(again->instance->params(), 3), (std::vector<std::string>{"r", "sim.dt", "q"}));
  // make_model_scenario keeps the order of an ordered document too.
  auto s = make_model_scenario(o, kFile);
  ASSERT_TRUE(s.ok()) << s.error();
  EXPECT_EQ(keys((*s)->params(), 3), (std::vector<std::string>{"r", "sim.dt", "q"}));
}

TEST(ModelWorldTrips, AFilterDeclaredInTheFileKeepsItsPlace) {
  nlohmann::ordered_json o = nlohmann::ordered_json::parse(base().dump());
  nlohmann::ordered_json params = nlohmann::ordered_json::object();
  params["r"] = o["parameters"]["r"];
  params["filter"] = {{"value", "ukf"}};
  params["q"] = o["parameters"]["q"];
  o["parameters"] = params;
  auto s = make_model_scenario(o, kFile);
  ASSERT_TRUE(s.ok()) << s.error();
  EXPECT_EQ(keys((*s)->params(), 3), (std::vector<std::string>{"r", "filter", "q"}));
  EXPECT_EQ((*s)->params().format("filter", (*s)->params().defaults().at("filter")), "ukf");
}

TEST(ModelWorldTrips, EveryShippedModelListsItsParametersInTheFilesOrder) {
  for (const char* name :
       {"cv1d", "cv2d", "ca1d", "singer", "range_bearing", "pendulum", "helicopter_indirect"}) {
    SCOPED_TRACE(name);
    const std::string path = kModels + name + ".json";
    auto p = load_preset(path);
    ASSERT_TRUE(p.ok()) << p.error();
    std::vector<std::string> declared;
    const auto file = nlohmann::ordered_json::parse(read(path));
    for (const auto& [key, value] : file.at("parameters").items())
      declared.push_back(key);
    ASSERT_GE(declared.size(), 5u);
    EXPECT_EQ(keys(p->instance->params(), declared.size()), declared);
  }
  // ballbeam.json (a model file since issue 30, the last seed preset to become one) lists the
  // retired built-in's keys in the built-in's order: the order of its version-2 preset fixture.
  auto h = load_preset(KFW_SOURCE_DIR "/presets/ballbeam.json");
  ASSERT_TRUE(h.ok()) << h.error();
  std::vector<std::string> own;
  const auto fixture =
      nlohmann::ordered_json::parse(read(KFW_SOURCE_DIR "/tests/fixtures/preset_v2/ballbeam.json"));
  ASSERT_EQ(fixture.at("scenario"), "ballbeam");
  for (const auto& [key, value] : fixture.at("parameters").items())
    own.push_back(key);
  ASSERT_EQ(own.size(), 16u);
  std::vector<std::string> kept;
  for (const auto& k : keys(h->instance->params(), 100)) {
    if (std::find(own.begin(), own.end(), k) != own.end()) kept.push_back(k);
  }
  EXPECT_EQ(kept, own);
}

TEST(ModelWorldTrips, AnOrderedDocumentKeepsTheFirstPlaceAndTheLastValueOfAKey) {
  auto j = parse_ordered_json_document(R"({"b": 1, "a": {"y": 1, "x": 2}, "b": 3})", "d.json");
  ASSERT_TRUE(j.ok()) << j.error();
  EXPECT_EQ(j->dump(), R"({"b":3,"a":{"y":1,"x":2}})");
  EXPECT_FALSE(parse_ordered_json_document(R"({"a": 1,})", "d.json").ok());
}

TEST(ModelWorldTrips, AnObjectOfManyKeysIsReadInOrderWithoutAQuadraticCost) {
  // 100 000 keys in one object: nlohmann's own ordered parser searches each key it inserts
  // (80 000 keys took 21 s); the reader's builder finds them by hashing.
  std::string big = "{";
  for (int i = 0; i < 100000; ++i)
    big += (i ? ", \"k" : "\"k") + std::to_string(i) + "\": 1";
  big += "}";
  std::string text = read(KFW_SOURCE_DIR "/presets/helicopter.json");
  text.replace(text.find("\"parameters\""), 0, "\"sim\": " + big + ", ");
  const auto start = std::chrono::steady_clock::now();
  auto p = parse_preset(text, "big.json");
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.error().find("big.json: sim.k0: unknown key"), std::string::npos) << p.error();
  EXPECT_LT(std::chrono::steady_clock::now() - start,
            std::chrono::seconds(5) * testing::kTimeScale);
}

// ---- 6. A primary of several states -----------------------------------------------------------

json cv2d() {
  return json::parse(read(kModels + "cv2d.json"));
}

TEST(ModelWorldTrips, APrimaryOfSeveralStatesIsTheEuclideanRmse) {
  json j = cv2d();
  j["model"]["version"] = 2;  // a list of states is a version-2 form
  j["model"]["primary"] = {"px", "py"};
  auto s = load(j);
  ASSERT_TRUE(s.ok()) << s.error();
  EXPECT_EQ((*s)->primary_state(), "");  // the scenario sets rmse itself
  ParamValues v = (*s)->params().defaults();
  v["sim.duration"] = 20;
  auto d = (*s)->simulate(v);
  ASSERT_TRUE(d.ok()) << d.error();
  auto r = (*s)->run(*d, v);
  ASSERT_TRUE(r.ok()) << r.error();
  const Metrics& m = (*r)->metrics;
  // sqrt(mean(ex² + ey²)), from the estimates and the truth.
  const auto states = (*r)->states();
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t k = 0; k < (*r)->steps(); ++k) {
    double e2 = 0.0;
    for (const auto& st : states) {
      if (st.key != "px" && st.key != "py") continue;
      const double e = (*st.estimate)[k] - (*st.truth)[k];
      e2 += e * e;
    }
    sum += e2;
    ++count;
  }
  const double expected = std::sqrt(sum / static_cast<double>(count));
  EXPECT_NEAR(m.at("rmse"), expected, 1e-10 * expected);
  const double px = m.at("rmse.px"), py = m.at("rmse.py");
  EXPECT_NEAR(m.at("rmse"), std::sqrt(px * px + py * py), 1e-9 * expected);
  // One state in a list, or as a name: the RMSE of that state, as before.
  for (const json& one : {json("px"), json::array({"px"})}) {
    j["model"]["primary"] = one;
    auto s1 = load(j);
    ASSERT_TRUE(s1.ok()) << s1.error();
    EXPECT_EQ((*s1)->primary_state(), "px");
    auto r1 = (*s1)->run(*d, v);
    ASSERT_TRUE(r1.ok()) << r1.error();
    EXPECT_EQ((*r1)->metrics.at("rmse"), (*r1)->metrics.at("rmse.px"));
  }
}

TEST(ModelWorldTrips, APrimaryOfSeveralStatesWithoutTheirTruthIsUndefined) {
  json j = base();
  j["model"]["version"] = 2;
  j["model"]["primary"] = {"px", "vx"};  // vx has no truth column
  auto s = load(j);
  ASSERT_TRUE(s.ok()) << s.error();
  auto r = (*s)->run(data(20, zero), (*s)->params().defaults());
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ((*r)->metrics.count("rmse"), 0u);
  ASSERT_EQ((*r)->undefined.count("rmse"), 1u);
  EXPECT_NE((*r)->undefined.at("rmse").find("'vx'"), std::string::npos)
      << (*r)->undefined.at("rmse");
}

TEST(ModelWorldTrips, ABadPrimaryIsRefused) {
  json j = base();
  j["model"]["primary"] = {"px", "py"};
  expect_refused(j, {"model.primary: a list of states is a version-2 form: set \"version\": 2"});
  j["model"]["version"] = 2;
  j["model"]["primary"] = json::array();
  expect_refused(j, {"model.primary: expected a state or a non-empty list of states"});
  j["model"]["primary"] = {"px", "pxx"};
  expect_refused(j, {"model.primary[1]: 'pxx' is not a state (did you mean 'px'?)"});
  j["model"]["primary"] = {"px", "px"};
  expect_refused(j, {"model.primary[1]: 'px' is named twice"});
  j["model"]["primary"] = 3;
  expect_refused(j, {"model.primary: expected a state or a non-empty list of states"});
}

}  // namespace
}  // namespace kfw::world_trips
