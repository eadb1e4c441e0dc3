// The kfw command line: one CLI11 declaration, "did you mean" for options, --help and --version.
#include "app_options.h"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include "common/cli_runner.h"

#include <array>
#include <cstdio>
#include <string>

namespace {

using Out = kfw::testing::CliOutput;

Out kfw_gui(const std::string& args, const std::string& redirect = "2>&1") {
  return kfw::testing::run_command(std::string(KFW_GUI) + " " + args + " " + redirect);
}

TEST(AppOptions, ParsesEveryOption) {
  auto o =
      kfw::parseAppOptions({"presets/x.json", "--data", "d.csv", "--set", "Q=1", "--set=R=2",
                            "--export", "out", "--format", "png,svg", "--changes", "10",
                            "--bench-latency", "--session", "s.json", "--screenshot", "w.png"});
  ASSERT_TRUE(o.ok()) << o.error();
  EXPECT_EQ(o->preset, "presets/x.json");
  EXPECT_EQ(o->data, QString("d.csv"));
  EXPECT_EQ(o->sets, (QStringList{"Q=1", "R=2"}));
  EXPECT_EQ(o->export_dir, QString("out"));
  EXPECT_EQ(o->formats, "png,svg");
  EXPECT_EQ(o->bench_changes, 10);
  EXPECT_TRUE(o->bench_latency);
  EXPECT_EQ(o->session, QString("s.json"));
  EXPECT_EQ(o->screenshot, QString("w.png"));
  auto d = kfw::parseAppOptions({});
  ASSERT_TRUE(d.ok());
  EXPECT_EQ(d->preset, "helicopter");
  EXPECT_EQ(d->formats, "png");
  EXPECT_FALSE(d->export_dir || d->help || d->version);
}

TEST(AppOptions, ExportOptions) {
  auto o = kfw::parseAppOptions({"cv1d", "--export", "d", "--size", "column", "--dpi", "600",
                                 "--font-scale", "1.5", "--plot", "angle", "--plot=nis", "--theme",
                                 "dark"});
  ASSERT_TRUE(o.ok()) << o.error();
  EXPECT_EQ(o->size, QString("column"));
  EXPECT_EQ(o->dpi, 600.0);
  EXPECT_EQ(o->font_scale, 1.5);
  EXPECT_EQ(o->plots, (QStringList{"angle", "nis"}));
  EXPECT_EQ(o->theme, "dark");
  auto l = kfw::parseAppOptions({"--list-plots", "radome", "--present"});
  ASSERT_TRUE(l.ok()) << l.error();
  EXPECT_TRUE(l->list_plots);
  EXPECT_TRUE(l->present);
  EXPECT_EQ(l->preset, "radome");
  EXPECT_FALSE(kfw::parseAppOptions({"--dpi", "5"}).ok());
  EXPECT_FALSE(kfw::parseAppOptions({"--font-scale", "0"}).ok());
}

TEST(AppOptions, BadArgumentsAreOneLineErrorsWithTheNearestName) {
  auto o = kfw::parseAppOptions({"--exprot", "out"});
  ASSERT_FALSE(o.ok());
  EXPECT_EQ(o.err().exit_code, kfw::kExitInvalid);
  EXPECT_NE(o.error().find("unknown option '--exprot' (did you mean '--export'?)"),
            std::string::npos)
      << o.error();
  EXPECT_NE(kfw::parseAppOptions({"a", "b"}).error().find("more than one preset"),
            std::string::npos);
  EXPECT_NE(kfw::parseAppOptions({"--changes", "1"}).error().find("--changes"), std::string::npos);
  EXPECT_NE(kfw::parseAppOptions({"--data"}).error().find("--data"), std::string::npos);
}

TEST(AppOptions, HelpAndVersion) {
  EXPECT_TRUE(kfw::parseAppOptions({"--help"})->help);
  EXPECT_TRUE(kfw::parseAppOptions({"--version"})->version);
  for (const char* s : {"--export", "--screenshot", "--bench-latency", "--session", "PRESET"})
    EXPECT_NE(kfw::appHelp().find(s), std::string::npos) << s;
  const Out v = kfw_gui("--version");
  EXPECT_EQ(v.code, 0);
  EXPECT_EQ(v.text, std::string("kfw ") + KFW_VERSION + "\n");
  const Out h = kfw_gui("--help", "2>/dev/null");
  EXPECT_EQ(h.code, 0);
  EXPECT_NE(h.text.find("--export"), std::string::npos) << h.text;
  const Out bad = kfw_gui("--exprot out");
  EXPECT_EQ(bad.code, 2);
  EXPECT_EQ(bad.text,
            "kfw: unknown option '--exprot' (did you mean '--export'?) (try kfw --help)\n");
}

}  // namespace
