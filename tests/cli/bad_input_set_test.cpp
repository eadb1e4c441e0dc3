// The bad-input matrix, `--set` values and sweep grids (issue 16): wrong types, out-of-range
// values, NaN, inf, overflow, zero and negative variances (parameter-only: exit 2 before the run),
// grid sizes 0, 1 and huge. Each case: one line naming the key or option, nothing written.
#include <chrono>

#include "common/bad_input.h"

namespace kfw {
namespace {

using testing::cli;

class BadSet : public testing::BadInput {
 protected:
  void refused(const std::string& preset, const std::string& set,
               std::initializer_list<std::string> fragments) {
    expect_refused("run " + preset_path(preset) + " --set '" + set + "'", 2, fragments);
  }
};

TEST_F(BadSet, ValuesThatAreNotFiniteNumbers) {
  refused("helicopter", "Q=abc", {"Q", "'abc' is not a number"});
  refused("helicopter", "Q=", {"Q"});
  refused("helicopter", "Q=nan", {"Q"});
  refused("helicopter", "Q=NaN", {"Q"});
  refused("helicopter", "Q=inf", {"Q"});
  refused("helicopter", "R=-inf", {"R"});
  refused("helicopter", "Q=1e999", {"Q"});
  refused("helicopter", "Q=0x10", {"Q"});
  refused("helicopter", "Q=1,5", {"Q"});
  refused("helicopter", "Q=" + std::string(100000, '9'), {"Q"});
}

TEST_F(BadSet, KeysAndSyntax) {
  refused("helicopter", "Qq=1", {"Qq", "did you mean 'Q'"});
  refused("helicopter", "Q", {"Q"});
  refused("helicopter", "=1", {"="});
  refused("helicopter", "sim.sede=3", {"sim.sede"});
}

TEST_F(BadSet, OutOfRangeZeroNegativeAndFractionalValues) {
  refused("helicopter", "Q=1e300", {"Q", "range"});
  refused("helicopter", "Q=0", {"Q"});
  refused("helicopter", "R=-1", {"R"});
  refused("helicopter", "gamma=0.2", {"gamma"});
  refused("helicopter", "m=2.5", {"m"});
  refused("helicopter", "m=0", {"m"});
  refused("underwater", "sigma_range=0", {"sigma_range"});
  refused("radome", "R=-0.5", {"R"});
  refused("ballbeam", "Q=-1", {"Q"});
}

TEST_F(BadSet, ANonPsdModelCovarianceIsRefusedBeforeTheRun) {
  // cv2d's P0 is a diagonal of parameters: a negative entry is out of range (exit 2, keyed).
  expect_refused("run " + std::string(KFW_SOURCE_DIR) + "/presets/models/cv1d.json --set P0_x=-1",
                 2, {"P0_x"});
  expect_refused("run " + std::string(KFW_SOURCE_DIR) + "/presets/models/cv1d.json --set sigma_r=0",
                 2, {"sigma_r"});
}

TEST_F(BadSet, GridSizesZeroOneAndHuge) {
  const std::string sweep = "sweep " + preset_path("helicopter") + " --metric rmse --out " + out;
  const auto start = std::chrono::steady_clock::now();
  expect_refused(sweep + " --param Q=1:100:0", 2, {"--param", "Q"}, false);
  expect_refused(sweep + " --param Q=1:100:-3", 2, {"--param"}, false);
  expect_refused(sweep + " --param Q=1:100:2.5", 2, {"--param"}, false);
  expect_refused(sweep + " --param Q=1:100:100000000", 2, {"1000000"}, false);
  expect_refused(sweep + " --param Q=1:100:2000 --param R=1:100:2000", 2, {"--max-points"}, false);
  expect_refused(sweep + " --param Q=nan:100:3", 2, {"--param"}, false);
  expect_refused(sweep + " --param Q=1:inf:3", 2, {"--param"}, false);
  expect_refused(sweep + " --param Q=1:1e999:3", 2, {"--param"}, false);
  expect_refused(sweep + " --param Q=-1:100:3:log", 2, {"--param"}, false);
  expect_refused(sweep + " --param Q=1:1e300:3", 2, {"Q"}, false);
  expect_refused(sweep + " --param Qq=1:100:3", 2, {"Qq"}, false);
  EXPECT_LT(std::chrono::steady_clock::now() - start,
            std::chrono::seconds(10) * testing::kTimeScale);
  // n = 1 is lo alone: one run, a result.
  std::filesystem::remove(out);
  auto one = cli(sweep + " --param Q=10:100:1");
  EXPECT_EQ(one.code, 0) << one.text;
  const std::string table = read(out);
  EXPECT_EQ(std::count(table.begin(), table.end(), '\n'), 2) << table;
}

}  // namespace
}  // namespace kfw
