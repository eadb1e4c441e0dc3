// Every file format kfw has written, as saved by commit d410b8e (tests/fixtures/README.md: presets
// v1 and v2, model files v1, sessions v1 and v2, Monte Carlo and sweep parts v1), loads through the
// engine's own loaders with the values it was saved with; each seed preset still reports the
// metrics listed by `kfw-cli metrics` at that commit.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "common/fixture_metric_changes.h"
#include "common/working_directory.h"
#include "core/metrics.h"
#include "core/retired.h"
#include "core/scenario.h"
#include "document/document.h"
#include "document/preset.h"
#include "document/session.h"
#include "experiment/grammar.h"
#include "experiment/monte_carlo.h"
#include "experiment/sweep.h"

namespace kfw {
namespace format_fixtures_test {
namespace {

namespace fs = std::filesystem;

const fs::path kFixtureDir = fs::path(KFW_SOURCE_DIR) / "tests" / "fixtures";
const std::string kBroadLog = "data/broad/10_undisturbed_slow_translation_A.csv";

// A seed preset: a few of its values as saved, and the value its sessions changed.
struct SeedFixture {
  std::string name, scenario;
  std::vector<std::pair<std::string, double>> values;
  std::string changed_key;
  double changed_value = 0.0;
  bool simulates = true;  // Monte Carlo parts exist only for presets without a data file

  double preset_value(const std::string& key) const {
    for (const auto& [k, v] : values) {
      if (k == key) return v;
    }
    ADD_FAILURE() << name << ": no expected value of " << key;
    return NAN;
  }
};

const std::vector<SeedFixture>& seed_fixtures() {
  static const std::vector<SeedFixture> seeds = {
      {"helicopter",
       "helicopter",
       {{"Q", 67.24}, {"R", 1.96}, {"gamma", 0.0}, {"sim.seed", 1.0}, {"window", 50.0}},
       "Q",
       100.0},
      {"broad_imu",
       "helicopter",
       {{"Q", 256.0}, {"R", 4096.0}, {"gamma", 0.003}, {"P0_bias", 4.0}},
       "R",
       1024.0,
       false},
      {"radome",
       "radome",
       {{"Q", 100.0}, {"R", 1e-6}, {"grid.n_psi", 7.0}, {"markov.stay", 0.99}},
       "Q",
       50.0},
      {"ballbeam",
       "ballbeam",
       {{"Q", 0.5013}, {"R", 4e-6}, {"filter", 1.0}, {"sim.seed", 3.0}, {"sim.theta_max", 0.785}},
       "Q",
       0.25},
      {"underwater",
       "underwater",
       {{"q_pos", 0.07}, {"sigma_range", 0.1}, {"sim.outliers", 276.0}, {"sim.seed", 4.0}},
       "q_pos",
       0.1},
  };
  return seeds;
}

// Issue 27 (sessions version 3): a file that names a retired built-in (core/retired.h) loads as
// its shipped model file, so its preset's scenario is "model", and the built-in's view parameter
// `window`, which the model file lacks, is dropped (with a notice,
// tests/engine/sessions_v3_test.cpp).
std::string loads_as(const std::string& scenario) {
  return find_retired(scenario) ? "model" : scenario;
}

bool dropped_on_load(const std::string& scenario, const std::string& key) {
  return find_retired(scenario) && key == "window";
}

fs::path fixture(const std::string& dir, const std::string& name) {
  return kFixtureDir / dir / (name + ".json");
}

nlohmann::json fixture_json(const fs::path& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  return nlohmann::json::parse(in, nullptr, false);
}

// The shared log as a preset in tests/fixtures/<dir>/ names it, resolved against the source tree.
std::string broad_log_path() {
  return (fs::path(KFW_SHARED_DIR) / kBroadLog).lexically_normal().string();
}

TEST(FormatFixtures, PresetsOfVersion1And2LoadTheValuesTheyWereSavedWith) {
  for (const auto& s : seed_fixtures()) {
    SCOPED_TRACE(s.name);
    auto v1 = load_preset(fixture("preset_v1", s.name).string());
    auto v2 = load_preset(fixture("preset_v2", s.name).string());
    ASSERT_TRUE(v1.ok()) << v1.error();
    ASSERT_TRUE(v2.ok()) << v2.error();
    EXPECT_EQ(v1->version, 1);
    EXPECT_EQ(v2->version, 2);
    for (const Preset* p : {&*v1, &*v2}) {
      EXPECT_EQ(p->scenario, loads_as(s.scenario));
      for (const auto& [key, value] : s.values) {
        if (dropped_on_load(s.scenario, key)) {
          EXPECT_EQ(p->values.count(key), 0u) << key << " in " << p->path;
        } else {
          EXPECT_EQ(p->values.at(key), value) << key << " in " << p->path;
        }
      }
      if (s.simulates) {
        EXPECT_FALSE(p->data_path) << p->path;
      } else {
        ASSERT_TRUE(p->data_path) << p->path;
        EXPECT_EQ(*p->data_path, broad_log_path()) << p->path;
      }
    }
    // Version 1 holds the same values and ranges; it has no flags: the scenario's table gives them
    // (presets/README.md), where version 2 carries the preset's own.
    EXPECT_EQ(v1->values, v2->values);
    EXPECT_EQ(v1->ranges, v2->ranges);
    // Issue 27: a retired scenario's files take the flags of the model file they load as.
    if (find_retired(s.scenario)) {
      EXPECT_EQ(v1->meta, v2->meta);
    } else {
      for (const auto& spec : v1->instance->params().specs()) {
        EXPECT_EQ(v1->meta.at(spec.key), (ParamMeta{spec.tunable, spec.scale_group})) << spec.key;
      }
    }
    EXPECT_TRUE(v2->meta.at(s.changed_key).tunable);
  }
}

TEST(FormatFixtures, ModelFilesOfVersion1LoadTheirModelAndRun) {
  struct ModelFixture {
    std::string name, primary, filter;
    std::vector<std::pair<std::string, double>> values;
  };
  const std::vector<ModelFixture> models = {
      {"ca1d", "x", "kf", {{"q_jerk", 0.05}, {"sigma_r", 1.0}, {"sim.dt", 0.05}}},
      {"cv1d", "x", "kf", {{"sigma_a", 0.5}, {"sigma_r", 2.0}, {"sim.dt", 0.1}}},
      {"cv2d", "px", "kf", {{"sigma_r", 5.0}, {"vx0", 10.0}, {"vy0", 5.0}}},
      {"helicopter_indirect", "theta", "kf", {{"Q", 67.24}, {"R", 1.96}, {"sim.dt", 0.02}}},
      {"pendulum", "theta", "ekf", {{"L", 1.0}, {"theta0", 1.0}, {"g", 9.81}}},
      {"range_bearing", "px", "ekf", {{"sigma_range", 10.0}, {"py0", 900.0}, {"vy0", -30.0}}},
      {"singer", "x", "kf", {{"tau", 10.0}, {"sigma_m", 2.0}, {"sigma_r", 5.0}}},
  };
  for (const auto& m : models) {
    SCOPED_TRACE(m.name);
    auto p = load_preset(fixture("model_v1", m.name).string());
    ASSERT_TRUE(p.ok()) << p.error();
    EXPECT_EQ(p->version, 2);  // d410b8e writes a model file inside a version-2 preset
    EXPECT_EQ(p->scenario, "model");
    ASSERT_TRUE(p->model.is_object());
    EXPECT_EQ(p->model.at("version"), 1);
    EXPECT_EQ(p->model.at("primary"), m.primary);
    EXPECT_EQ(p->model.at("filter"), m.filter);
    ASSERT_NE(p->instance, nullptr);
    EXPECT_EQ(p->instance->primary_state(), m.primary);
    for (const auto& [key, value] : m.values)
      EXPECT_EQ(p->values.at(key), value) << key;
    auto data = p->instance->simulate(p->values);
    ASSERT_TRUE(data.ok()) << data.error();
    auto run = p->instance->run(*data, p->values);
    ASSERT_TRUE(run.ok()) << run.error();
    EXPECT_TRUE((*run)->metrics.count("rmse"));
  }
}

TEST(FormatFixtures, SessionsOfVersion1And2LoadTheirValuesSnapshotsAndData) {
  for (const auto& s : seed_fixtures()) {
    SCOPED_TRACE(s.name);
    std::vector<Session> loaded;
    for (int version : {1, 2}) {
      const std::string dir = "session_v" + std::to_string(version);
      const fs::path path = fixture(dir, s.name);
      EXPECT_EQ(fixture_json(path).at("version"), version) << path;
      auto session = load_session(path.string());
      ASSERT_TRUE(session.ok()) << session.error();
      // Paths are the session file's (issue 32, item 15): read from its folder.
      const auto beside = [&](const std::string& rel) {
        return (path.parent_path() / rel).lexically_normal().string();
      };
      EXPECT_EQ(session->preset_path, beside("../../../presets/" + s.name + ".json"));
      EXPECT_EQ(session->scenario, s.scenario);
      EXPECT_EQ(session->values.at(s.changed_key), s.changed_value);
      for (const auto& [key, value] : s.values) {
        if (key != s.changed_key) {
          EXPECT_EQ(session->values.at(key), value) << key;
        }
      }
      ASSERT_EQ(session->snapshots.size(), 1u);
      EXPECT_EQ(session->snapshots[0].name, "preset");
      EXPECT_EQ(session->snapshots[0].values.at(s.changed_key), s.preset_value(s.changed_key));
      EXPECT_TRUE(session->tuning_set.empty());
      if (s.name == "helicopter") {
        EXPECT_EQ(session->data_path, beside("../../../data/helicopter.csv"));
        EXPECT_EQ(session->data_hash, "3eb3381adfa4efe3");
        ASSERT_EQ(session->mapping.size(), 3u);  // version 1: "columns"
        for (const char* role : {"gyro", "angle", "truth"})
          EXPECT_EQ(session->mapping.at(role).column, role);
      } else if (s.name == "broad_imu") {
        EXPECT_EQ(session->data_path, beside("../../../../shared/" + kBroadLog));
        EXPECT_EQ(session->data_hash, "3cb65696bf6e627d");
        EXPECT_TRUE(session->mapping.blank());
      } else {
        EXPECT_FALSE(session->data_path);
        EXPECT_TRUE(session->mapping.blank());
      }
      // The window layout: ':'-separated base64 in version 1, a JSON object in version 2.
      ASSERT_FALSE(session->window_state.empty());
      EXPECT_EQ(session->window_state.front() == '{', version == 2) << session->window_state;

      // Opened from its own directory, as it was saved: the preset and values are applied.
      testing::WorkingDirectory cwd(kFixtureDir / dir);
      auto doc = Document::from_session(*session, path.string());
      ASSERT_TRUE(doc.ok()) << doc.error();
      EXPECT_EQ(doc->preset().scenario, loads_as(s.scenario));
      EXPECT_EQ(doc->values().at(s.changed_key), s.changed_value);
      // Issue 27: a retired scenario's snapshots lose the keys its model file lacks (`window`).
      std::vector<Snapshot> kept = session->snapshots;
      for (auto& snap : kept) {
        if (find_retired(s.scenario)) snap.values.erase("window");
      }
      EXPECT_EQ(doc->snapshots(), kept);
      EXPECT_EQ(doc->data().has_value(), session->data_path.has_value());
      // The shared log does not change (data/helicopter.csv may be regenerated: a notice then).
      if (s.name == "broad_imu" && fs::exists(*session->data_path)) {
        auto hash = file_hash(*session->data_path);
        ASSERT_TRUE(hash.ok()) << hash.error();
        EXPECT_EQ(*hash, session->data_hash);
      }
      loaded.push_back(std::move(*session));
    }
    // Both versions hold the same state.
    ASSERT_EQ(loaded.size(), 2u);
    EXPECT_EQ(loaded[0].values, loaded[1].values);
    EXPECT_EQ(loaded[0].snapshots, loaded[1].snapshots);
    EXPECT_EQ(loaded[0].data_path, loaded[1].data_path);
    EXPECT_EQ(loaded[0].data_hash, loaded[1].data_hash);
    EXPECT_EQ(loaded[0].mapping, loaded[1].mapping);
  }
}

TEST(FormatFixtures, MonteCarloPartsOfVersion1LoadEveryRunAsSaved) {
  for (const auto& s : seed_fixtures()) {
    if (!s.simulates) continue;
    SCOPED_TRACE(s.name);
    const fs::path path = fixture("montecarlo_v1", s.name);
    const nlohmann::json j = fixture_json(path);
    EXPECT_EQ(j.at("version"), 1);
    auto part = part_from_json(j, path.string());
    ASSERT_TRUE(part.ok()) << part.error();
    EXPECT_EQ(part->scenario, s.scenario);
    EXPECT_EQ(part->source, "presets/" + s.name + ".json");
    EXPECT_EQ(part->seeds, (std::vector<long long>{1, 2}));
    EXPECT_EQ(part->shard.index, 1u);
    EXPECT_EQ(part->shard.count, 1u);
    EXPECT_EQ(part->t, j.at("t").get<std::vector<double>>());
    ASSERT_EQ(part->runs.size(), 2u);
    for (std::size_t i = 0; i < part->runs.size(); ++i) {
      const SeedRun& r = part->runs[i];
      const nlohmann::json& saved = j.at("runs").at(i);
      EXPECT_EQ(r.seed, static_cast<long long>(i + 1));
      EXPECT_FALSE(r.stopped());
      EXPECT_EQ(r.metrics.size(), saved.at("metrics").size());
      for (const auto& [key, value] : saved.at("metrics").items())
        EXPECT_EQ(r.metrics.at(key), value.get<double>()) << "seed " << r.seed << ": " << key;
      EXPECT_EQ(r.undefined.size(), saved.value("undefined", nlohmann::json::object()).size());
      EXPECT_TRUE(r.metrics.count("rmse"));
    }
    ASSERT_TRUE(part->nees);
    EXPECT_EQ(part->nees->count.size(), part->t.size());
    EXPECT_EQ(part->nis.size(), j.at("nis").size());
    EXPECT_TRUE(part->error && part->variance);
    // A part of one shard of one is the whole set: it merges alone.
    auto merged = merge_montecarlo_parts({*part}, {path.string()});
    ASSERT_TRUE(merged.ok()) << merged.error();
    const MonteCarloSummary summary = summarize_monte_carlo(*merged);
    EXPECT_EQ(summary.completed, 2u);
    EXPECT_TRUE(summary.stopped.empty());
    EXPECT_EQ(summary.metrics.at("rmse").n, 2u);
  }
}

// kfw-cli merge is the reader of sweep parts (tests/cli/format_fixtures_cli_test.cpp); here each
// part's grid, metric and base values are read back through the engine's sweep and grammar.
TEST(FormatFixtures, SweepPartsOfVersion1NameAGridMetricAndValuesTheEngineAccepts) {
  for (const auto& s : seed_fixtures()) {
    SCOPED_TRACE(s.name);
    const nlohmann::json j = fixture_json(fixture("sweep_v1", s.name));
    EXPECT_EQ(j.at("kind"), "sweep");
    EXPECT_EQ(j.at("version"), 1);
    EXPECT_EQ(j.at("scenario"), s.scenario);
    EXPECT_EQ(j.at("metric"), "rmse");
    EXPECT_EQ(j.at("direction"), "lower");
    EXPECT_EQ(j.at("shard"), (nlohmann::json{{"index", 1}, {"count", 1}}));
    // The part names a retired built-in; its model file has the same keys and metrics.
    auto preset = load_preset(retired_model_path(j.at("scenario").get<std::string>()));
    ASSERT_TRUE(preset.ok()) << preset.error();
    const ParamTable& table = preset->instance->params();
    EXPECT_TRUE(is_declared_metric(*preset->instance, j.at("metric").get<std::string>()));
    std::vector<SweepAxis> axes;
    for (const auto& a : j.at("axes")) {
      const std::string text = a.at("key").get<std::string>() + "=" + a.at("lo").dump() + ":" +
                               a.at("hi").dump() + ":" + a.at("n").dump() +
                               (a.at("log").get<bool>() ? ":log" : ":lin");
      auto axis = parse_sweep_axis(table, text);
      ASSERT_TRUE(axis.ok()) << axis.error();
      EXPECT_EQ(axis->key, s.changed_key);
      EXPECT_EQ(axis->lo, a.at("lo").get<double>());
      EXPECT_EQ(axis->hi, a.at("hi").get<double>());
      axes.push_back(*axis);
    }
    ASSERT_EQ(axes.size(), 1u);
    EXPECT_EQ(grid_size(axes, 1000), j.at("total_points").get<std::size_t>());
    const auto& points = j.at("points");
    ASSERT_EQ(points.size(), 3u);
    const std::vector<double> grid = axes[0].values();
    for (std::size_t i = 0; i < points.size(); ++i) {
      EXPECT_EQ(points[i].at("index"), i);
      EXPECT_EQ(points[i].at("at").at(0).get<double>(), grid[i]);
      EXPECT_GT(points[i].at("value").get<double>(), 0.0);
    }
    for (const auto& [key, value] : j.at("base").items()) {
      if (find_retired(s.scenario)->is_dropped(key)) continue;  // the helicopter's window
      auto st = table.check(key, value.get<double>());
      EXPECT_TRUE(st.ok()) << key << ": " << st.error();
    }
    for (const auto& [key, value] : s.values)
      EXPECT_EQ(j.at("base").at(key).get<double>(), value) << key;
  }
}

// The first column of a `kfw-cli metrics` listing.
std::vector<std::string> listed_keys(const fs::path& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  std::vector<std::string> keys;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty()) keys.push_back(line.substr(0, line.find('\t')));
  }
  return keys;
}

TEST(FormatFixtures, SeedPresetsReportTheMetricsListedAtTheFixturesCommit) {
  for (const auto& s : seed_fixtures()) {
    SCOPED_TRACE(s.name);
    auto p = load_preset(std::string(KFW_SOURCE_DIR) + "/presets/" + s.name + ".json");
    ASSERT_TRUE(p.ok()) << p.error();
    std::vector<std::string> keys;
    for (const auto& spec : shared_metric_specs())
      keys.push_back(spec.key);
    for (const auto& spec : p->instance->metric_specs())
      keys.push_back(spec.key);
    const auto saved = listed_keys(kFixtureDir / "metrics" / (s.name + ".tsv"));
    EXPECT_GT(saved.size(), 10u);
    // The differences CHANGES.md lists (common/fixture_metric_changes.h), and nothing else.
    EXPECT_EQ(testing::compare_with_changes(keys, saved, testing::fixture_metric_changes(s.name)),
              "");
  }
}

}  // namespace
}  // namespace format_fixtures_test
}  // namespace kfw
