// Preset format version 2 (presets/README.md): every shipped preset loads as version 1 and
// round-trips through version 2 unchanged; overflowing numbers and wrong types name their key.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/scenario.h"
#include "document/preset.h"

namespace kfw {
namespace {

namespace fs = std::filesystem;

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

// The version-1 form of a file: no flags, version 1.
std::string as_version_1(const std::string& text) {
  auto j = nlohmann::ordered_json::parse(text);
  j["version"] = 1;
  for (auto& [k, e] : j["parameters"].items()) {
    if (e.is_object()) {
      e.erase("tunable");
      e.erase("scale_group");
    }
  }
  return j.dump(2);
}

std::vector<fs::path> shipped() {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(std::string(KFW_SOURCE_DIR) + "/presets")) {
    if (e.path().extension() == ".json") out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

TEST(PresetV2, ShippedPresetsAreVersion2WithFlags) {
  const auto files = shipped();
  ASSERT_EQ(files.size(), 5u);
  for (const auto& f : files) {
    auto p = load_preset(f.string());
    ASSERT_TRUE(p.ok()) << p.error();
    EXPECT_EQ(p->version, 2) << f;
    int tunable = 0;
    for (const auto& [k, m] : p->meta)
      tunable += m.tunable ? 1 : 0;
    EXPECT_GE(tunable, 2) << f << ": every shipped preset marks its noise terms tunable";
  }
}

TEST(PresetV2, Version1LoadsAndRoundTripsUnchangedInValues) {
  for (const auto& f : shipped()) {
    const std::string dir = f.parent_path().string();
    auto v1 = parse_preset(as_version_1(read(f)), f.string());
    ASSERT_TRUE(v1.ok()) << v1.error();
    EXPECT_EQ(v1->version, 1);
    const std::string written = preset_to_json(*v1);
    EXPECT_NE(written.find("\"version\": 2"), std::string::npos);
    auto v2 = parse_preset(written, f.string());
    ASSERT_TRUE(v2.ok()) << v2.error();
    EXPECT_EQ(v2->values, v1->values) << f;
    EXPECT_EQ(v2->ranges, v1->ranges) << f;
    EXPECT_EQ(v2->data_path, v1->data_path) << f;
    // And the shipped version-2 file itself round-trips with its flags.
    auto shipped_v2 = load_preset(f.string());
    ASSERT_TRUE(shipped_v2.ok());
    auto again = parse_preset(preset_to_json(*shipped_v2), f.string());
    ASSERT_TRUE(again.ok()) << again.error();
    EXPECT_EQ(again->values, shipped_v2->values);
    EXPECT_EQ(again->meta, shipped_v2->meta);
  }
}

TEST(PresetV2, OverflowAnywhereIsRefusedWithItsKey) {
  const std::string text = read(std::string(KFW_SOURCE_DIR) + "/presets/helicopter.json");
  struct Case {
    std::string from, to, key;
  };
  const Case cases[] = {
      {"\"value\": 67.24", "\"value\": 1e999", "parameters.Q.value"},
      {"\"min\": 1e-06", "\"min\": -1e999", "parameters.Q.min"},
      {"\"version\": 2", "\"version\": 1e999", "version"},
      {"\"max\": 1000000.0", "\"max\": 1e400", "parameters.Q.max"},
  };
  for (const auto& c : cases) {
    std::string bad = text;
    const auto at = bad.find(c.from);
    ASSERT_NE(at, std::string::npos) << c.from;
    bad.replace(at, c.from.size(), c.to);
    auto p = parse_preset(bad, "h.json");
    ASSERT_FALSE(p.ok()) << c.to;
    EXPECT_NE(p.error().find("h.json:"), std::string::npos) << p.error();
    EXPECT_NE(p.error().find(c.key + ": number overflows a double"), std::string::npos)
        << p.error();
    EXPECT_EQ(p.exit_code(), kExitInvalid);
  }
}

TEST(PresetV2, WrongTypesAndHugeVersionsNameTheKey) {
  const std::string head = R"({"format": "kfw-preset", "scenario": "helicopter", )";
  auto err = [&](const std::string& rest) {
    auto p = parse_preset(head + rest, "h.json");
    return p.ok() ? std::string("accepted") : p.error();
  };
  EXPECT_NE(err(R"("version": 4294967297})").find("version: 4294967297"), std::string::npos);
  EXPECT_NE(err(R"("version": 2, "title": 3})").find("title: must be a string, not a number"),
            std::string::npos);
  EXPECT_NE(err(R"("version": 2, "parameters": {"Q": [1]}})").find("parameters.Q: expected"),
            std::string::npos);
  EXPECT_NE(err(R"("version": 2, "sim": {"x0_from_prior": 1}})").find("sim.x0_from_prior"),
            std::string::npos);
  EXPECT_NE(err(R"("version": 2, "model": {}})").find("model: only a preset whose scenario"),
            std::string::npos);
  // Nesting deeper than 256 levels is refused, not recursed into.
  std::string deep = head + R"("version": 2, "description": )";
  for (int i = 0; i < 300; ++i)
    deep += "[";
  EXPECT_NE(err(deep.substr(head.size())).find("nested deeper than 256"), std::string::npos);
}

TEST(PresetV2, MappingRoundTrips) {
  const std::string text = R"({"format": "kfw-preset", "version": 2, "scenario": "helicopter",
    "mapping": {"t": {"column": "time_ms", "unit": "ms"}, "gyro": {"column": "omega", "unit": "rad/s"},
                "angle": "roll", "truth": {"column": "ref", "scale": 2, "offset": 1, "flip": true}}})";
  auto p = parse_preset(text, "m.json");
  ASSERT_TRUE(p.ok()) << p.error();
  EXPECT_EQ(p->mapping.at("t").unit, "ms");
  EXPECT_EQ(p->mapping.at("angle").column, "roll");
  EXPECT_TRUE(p->mapping.at("truth").flip);
  auto back = parse_preset(preset_to_json(*p), "m.json");
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_EQ(back->mapping, p->mapping);
}

}  // namespace
}  // namespace kfw
