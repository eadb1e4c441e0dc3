// kfw's own message is the first line on stderr: without XDG_RUNTIME_DIR, Qt would print its
// "XDG_RUNTIME_DIR not set" notice first (issue 16); kfw gives it a private directory instead.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "common/cli_runner.h"

namespace {

TEST(RuntimeDir, KfwsMessageIsTheFirstLineWithoutXdgRuntimeDir) {
  const auto dir = std::filesystem::path(::testing::TempDir()) / "kfw_runtime_dir_export";
  std::filesystem::remove_all(dir);
  // stderr only (stdout to /dev/null): a preset that does not exist, after QApplication started.
  auto r = kfw::testing::run_command("env -u XDG_RUNTIME_DIR QT_QPA_PLATFORM=offscreen " +
                                     std::string(KFW_GUI) + " no_such_preset_xyz --export " +
                                     dir.string() + " 2>&1 >/dev/null");
  EXPECT_EQ(r.code, 2) << r.text;
  EXPECT_EQ(r.text.rfind("kfw: ", 0), 0u) << r.text;
  EXPECT_EQ(r.text.find("XDG_RUNTIME_DIR"), std::string::npos) << r.text;
  EXPECT_NE(r.text.find("no_such_preset_xyz"), std::string::npos) << r.text;
}

}  // namespace
