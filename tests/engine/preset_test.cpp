#include "document/preset.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "core/scenario.h"

namespace kfw {
namespace {

void expect_preset_error(const std::string& text, const std::string& fragment) {
  auto p = parse_preset(text, "p.json");
  ASSERT_FALSE(p.ok()) << text;
  EXPECT_NE(p.error().find(fragment), std::string::npos) << p.error();
}

const char* kHead = R"({"format": "kfw-preset", "version": 1, "scenario": "helicopter", )";

TEST(Preset, EveryShippedPresetLoads) {
  int n = 0;
  for (const auto& e :
       std::filesystem::directory_iterator(std::string(KFW_SOURCE_DIR) + "/presets")) {
    if (e.path().extension() != ".json") continue;
    auto p = load_preset(e.path().string());
    ASSERT_TRUE(p.ok()) << p.error();
    ASSERT_TRUE(p->instance) << e.path();  // a built-in or a model file's own scenario
    EXPECT_TRUE(p->instance->params().check(p->values).ok()) << e.path();
    ++n;
  }
  EXPECT_GE(n, 1);
}

TEST(Preset, ErrorsNameLineKeyAndUnit) {
  expect_preset_error("{\n  \"format\": \"kfw-preset\",\n  \"version\": 1,,\n}", "p.json:3:");
  expect_preset_error(R"({"format": "other", "version": 1})",
                      "format: 'other', expected 'kfw-preset'");
  expect_preset_error(R"({"format": "kfw-preset", "version": 9, "scenario": "helicopter"})",
                      "p.json: version: 9; this build reads versions 1 and 2");
  expect_preset_error(R"({"format": "kfw-preset", "version": 1, "scenario": "nope"})",
                      "unknown scenario 'nope'");
  expect_preset_error(std::string(kHead) + R"("parameters": {"Zz": 1}})",
                      "parameters.Zz: unknown parameter");
  expect_preset_error(std::string(kHead) + R"("parameters": {"R": {"value": -1}}})",
                      "'R' = -1 is out of range");
  expect_preset_error(std::string(kHead) + R"("parameters": {"R": {"value": 1, "unit": "rad²"}}})",
                      "parameters.R.unit: 'rad²' does not match the parameter's unit 'deg²'");
  expect_preset_error(
      std::string(kHead) + R"("parameters": {"R": {"value": 1, "min": 5, "max": 2}}})",
      "must be increasing");
  expect_preset_error(std::string(kHead) + R"("parameters": {"R": {"value": "x"}}})",
                      "must be a number");
  expect_preset_error(std::string(kHead) + R"("parameters": {"R": {"valeu": 1}}})",
                      "p.json: parameters.R.valeu: unknown key (did you mean 'value'?)");
  expect_preset_error(std::string(kHead) + R"("paramters": {}})",
                      "p.json: paramters: unknown key (did you mean 'parameters'?)");
  expect_preset_error(std::string(kHead) + R"("parameters": {"R": {"value": 1, "tunable": 1}}})",
                      "parameters.R.tunable: must be true or false");
  expect_preset_error(
      std::string(kHead) + R"("mapping": {"gyro": {"column": "g", "unit": "furlong"}}})",
      "mapping.gyro.unit: unknown unit 'furlong'");
}

TEST(Preset, RoundTripKeepsValuesAndRanges) {
  auto p = parse_preset(
      std::string(kHead) + R"("parameters": {"Q": {"value": 256, "min": 1, "max": 1000}, "m": 5}})",
      "");
  ASSERT_TRUE(p.ok()) << p.error();
  EXPECT_EQ(p->values.at("Q"), 256);
  EXPECT_EQ(p->values.at("m"), 5);
  EXPECT_EQ(p->values.at("R"), 1.96);  // default from the table
  auto back = parse_preset(preset_to_json(*p), "");
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_EQ(back->values, p->values);
  EXPECT_EQ(back->ranges.at("Q"), (std::pair<double, double>(1, 1000)));
}

}  // namespace
}  // namespace kfw
