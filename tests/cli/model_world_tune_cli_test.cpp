// Issue 27 (model files, part 2): `kfw-cli tune` on a new model file that marks nothing tunable
// tunes the parameters of its Q and R and says which objective it used and why; a file that opts
// out of the default is refused with what to add; a declared default_objective is used.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/cli_runner.h"
#include "common/van_der_pol.h"

namespace kfw {
namespace model_world_tune_cli_test {
namespace {

using testing::cli;
namespace fs = std::filesystem;

class ModelWorldTuneCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("kfw_model_world_tune_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const nlohmann::json& j) const {
    const std::string p = (dir_ / name).string();
    std::ofstream(p) << j.dump(2);
    return p;
  }
  fs::path dir_;
};

TEST_F(ModelWorldTuneCli, ANewModelFileIsTunedOverItsNoiseAndSaysWhichObjective) {
  const std::string file = write("vdp.json", testing::van_der_pol_preset());
  const std::string err = (dir_ / "err.txt").string();
  auto r = cli("tune " + file + " --budget 30", "2>" + err);
  std::ifstream e(err);
  const std::string stderr_text((std::istreambuf_iterator<char>(e)), {});
  ASSERT_EQ(r.code, 0) << r.text << stderr_text;
  auto j = nlohmann::json::parse(r.text);
  EXPECT_EQ(j["params"].size(), 2u);
  EXPECT_TRUE(j["params"].contains("q"));
  EXPECT_TRUE(j["params"].contains("sigma"));
  EXPECT_EQ(j["objective"], "rmse+anis");
  EXPECT_NE(j["objective_from"].get<std::string>().find("no scale group"), std::string::npos);
  EXPECT_TRUE(j.contains("objective_value"));
  EXPECT_NE(stderr_text.find("objective 'rmse+anis' (truth and no scale group"), std::string::npos)
      << stderr_text;
  // Asked for by name, the objective says so.
  auto named = cli("tune " + file + " --budget 10 --objective nll", "2>/dev/null");
  ASSERT_EQ(named.code, 0) << named.text;
  EXPECT_EQ(nlohmann::json::parse(named.text)["objective_from"], "--objective");
}

TEST_F(ModelWorldTuneCli, AFileThatMarksNothingIsRefusedWithWhatToAdd) {
  auto j = testing::van_der_pol_preset();
  for (auto& [k, e] : j["parameters"].items())
    e["tunable"] = false;
  const std::string file = write("none.json", j);
  auto r = cli("tune " + file);
  EXPECT_EQ(r.code, 2) << r.text;
  EXPECT_NE(r.text.find("none.json marks no parameter tunable"), std::string::npos) << r.text;
  EXPECT_NE(r.text.find("add \"tunable\": true"), std::string::npos) << r.text;
}

TEST_F(ModelWorldTuneCli, ADeclaredDefaultObjectiveIsUsed) {
  auto j = testing::van_der_pol_preset();
  j["default_objective"] = "nll";
  const std::string file = write("nll.json", j);
  auto r = cli("tune " + file + " --budget 10", "2>/dev/null");
  ASSERT_EQ(r.code, 0) << r.text;
  auto out = nlohmann::json::parse(r.text);
  EXPECT_EQ(out["objective"], "nll");
  EXPECT_NE(out["objective_from"].get<std::string>().find("default_objective"), std::string::npos);
  // A typo in the file is refused when it loads, with the nearest name.
  j["default_objective"] = "nlll";
  auto bad = cli("tune " + write("bad.json", j));
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.text.find("default_objective: unknown objective 'nlll'"), std::string::npos)
      << bad.text;
}

}  // namespace
}  // namespace model_world_tune_cli_test
}  // namespace kfw
