// CI's share of the fuzzing (issue 16): every committed corpus file (tests/fuzz/corpus/NAME/) goes
// through its harness — the same function the libFuzzer targets call (tests/fuzz/harness.h) — and
// must give an allowed outcome. `make fuzz` runs the long, local searches.
#include <gtest/gtest.h>

#include <filesystem>

#include "../fuzz/harness.h"

namespace kfw {
namespace {

namespace fs = std::filesystem;

class FuzzCorpus : public ::testing::TestWithParam<std::string> {};

TEST_P(FuzzCorpus, EveryFileGivesAValueOrAnError) {
  const fs::path dir = fs::path(KFW_SOURCE_DIR) / "tests/fuzz/corpus" / GetParam();
  ASSERT_TRUE(fs::is_directory(dir)) << dir;
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    std::ifstream in(e.path(), std::ios::binary);
    std::ostringstream os;
    os << in.rdbuf();
    EXPECT_EQ(fuzz::run_harness(GetParam(), os.str()), "") << e.path();
    ++files;
  }
  EXPECT_GT(files, 0);
}

std::vector<std::string> harness_names() {
  return {std::begin(fuzz::kHarnesses), std::end(fuzz::kHarnesses)};
}

INSTANTIATE_TEST_SUITE_P(Harnesses, FuzzCorpus, ::testing::ValuesIn(harness_names()),
                         [](const auto& p) { return p.param; });

}  // namespace
}  // namespace kfw
