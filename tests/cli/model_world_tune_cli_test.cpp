// Issue 27 (model files, part 2): `kfw-cli tune` on a model file that opts out of the default
// tunable keys is refused with what to add.
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

}  // namespace
}  // namespace model_world_tune_cli_test
}  // namespace kfw
