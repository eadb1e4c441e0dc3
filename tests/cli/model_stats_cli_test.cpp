// `kfw-cli stats` on any model file with a covariance block (issue 27, engine/model/model_stats.h):
// the README's cv2d example — the estimate's error covariance beside σ_r² I — and a file without
// such a block, which has no such command.
#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "common/cli_runner.h"

namespace {

using kfw::testing::cli;

std::string cv2d_with_error_cov() {
  std::ifstream in(KFW_SOURCE_DIR "/presets/models/cv2d.json");
  auto p = nlohmann::ordered_json::parse(in);
  auto& m = p["model"];
  m["version"] = 2;
  m["derived"] = {{"err_x", {{"expression", "px - px_true"}, {"unit", "m"}, {"label", "x error"}}},
                  {"err_y", {{"expression", "py - py_true"}, {"unit", "m"}, {"label", "y error"}}}};
  m["plots"] = nlohmann::ordered_json::array({{{"kind", "covariance"},
                                               {"id", "error_cov"},
                                               {"series", {"err_x", "err_y"}},
                                               {"design", {"sigma_r^2", "sigma_r^2"}}}});
  const auto path = std::filesystem::temp_directory_path() /
                    ("cv2d_stats_" + std::to_string(::getpid()) + ".json");
  std::ofstream(path) << p.dump(2);
  return path.string();
}

TEST(ModelStatsCli, AnyFileWithACovarianceBlockPrintsItsMatrices) {
  const std::string file = cv2d_with_error_cov();
  auto r = cli("stats " + file + " --set sim.duration=200", "2>/dev/null");
  ASSERT_EQ(r.code, 0) << r.text;
  const auto j = nlohmann::json::parse(r.text);
  const auto& b = j["blocks"]["error_cov"];
  ASSERT_EQ(b["series"], nlohmann::json({"derived.err_x", "derived.err_y"})) << r.text;
  EXPECT_GT(b["samples"].get<int>(), 100);
  EXPECT_FALSE(b.contains("excluded"));  // not at instants
  const double sr2 = b["design"][0][0].get<double>();
  EXPECT_GT(sr2, 0.0);
  EXPECT_EQ(b["design"][0][1].get<double>(), 0.0);
  // The filter does better than a raw fix: each error variance below σ_r², and symmetric.
  for (int i = 0; i < 2; ++i)
    EXPECT_LT(b["covariance"][i][i].get<double>(), sr2) << i;
  EXPECT_EQ(b["covariance"][0][1].get<double>(), b["covariance"][1][0].get<double>());
  EXPECT_FALSE(j.contains("outliers_injected"));  // no channel declares an outlier column
  std::filesystem::remove(file);
}

TEST(ModelStatsCli, AFileWithoutOneHasNoStats) {
  auto r = cli("stats " KFW_SOURCE_DIR "/presets/models/cv2d.json");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.text.find("has no command 'stats'"), std::string::npos) << r.text;
}

}  // namespace
