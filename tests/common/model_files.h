// The model files of presets/models/ as scenarios, for engine tests.
#pragma once

#include <gtest/gtest.h>

#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "core/scenario.h"
#include "model/model_scenario.h"

namespace kfw::testing {

inline const std::string kModelDir = KFW_SOURCE_DIR "/presets/models/";

// The model file at `path` (a test failure and null when it does not load).
inline std::unique_ptr<Scenario> load_model_file(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  auto s = make_model_scenario(nlohmann::json::parse(in), path);
  EXPECT_TRUE(s.ok()) << s.error();
  return s.ok() ? std::move(*s) : nullptr;
}

// presets/models/NAME.
inline std::unique_ptr<Scenario> load_model(const std::string& name) {
  return load_model_file(kModelDir + name);
}

}  // namespace kfw::testing
