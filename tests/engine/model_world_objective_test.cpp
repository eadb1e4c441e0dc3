// Issue 27 (model files, part 2), the tuning side: a model file that marks nothing tunable is
// tuned over the parameters of its Q and R.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <set>

#include "common/van_der_pol.h"
#include "document/preset.h"
#include "experiment/tuning.h"

namespace kfw {
namespace model_world_objective_test {
namespace {

using testing::van_der_pol_preset;

Preset preset_of(const nlohmann::json& j) {
  auto p = parse_preset(j.dump(), "vdp.json");
  EXPECT_TRUE(p.ok()) << p.error();
  return p.ok() ? std::move(*p) : Preset{};
}

std::set<std::string> keys_of(const std::vector<SearchParam>& params) {
  std::set<std::string> out;
  for (const auto& p : params)
    out.insert(p.key);
  return out;
}

TEST(ModelWorldTune, AFileThatMarksNothingTunableIsTunedOverItsNoiseParameters) {
  const Preset p = preset_of(van_der_pol_preset());
  const auto search = default_search(p);
  // q is in Q, sigma in R; mu (in f), P0_x (in P0), x10 (in x0) and the sim keys are not.
  EXPECT_EQ(keys_of(search), (std::set<std::string>{"q", "sigma"}));
  for (const auto& s : search) {
    EXPECT_TRUE(s.log) << s.key << ": a log-scale key is searched in log10";
    EXPECT_TRUE(s.scale_group.empty()) << s.key;
  }
  // The default is written out, so a saved file keeps it.
  auto again = parse_preset(preset_to_json(p), "vdp.json");
  ASSERT_TRUE(again.ok()) << again.error();
  EXPECT_EQ(keys_of(default_search(*again)), (std::set<std::string>{"q", "sigma"}));
}

TEST(ModelWorldTune, AFileThatSaysTunableTakesNoDefault) {
  // One flag anywhere: the file chose, and gets only what it marked.
  auto j = van_der_pol_preset();
  j["parameters"]["mu"]["tunable"] = true;
  EXPECT_EQ(keys_of(default_search(preset_of(j))), (std::set<std::string>{"mu"}));
  // Everything false: nothing to search, and the message says what to add.
  j["parameters"]["mu"]["tunable"] = false;
  const Preset none = preset_of(j);
  EXPECT_TRUE(default_search(none).empty());
  const std::string msg = no_tunable_message(none);
  EXPECT_NE(msg.find("vdp.json marks no parameter tunable"), std::string::npos) << msg;
  EXPECT_NE(msg.find("add \"tunable\": true"), std::string::npos) << msg;
  EXPECT_NE(msg.find("q, sigma"), std::string::npos) << msg;
}

}  // namespace
}  // namespace model_world_objective_test
}  // namespace kfw
