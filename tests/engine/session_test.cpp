#include "document/session.h"

#include <gtest/gtest.h>

#include <fstream>

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

}  // namespace
}  // namespace kfw
