// The native path (issue 33, native/native_model.h): every shipped preset run with its model's
// expressions compiled by the system's C compiler equals the muparser run (the oracle) to 1e-9
// in the form of ../shared/STAGE.md: |a − b| ≤ tol·(|b| + σ_b), σ_b the posterior standard
// deviation for a state's column, the column's largest magnitude for the others. The compiled
// code is cached by content hash in a private folder and checked before it is loaded.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/scenario.h"
#include "document/workspace.h"
#include "native/native_model.h"

namespace kfw {
namespace scale_native_test {
namespace {

namespace fs = std::filesystem;

bool compiler_runs() {
  return std::system("cc --version > /dev/null 2>&1") == 0;
}

struct NativeOn {
  fs::path dir;
  NativeOn() {
    dir = fs::temp_directory_path() / ("kfw_native_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    const auto st = native::enable({dir.string(), ""});
    EXPECT_TRUE(st.ok()) << st.error();
  }
  ~NativeOn() {
    native::disable();
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

std::vector<std::string> every_preset() {
  std::vector<std::string> out;
  for (const char* d : {"/presets", "/presets/models"}) {
    for (const auto& e : fs::directory_iterator(std::string(KFW_SOURCE_DIR) + d)) {
      if (e.path().extension() == ".json") out.push_back(e.path().string());
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

// The worst |a − b| / (|b| + σ_b) over every column and row.
double worst_difference(const Dataset& a, const Dataset& b, std::string& where) {
  double worst = 0.0;
  for (std::size_t c = 0; c < b.names.size(); ++c) {
    const std::string& name = b.names[c];
    const int ia = a.index(name);
    if (ia < 0 || a.rows() != b.rows()) {
      where = "missing or ragged column " + name;
      return INFINITY;
    }
    const auto& va = a.columns[static_cast<std::size_t>(ia)];
    const auto& vb = b.columns[c];
    const std::vector<double>* var = nullptr;
    if (name.rfind("x.", 0) == 0 && b.has("P." + name.substr(2)))
      var = &b.col("P." + name.substr(2));
    double largest = 0.0;
    for (double v : vb)
      largest = std::isfinite(v) ? std::max(largest, std::abs(v)) : largest;
    for (std::size_t k = 0; k < vb.size(); ++k) {
      if (std::isnan(va[k]) && std::isnan(vb[k])) continue;
      const double sigma = var ? std::sqrt(std::max(0.0, (*var)[k])) : largest;
      const double d = std::abs(va[k] - vb[k]) / (std::abs(vb[k]) + sigma + 1e-300);
      if (!(d <= worst)) {
        worst = std::isnan(d) ? INFINITY : d;
        where = name + " row " + std::to_string(k);
      }
    }
  }
  return worst;
}

TEST(ScaleNative, EveryPresetEqualsTheMuparserRun) {
  if (!compiler_runs()) GTEST_SKIP() << "no C compiler (cc): the native path falls back";
  const auto presets = every_preset();
  ASSERT_GE(presets.size(), 15u);
  std::vector<Dataset> data, oracle;
  std::vector<Workspace> spaces;
  std::vector<std::string> names;
  for (const auto& p : presets) {
    auto ws = open_workspace(p, std::nullopt, {});
    ASSERT_TRUE(ws) << ws.error();
    if (ws->data_path && !fs::exists(*ws->data_path)) continue;  // ../shared absent (a bare clone)
    auto d = load_dataset(*ws);  // simulated by muparser once: both runs filter the same data
    ASSERT_TRUE(d) << p << ": " << d.error();
    auto r = ws->scenario->run(*d, ws->values);
    ASSERT_TRUE(r) << p << ": " << r.error();
    oracle.push_back((*r)->table());
    data.push_back(std::move(*d));
    spaces.push_back(std::move(*ws));
    names.push_back(p);
  }
  NativeOn on;
  ASSERT_GE(spaces.size(), 15u);
  for (std::size_t i = 0; i < spaces.size(); ++i) {
    SCOPED_TRACE(names[i]);
    const auto before = native::stats();
    auto r = spaces[i].scenario->run(data[i], spaces[i].values);
    ASSERT_TRUE(r) << r.error();
    const auto after = native::stats();
    EXPECT_GT(after.groups_native, before.groups_native);
    EXPECT_EQ(after.groups_fallback, before.groups_fallback) << after.last_error;
    std::string where;
    EXPECT_LE(worst_difference((*r)->table(), oracle[i], where), 1e-9) << where;
  }
  // A second run of a model met before loads nothing new.
  const auto before = native::stats();
  ASSERT_TRUE(spaces[0].scenario->run(data[0], spaces[0].values));
  EXPECT_EQ(native::stats().compiles, before.compiles);
}

// The cache folder is private; a model met again in a new process is loaded from it without a
// compile; a shared object whose bytes no longer match the hash recorded when it was built is
// rebuilt, not loaded; without a compiler the run falls back to muparser and still succeeds.
TEST(ScaleNative, TheCacheIsPrivateCheckedAndOptional) {
  if (!compiler_runs()) GTEST_SKIP() << "no C compiler (cc)";
  auto ws = open_workspace(std::string(KFW_SOURCE_DIR) + "/presets/models/van_der_pol.json",
                           std::nullopt, {});
  ASSERT_TRUE(ws) << ws.error();
  auto d = load_dataset(*ws);  // simulated before the native path is on
  ASSERT_TRUE(d) << d.error();
  NativeOn on;
  struct stat st {};
  ASSERT_EQ(::stat(on.dir.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0700u);
  native::forget();
  auto s0 = native::stats();
  ASSERT_TRUE(ws->scenario->run(*d, ws->values));
  auto s1 = native::stats();
  EXPECT_EQ(s1.compiles, s0.compiles + 1);
  native::forget();  // as a new process would
  ASSERT_TRUE(ws->scenario->run(*d, ws->values));
  auto s2 = native::stats();
  EXPECT_EQ(s2.compiles, s1.compiles);
  EXPECT_EQ(s2.cache_loads, s1.cache_loads + 1);
  std::size_t objects = 0;
  for (const auto& e : fs::directory_iterator(on.dir)) {
    if (e.path().extension() != ".so") continue;
    ++objects;
    std::ofstream(e.path(), std::ios::binary | std::ios::app) << "tampered";
  }
  EXPECT_EQ(objects, 1u);
  native::forget();
  ASSERT_TRUE(ws->scenario->run(*d, ws->values));
  EXPECT_EQ(native::stats().compiles, s2.compiles + 1);  // rebuilt
  // No compiler: muparser evaluates, the run is the same.
  ASSERT_TRUE(native::enable({(on.dir / "other").string(), "no-such-compiler-kfw"}).ok());
  native::forget();
  const auto s3 = native::stats();
  auto r = ws->scenario->run(*d, ws->values);
  ASSERT_TRUE(r) << r.error();
  EXPECT_GT(native::stats().groups_fallback, s3.groups_fallback);
  EXPECT_NE(native::stats().last_error.find("no-such-compiler-kfw"), std::string::npos);
}

}  // namespace
}  // namespace scale_native_test
}  // namespace kfw
