// Sessions version 3 and the retired built-ins (issue 27, /work/shared/STAGE.md "Formats and
// compatibility"): a preset or session that names a retired scenario loads as its shipped model
// file with its values and one notice; version 3 refuses unknown keys, versions 1 and 2 note them;
// a higher version was written by a newer kfw; the writer writes version 3.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "common/working_directory.h"
#include "core/retired.h"
#include "core/scenario.h"
#include "document/document.h"
#include "document/preset.h"
#include "document/session.h"

namespace kfw {
namespace sessions_v3_test {
namespace {

namespace fs = std::filesystem;

const fs::path kFixtureDir = fs::path(KFW_SOURCE_DIR) / "tests" / "fixtures";

// The fixtures of the retired helicopter: the preset, the key its sessions changed and the value.
struct RetiredFixture {
  std::string name, changed_key;
  double changed_value, preset_value;
  bool has_data;
};

const std::vector<RetiredFixture> kRetired = {{"helicopter", "Q", 100.0, 67.24, true},
                                              {"broad_imu", "R", 1024.0, 4096.0, true}};

std::string fixture(const std::string& dir, const std::string& name) {
  return (kFixtureDir / dir / (name + ".json")).string();
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

const std::string kSessionHead = R"({"format": "kfw-session", "preset": "presets/radome.json",
  "scenario": "radome", "values": {"Q": 50}, "data": null, "snapshots": [], )";

TEST(SessionsV3, RetiredPresetsOfVersion1And2LoadAsTheModelFileWithTheirValuesAndOneNotice) {
  for (const auto& f : kRetired) {
    for (const char* dir : {"preset_v1", "preset_v2"}) {
      SCOPED_TRACE(f.name + " " + dir);
      const std::string path = fixture(dir, f.name);
      auto p = load_preset(path);
      ASSERT_TRUE(p.ok()) << p.error();
      EXPECT_EQ(p->scenario, "model");
      EXPECT_EQ(p->retired_from, "helicopter");
      ASSERT_TRUE(p->model.is_object());
      EXPECT_EQ(p->path, path);
      EXPECT_EQ(p->values.at(f.changed_key), f.preset_value);
      EXPECT_EQ(p->values.count("window"), 0u);
      EXPECT_EQ(p->dropped_keys, std::vector<std::string>{"window"});
      ASSERT_EQ(p->notices.size(), 1u);
      const std::string& n = p->notices[0];
      EXPECT_TRUE(contains(n, path + ": scenario 'helicopter' is retired")) << n;
      EXPECT_TRUE(contains(n, retired_model_path("helicopter"))) << n;
      EXPECT_TRUE(contains(n, "window")) << n;
      EXPECT_TRUE(contains(n, "kfw-cli upgrade")) << n;
      EXPECT_EQ(p->data_path.has_value(), f.name == "broad_imu");
      auto data = p->instance->simulate(p->values);
      ASSERT_TRUE(data.ok()) << data.error();
    }
  }
}

TEST(SessionsV3, RetiredSessionsOfVersion1And2LoadTheirValuesAndDropWindowAndViewState) {
  for (const auto& f : kRetired) {
    for (int version : {1, 2}) {
      SCOPED_TRACE(f.name + " v" + std::to_string(version));
      const std::string dir = "session_v" + std::to_string(version);
      const std::string path = fixture(dir, f.name);
      auto s = load_session(path);
      ASSERT_TRUE(s.ok()) << s.error();
      EXPECT_EQ(s->version, version);
      EXPECT_TRUE(s->notices.empty());
      testing::WorkingDirectory cwd(kFixtureDir / dir);
      auto d = Document::from_session(*s, path);
      ASSERT_TRUE(d.ok()) << d.error();
      EXPECT_EQ(d->preset().scenario, "model");
      EXPECT_EQ(d->values().at(f.changed_key), f.changed_value);
      EXPECT_EQ(d->values().count("window"), 0u);
      ASSERT_EQ(d->snapshots().size(), 1u);
      EXPECT_EQ(d->snapshots()[0].values.at(f.changed_key), f.preset_value);
      EXPECT_EQ(d->snapshots()[0].values.count("window"), 0u);
      // One notice for the retired scenario (naming `window`); version 2 held the helicopter
      // view's zoom and plots, one notice more.
      const auto& notices = d->notices();
      ASSERT_EQ(notices.size(), version == 2 ? 2u : 1u);
      EXPECT_TRUE(contains(notices[0], "scenario 'helicopter' is retired")) << notices[0];
      EXPECT_TRUE(contains(notices[0], "window")) << notices[0];
      if (version == 2) {
        EXPECT_TRUE(contains(notices[1], "view state")) << notices[1];
        EXPECT_FALSE(contains(d->view_state(), "\"zoom\"")) << d->view_state();
        EXPECT_TRUE(contains(d->view_state(), "\"geometry\"")) << d->view_state();
      }
    }
  }
}

TEST(SessionsV3, AVersion3SessionRefusesAnUnknownKeyNamingFileAndKey) {
  for (const std::string& extra :
       {std::string(R"("window": "", "snapshot": [])"),
        std::string(R"("window": "", "columns": {})"),
        std::string(
            R"("window": "", "mapping": {}, "tuning_set": [{"path": "a.csv", "mapp": {}}])")}) {
    SCOPED_TRACE(extra);
    auto s = parse_session(kSessionHead + R"("version": 3, )" + extra + "}", "old.json");
    ASSERT_FALSE(s.ok());
    EXPECT_TRUE(contains(s.error(), "old.json: ")) << s.error();
    EXPECT_TRUE(contains(s.error(), "unknown key")) << s.error();
  }
  auto s = parse_session(kSessionHead + R"("version": 3, "window": "", "snapshot": []})", "s.json");
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error(), "s.json: snapshot: unknown key 'snapshot' (did you mean 'snapshots'?)");
}

TEST(SessionsV3, AVersion2SessionWithAnUnknownKeyLoadsWithANoticeNamingUpgrade) {
  auto s =
      parse_session(kSessionHead + R"("version": 2, "window": "", "zoom_level": 3})", "s.json");
  ASSERT_TRUE(s.ok()) << s.error();
  ASSERT_EQ(s->notices.size(), 1u);
  EXPECT_TRUE(contains(s->notices[0], "s.json: zoom_level: unknown key")) << s->notices[0];
  EXPECT_TRUE(contains(s->notices[0], "kfw-cli upgrade s.json")) << s->notices[0];
  EXPECT_EQ(s->values.at("Q"), 50.0);
}

TEST(SessionsV3, AHigherVersionWasWrittenByANewerKfw) {
  auto s = parse_session(kSessionHead + R"("version": 99, "window": ""})", "s.json");
  ASSERT_FALSE(s.ok());
  EXPECT_TRUE(contains(s.error(), "s.json: version: 99: written by a newer kfw (version 99)"))
      << s.error();
  auto zero = parse_session(kSessionHead + R"("version": 0, "window": ""})", "s.json");
  ASSERT_FALSE(zero.ok());
  EXPECT_FALSE(contains(zero.error(), "newer")) << zero.error();
}

TEST(SessionsV3, ASavedSessionIsVersion3AndRoundTripsWithoutNotices) {
  auto d = Document::open(std::string(KFW_SOURCE_DIR) + "/presets/helicopter.json", std::nullopt);
  ASSERT_TRUE(d.ok()) << d.error();
  EXPECT_TRUE(d->notices().empty());
  ASSERT_TRUE(d->set_value("Q", 12.5).ok());
  d->add_snapshot({"pin", d->values()});
  d->set_view_state(R"({"geometry":"AA==","zoom":{}})");
  const Session s = d->to_session();
  const std::string text = session_to_json(s);
  EXPECT_TRUE(contains(text, "\"version\": 3")) << text;
  auto back = parse_session(text, "s.json");
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_EQ(back->version, 3);
  EXPECT_EQ(back->scenario, "model");
  EXPECT_EQ(session_to_json(*back), text);
  auto reopened = Document::from_session(*back, "s.json");
  ASSERT_TRUE(reopened.ok()) << reopened.error();
  EXPECT_TRUE(reopened->notices().empty());
  EXPECT_EQ(reopened->values(), d->values());
  EXPECT_EQ(reopened->snapshots(), d->snapshots());
  EXPECT_EQ(reopened->view_state(), d->view_state());  // a model's view state is its own
}

// The built-ins are gone (issue 30): their names build nothing, and each names a shipped model
// file that a preset naming it loads as.
TEST(SessionsV3, RetiredNamesAreNoScenarioAndLoadTheirModelFiles) {
  EXPECT_EQ(scenarios().names(), std::vector<std::string>{"model"});
  for (const auto& r : kRetiredScenarios) {
    const std::string name(r.scenario);
    EXPECT_EQ(scenarios().from_preset(name), nullptr) << name;
    // Its name with a model block is no model: refused, naming the key.
    auto built = parse_preset(
        R"({"format": "kfw-preset", "version": 2, "scenario": ")" + name + R"(", "model": {}})",
        "r.json");
    ASSERT_FALSE(built.ok()) << name;
    EXPECT_TRUE(contains(built.error(), "model: only a preset whose scenario is a model"))
        << built.error();
    EXPECT_TRUE(fs::is_regular_file(retired_model_path(name))) << retired_model_path(name);
    auto old = load_preset(fixture("preset_v2", name));
    ASSERT_TRUE(old.ok()) << name << ": " << old.error();
    EXPECT_EQ(old->scenario, "model") << name;
    EXPECT_EQ(old->retired_from, name);
  }
  const std::string unknown = unknown_scenario("helicoptr");
  EXPECT_TRUE(contains(unknown, "\"scenario\": \"model\"")) << unknown;
  EXPECT_FALSE(contains(unknown, "helicopter")) << unknown;
}

TEST(SessionsV3, AMissingShippedModelFileIsRefusedNamingTheFileAndTheScenario) {
  const fs::path empty = fs::temp_directory_path() / ("kfw_v3_" + std::to_string(::getpid()));
  fs::create_directories(empty);
  const char* before = std::getenv("KFW_PRESETS");
  const std::string saved = before ? before : "";
  ::setenv("KFW_PRESETS", empty.c_str(), 1);
  auto p = load_preset(fixture("preset_v2", "helicopter"));
  if (before) {
    ::setenv("KFW_PRESETS", saved.c_str(), 1);
  } else {
    ::unsetenv("KFW_PRESETS");
  }
  fs::remove_all(empty);
  ASSERT_FALSE(p.ok());
  EXPECT_EQ(p.exit_code(), kExitInvalid);
  EXPECT_TRUE(contains(p.error(), "scenario 'helicopter' is retired")) << p.error();
  EXPECT_TRUE(contains(p.error(), (empty / "helicopter.json").string())) << p.error();
}

}  // namespace
}  // namespace sessions_v3_test
}  // namespace kfw
