#include "document/session.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace kfw {
namespace {

TEST(Session, RoundTripKeepsEverything) {
  Session s;
  s.preset_path = "presets/helicopter.json";
  s.scenario = "helicopter";
  s.values = {{"Q", 256}, {"R", 4096}};
  s.data_path = "/data/log.csv";
  s.data_hash = "0123456789abcdef";
  s.mapping = to_mapping({{"gyro", "gx"}, {"angle", "acc_roll"}});
  s.mapping["gyro"].unit = "rad/s";
  s.tuning_set = {{"/data/a.csv", {}}, {"/data/b.csv", to_mapping({{"t", "time_s"}})}};
  s.snapshots = {{"loose", {{"Q", 1}, {"R", 2}}}, {"tight", {{"Q", 3}, {"R", 4}}}};
  s.window_state = "AAAA==";
  auto back = parse_session(session_to_json(s), "s.json");
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_EQ(back->preset_path, s.preset_path);
  EXPECT_EQ(back->values, s.values);
  EXPECT_EQ(back->data_path, s.data_path);
  EXPECT_EQ(back->data_hash, s.data_hash);
  EXPECT_EQ(back->mapping, s.mapping);
  EXPECT_EQ(back->tuning_set, s.tuning_set);
  ASSERT_EQ(back->snapshots.size(), 2u);
  EXPECT_EQ(back->snapshots[1].name, "tight");
  EXPECT_EQ(back->snapshots[1].values, s.snapshots[1].values);
  EXPECT_EQ(back->window_state, s.window_state);
}

TEST(Session, BadFilesAreErrorsNamingTheKey) {
  EXPECT_NE(parse_session("{", "s.json").error().find("s.json:1:"), std::string::npos);
  EXPECT_NE(parse_session(R"({"format": "x"})", "s.json").error().find("format:"),
            std::string::npos);
  // Version 1 wrote "columns": read as the mapping.
  auto v1 = parse_session(
      R"({"format": "kfw-session", "version": 1, "preset": "p", "scenario": "h", "columns": {"gyro": "gx"}})",
      "s.json");
  ASSERT_TRUE(v1.ok()) << v1.error();
  EXPECT_EQ(v1->mapping.at("gyro").column, "gx");
  EXPECT_NE(
      parse_session(R"({"format": "kfw-session", "version": 1, "values": {"Q": 1e999}})", "s.json")
          .error()
          .find("s.json:1:"),
      std::string::npos);
  const std::string head =
      R"({"format": "kfw-session", "version": 1, "preset": "p", "scenario": "h", )";
  EXPECT_NE(parse_session(head + R"("values": {"Q": "a"}})", "s.json").error().find("values.Q"),
            std::string::npos);
  EXPECT_NE(
      parse_session(head + R"("snapshots": [{"values": {}}]})", "s.json").error().find("name"),
      std::string::npos);
}

TEST(Session, HashAndColumnMap) {
  const std::string f = ::testing::TempDir() + "/kfw_hash.csv";
  { std::ofstream(f) << "t,gx,roll\n0,1,2\n"; }
  auto h1 = file_hash(f);
  ASSERT_TRUE(h1.ok());
  EXPECT_EQ(h1->size(), 16u);
  { std::ofstream(f) << "t,gx,roll\n0,1,3\n"; }
  EXPECT_NE(*file_hash(f), *h1);
  Dataset d;
  d.source = "f.csv";
  d.add("t", 1);
  d.add("gx", 1);
  d.add("roll", 1);
  EXPECT_EQ(header_key(d), "t,gx,roll");
  auto m = apply_column_map(d, {{"gyro", "gx"}, {"angle", "roll"}});
  ASSERT_TRUE(m.ok());
  EXPECT_EQ(m->names, (std::vector<std::string>{"t", "gyro", "angle"}));
  auto bad = apply_column_map(d, {{"gyro", "nope"}});
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("mapped column 'nope' (for 'gyro')"), std::string::npos);
}

// A session's paths are relative to the session file (issue 32, item 15): a folder of preset,
// log and session copied elsewhere opens from there; a session written before (paths from the
// current folder) still opens.
TEST(Session, PathsAreTheSessionFilesSoACopiedFolderOpens) {
  namespace fs = std::filesystem;
  const fs::path root =
      fs::temp_directory_path() / ("kfw_session_paths_" + std::to_string(::getpid()));
  fs::remove_all(root);
  fs::create_directories(root / "a" / "presets");
  fs::create_directories(root / "a" / "logs");
  fs::create_directories(root / "a" / "sessions");
  std::ofstream(root / "a" / "presets" / "p.json") << "{}";
  std::ofstream(root / "a" / "logs" / "d.csv") << "t\n0\n";
  Session s;
  s.preset_path = (root / "a" / "presets" / "p.json").string();
  s.data_path = (root / "a" / "logs" / "d.csv").string();
  s.tuning_set = {{(root / "a" / "logs" / "d.csv").string(), {}}};
  const fs::path file = root / "a" / "sessions" / "s.json";
  ASSERT_TRUE(save_session(file.string(), s).ok());
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  const auto j = nlohmann::json::parse(text.str());
  EXPECT_EQ(j["preset"], "../presets/p.json");
  EXPECT_EQ(j["data"]["path"], "../logs/d.csv");
  EXPECT_EQ(j["tuning_set"][0]["path"], "../logs/d.csv");
  // The whole folder copied elsewhere: the copy's files.
  fs::copy(root / "a", root / "b", fs::copy_options::recursive);
  auto back = load_session((root / "b" / "sessions" / "s.json").string());
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_EQ(back->preset_path, (root / "b" / "presets" / "p.json").string());
  EXPECT_EQ(*back->data_path, (root / "b" / "logs" / "d.csv").string());
  EXPECT_EQ(back->tuning_set[0].path, (root / "b" / "logs" / "d.csv").string());
  // An old session whose paths are the current folder's.
  const fs::path cwd = fs::current_path();
  fs::current_path(root / "a");
  Session old = s;
  old.preset_path = "presets/p.json";
  old.data_path = "logs/d.csv";
  old.tuning_set.clear();
  std::ofstream(root / "a" / "sessions" / "old.json") << session_to_json(old);
  auto o = load_session("sessions/old.json");
  fs::current_path(cwd);
  ASSERT_TRUE(o.ok()) << o.error();
  EXPECT_EQ(o->preset_path, "presets/p.json");
  EXPECT_EQ(*o->data_path, "logs/d.csv");
  fs::remove_all(root);
}

}  // namespace
}  // namespace kfw
