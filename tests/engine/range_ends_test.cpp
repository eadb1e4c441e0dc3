// Numerical extremes (issue 16): every shipped preset's every numeric parameter, at the minimum
// and the maximum of its declared range (the preset's, else the scenario's), must simulate and run
// with finite results — or stop with a message naming the step and time (exit 1). A refusal (exit
// 2) of a value inside the declared range, or a metric turned undefined because it was not finite,
// is a bug. sim.duration is cut to a few seconds (except when it is the parameter tested).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>

#include "document/workspace.h"

namespace kfw {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> preset_files() {
  std::vector<std::string> files;
  for (const char* sub : {"presets", "presets/models"}) {
    for (const auto& e : fs::directory_iterator(fs::path(KFW_SOURCE_DIR) / sub)) {
      // broad_imu runs the helicopter scenario (the same table) over the real log.
      if (e.path().extension() == ".json" && e.path().stem() != "broad_imu")
        files.push_back(e.path().string());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

// What one run at one end gives: "" when fine, else why it is a bug.
std::string check_end(const std::string& preset, const std::string& key, double v,
                      const ParamValues& base, const ParamTable& table, bool shorten = true) {
  std::ostringstream set;
  set.precision(17);
  set << key << '=' << v;
  std::vector<std::string> sets = {set.str()};
  if (shorten && key != "sim.duration" && base.count("sim.duration")) {
    const auto* d = table.find("sim.duration");
    const double shortest = std::min(base.at("sim.duration"), std::max(d->min, 5.0));
    std::ostringstream os;
    os.precision(17);
    os << "sim.duration=" << shortest;
    sets.push_back(os.str());
  }
  auto ws = open_workspace(preset, std::nullopt, sets);
  if (!ws) return "refused: " + ws.error();
  auto data = load_dataset(*ws);
  // The short duration may clash with this value (sim.dt = 10 s, a step at 100 s): the
  // preset's own duration decides.
  if (!data && data.exit_code() == kExitInvalid && sets.size() > 1)
    return check_end(preset, key, v, base, table, false);
  if (!data) {
    if (data.exit_code() == kExitFailed && data.error().find("(t = ") != std::string::npos)
      return "";
    return "simulation refused: " + data.error();
  }
  auto r = ws->scenario->run(*data, ws->values);
  if (!r && r.exit_code() == kExitInvalid && sets.size() > 1)
    return check_end(preset, key, v, base, table, false);
  if (!r) {
    if (r.exit_code() == kExitFailed && r.error().find("(t = ") != std::string::npos) return "";
    return "run failed without step and time: " + r.error();
  }
  std::string bad;
  for (const auto& [metric, value] : (*r)->metrics) {
    if (!std::isfinite(value)) bad += " " + metric + "=" + std::to_string(value);
  }
  for (const auto& [metric, why] : (*r)->undefined) {
    if (why.find("no finite value") != std::string::npos) bad += " " + metric + " not finite";
  }
  return bad.empty() ? "" : "non-finite results:" + bad;
}

class RangeEnds : public ::testing::TestWithParam<std::string> {};

TEST_P(RangeEnds, EveryParameterAtBothEnds) {
  const std::string preset = GetParam();
  auto ws = open_workspace(preset, std::nullopt, {});
  ASSERT_TRUE(ws.ok()) << ws.error();
  const ParamTable& table = ws->scenario->params();
  for (const auto& spec : table.specs()) {
    if (spec.scale == Scale::kChoice || spec.scale == Scale::kToggle) continue;
    auto range = std::make_pair(spec.min, spec.max);
    if (auto it = ws->preset.ranges.find(spec.key); it != ws->preset.ranges.end())
      range = it->second;
    for (const double v : {range.first, range.second}) {
      const std::string why = check_end(preset, spec.key, v, ws->values, table);
      const std::string id = fs::path(preset).stem().string() + " " + spec.key + "=" +
                             (v == range.first ? "min" : "max");
      EXPECT_EQ(why, "") << id << " (" << v << ")";
    }
  }
}

std::string case_name(const ::testing::TestParamInfo<std::string>& info) {
  std::string n = fs::path(info.param).stem().string();
  for (char& c : n) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return n;
}

INSTANTIATE_TEST_SUITE_P(Presets, RangeEnds, ::testing::ValuesIn(preset_files()), case_name);

}  // namespace
}  // namespace kfw
