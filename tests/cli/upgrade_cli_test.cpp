// kfw-cli upgrade FILE [--check] [--out F] (issue 27): each old fixture (copied to a scratch
// folder, never the fixture itself) becomes a file that loads with no notice and the same values,
// its original kept as FILE.bak; --check exits 0 current, 1 would change, 2 unreadable; a model
// file is already current; a version-1 part cannot be upgraded; bad input is refused, never hangs.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "common/cli_runner.h"
#include "common/working_directory.h"
#include "document/document.h"
#include "document/preset.h"
#include "document/session.h"

namespace kfw {
namespace upgrade_cli_test {
namespace {

namespace fs = std::filesystem;

using kfw::testing::cli;
using kfw::testing::run_command;

const fs::path kFixtureDir = fs::path(KFW_SOURCE_DIR) / "tests" / "fixtures";
const std::vector<std::string> kSeeds = {"helicopter", "broad_imu", "radome", "ballbeam",
                                         "underwater"};

std::string text_of(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// A scratch folder of this test process, emptied.
fs::path scratch(const std::string& name) {
  const fs::path d =
      fs::temp_directory_path() / ("kfw_upgrade_" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// kfw-cli ARGS run in `dir` (a session's paths are relative to the current directory).
kfw::testing::CliOutput cli_in(const fs::path& dir, const std::string& args) {
  return run_command("cd " + dir.string() + " && timeout 60 " + KFW_CLI + " " + args + " 2>&1");
}

TEST(UpgradeCli, EveryOldPresetBecomesOneThatLoadsWithoutNoticeAndTheSameValues) {
  const fs::path dir = scratch("presets");
  for (const char* version : {"preset_v1", "preset_v2"}) {
    for (const auto& name : kSeeds) {
      SCOPED_TRACE(std::string(version) + "/" + name);
      const fs::path original = kFixtureDir / version / (name + ".json");
      const fs::path copy = dir / (std::string(version) + "_" + name + ".json");
      fs::copy_file(original, copy);
      auto before = load_preset(original.string());
      ASSERT_TRUE(before.ok()) << before.error();
      const auto r = cli("upgrade " + copy.string());
      ASSERT_EQ(r.code, 0) << r.text;
      auto after = load_preset(copy.string());
      ASSERT_TRUE(after.ok()) << after.error();
      EXPECT_TRUE(after->notices.empty()) << after->notices.front();
      EXPECT_EQ(after->scenario, before->scenario);
      EXPECT_EQ(after->values, before->values);
      EXPECT_EQ(after->version, 2);
      if (contains(r.text, "upgraded")) {
        EXPECT_TRUE(contains(r.text, "kept as " + copy.string() + ".bak")) << r.text;
        EXPECT_EQ(text_of(copy.string() + ".bak"), text_of(original));
      } else {
        EXPECT_TRUE(contains(r.text, "already current")) << r.text;
        EXPECT_FALSE(fs::exists(copy.string() + ".bak"));
      }
      EXPECT_EQ(cli("upgrade " + copy.string() + " --check").code, 0);
    }
  }
  fs::remove_all(dir.parent_path());
}

TEST(UpgradeCli, EveryOldSessionBecomesVersion3ThatLoadsWithoutNoticeAndTheSameValues) {
  const fs::path dir = scratch("sessions");
  for (const char* version : {"session_v1", "session_v2"}) {
    for (const auto& name : kSeeds) {
      SCOPED_TRACE(std::string(version) + "/" + name);
      const fs::path cwd = kFixtureDir / version;  // where the session's paths start
      const fs::path original = cwd / (name + ".json");
      const fs::path copy = dir / (std::string(version) + "_" + name + ".json");
      fs::copy_file(original, copy);
      testing::WorkingDirectory in(cwd);
      auto old = load_session(original.string());
      ASSERT_TRUE(old.ok()) << old.error();
      auto before = Document::from_session(*old, original.string());
      ASSERT_TRUE(before.ok()) << before.error();
      EXPECT_EQ(cli_in(cwd, "upgrade " + copy.string() + " --check").code, 1);
      EXPECT_FALSE(fs::exists(copy.string() + ".bak"));
      const auto r = cli_in(cwd, "upgrade " + copy.string());
      ASSERT_EQ(r.code, 0) << r.text;
      EXPECT_TRUE(contains(r.text, "kept as " + copy.string() + ".bak")) << r.text;
      EXPECT_EQ(text_of(copy.string() + ".bak"), text_of(original));
      auto s = load_session(copy.string());
      ASSERT_TRUE(s.ok()) << s.error();
      EXPECT_EQ(s->version, 3);
      // The same log (the copy is elsewhere: its path may be read from the current folder).
      ASSERT_EQ(s->data_path.has_value(), old->data_path.has_value());
      // (Where the log is not here, a fresh clone without ../shared, neither names a file.)
      if (s->data_path && fs::exists(*old->data_path)) {
        EXPECT_EQ(fs::weakly_canonical(*s->data_path), fs::weakly_canonical(*old->data_path));
      }
      EXPECT_EQ(s->data_hash, old->data_hash);
      EXPECT_EQ(s->mapping, old->mapping);
      auto after = Document::from_session(*s, copy.string());
      ASSERT_TRUE(after.ok()) << after.error();
      EXPECT_TRUE(after->notices().empty()) << after->notices().front();
      EXPECT_EQ(after->preset().scenario, before->preset().scenario);
      EXPECT_EQ(after->values(), before->values());
      EXPECT_EQ(after->snapshots(), before->snapshots());
      EXPECT_EQ(after->view_state(), before->view_state());
      EXPECT_EQ(cli_in(cwd, "upgrade " + copy.string() + " --check").code, 0);
    }
  }
  fs::remove_all(dir.parent_path());
}

TEST(UpgradeCli, CheckPrintsWhatWouldChangeAndWritesNothing) {
  const fs::path dir = scratch("check");
  const fs::path copy = dir / "helicopter.json";
  fs::copy_file(kFixtureDir / "preset_v1" / "helicopter.json", copy);
  const auto r = cli("upgrade " + copy.string() + " --check");
  EXPECT_EQ(r.code, 1) << r.text;
  EXPECT_TRUE(contains(r.text, "scenario 'helicopter' (retired)")) << r.text;
  EXPECT_TRUE(contains(r.text, "window")) << r.text;
  EXPECT_EQ(text_of(copy), text_of(kFixtureDir / "preset_v1" / "helicopter.json"));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
  EXPECT_EQ(cli("upgrade " + (dir / "missing.json").string() + " --check").code, 2);
  fs::remove_all(dir.parent_path());
}

TEST(UpgradeCli, OutWritesElsewhereAndAnExistingBackupIsNeverOverwritten) {
  const fs::path dir = scratch("out");
  const fs::path copy = dir / "broad_imu.json";
  const std::string original = text_of(kFixtureDir / "preset_v2" / "broad_imu.json");
  fs::copy_file(kFixtureDir / "preset_v2" / "broad_imu.json", copy);
  const auto r = cli("upgrade " + copy.string() + " --out " + (dir / "new.json").string());
  ASSERT_EQ(r.code, 0) << r.text;
  EXPECT_EQ(text_of(copy), original);
  EXPECT_FALSE(fs::exists(copy.string() + ".bak"));
  auto p = load_preset((dir / "new.json").string());
  ASSERT_TRUE(p.ok()) << p.error();
  EXPECT_TRUE(p->notices.empty());
  EXPECT_EQ(cli("upgrade " + copy.string() + " --out " + copy.string()).code, 2);
  std::ofstream(copy.string() + ".bak") << "mine";
  const auto kept = cli("upgrade " + copy.string());
  EXPECT_EQ(kept.code, 2) << kept.text;
  EXPECT_TRUE(contains(kept.text, copy.string() + ".bak: exists")) << kept.text;
  EXPECT_EQ(text_of(copy.string() + ".bak"), "mine");
  EXPECT_EQ(text_of(copy), original);
  fs::remove_all(dir.parent_path());
}

TEST(UpgradeCli, AModelFileIsAlreadyCurrent) {
  for (const char* name : {"cv1d", "helicopter_indirect"}) {
    const fs::path path = kFixtureDir / "model_v1" / (std::string(name) + ".json");
    const auto r = cli("upgrade " + path.string() + " --check");
    EXPECT_EQ(r.code, 0) << r.text;
    EXPECT_TRUE(contains(r.text, "already current (a model file")) << r.text;
  }
  const auto shipped =
      cli("upgrade " + std::string(KFW_SOURCE_DIR) + "/presets/helicopter.json --check");
  EXPECT_EQ(shipped.code, 0) << shipped.text;
  EXPECT_TRUE(contains(shipped.text, "already current")) << shipped.text;
}

TEST(UpgradeCli, APartOfVersion1CannotBeUpgraded) {
  for (const char* part : {"montecarlo_v1/radome.json", "sweep_v1/helicopter.json"}) {
    const fs::path path = kFixtureDir / part;
    const auto r = cli("upgrade " + path.string());
    EXPECT_EQ(r.code, 2) << r.text;
    EXPECT_TRUE(contains(r.text, path.string() + ": a ")) << r.text;
    EXPECT_TRUE(contains(r.text, "part of version 1 cannot be upgraded")) << r.text;
    EXPECT_TRUE(contains(r.text, "content hash")) << r.text;
  }
}

TEST(UpgradeCli, BadInputIsRefusedWithThePathNamedAndNeverHangs) {
  const fs::path dir = scratch("bad");
  const fs::path binary = dir / "binary.json";
  std::ofstream(binary, std::ios::binary) << std::string("\x7f\x45LF\x00\x01\xff", 7);
  const fs::path fifo = dir / "fifo.json";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const fs::path text = dir / "other.json";
  std::ofstream(text) << R"({"format": "something-else"})";
  for (const fs::path& path : {binary, fifo, dir, dir / "missing.json", text}) {
    SCOPED_TRACE(path.string());
    for (const char* check : {"", " --check"}) {
      const auto r = run_command("timeout 20 " + std::string(KFW_CLI) + " upgrade " +
                                 path.string() + check + " 2>&1");
      EXPECT_EQ(r.code, 2) << r.text;
      EXPECT_TRUE(contains(r.text, path.string())) << r.text;
    }
  }
  fs::remove_all(dir.parent_path());
}

TEST(UpgradeCli, RetiredScenariosAreNotListed) {
  const auto list = cli("list", "2>/dev/null");
  ASSERT_EQ(list.code, 0) << list.text;
  // The line of compiled scenarios, when there is one (none since issue 30).
  const auto at = list.text.find("scenarios:");
  const std::string scenarios =
      at == std::string::npos ? "" : list.text.substr(at, list.text.find('\n', at) - at);
  EXPECT_FALSE(contains(scenarios, "helicopter")) << scenarios;
  EXPECT_FALSE(contains(scenarios, "radome")) << scenarios;    // a model file since issue 28
  EXPECT_FALSE(contains(scenarios, "ballbeam")) << scenarios;  // a model file since issue 30
  const auto help = cli("--help");
  EXPECT_TRUE(contains(help.text, "upgrade")) << help.text;
}

}  // namespace
}  // namespace upgrade_cli_test
}  // namespace kfw
