// kfw: the workbench window, headless export (--export) and GUI latency measurement.
#include <QApplication>
#include <QFont>
#include <QFontDatabase>
#include <QHashFunctions>
#include <QRegularExpression>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

#include <sys/stat.h>
#include <unistd.h>

#include "app_options.h"
#include "core/memory.h"
#include "core/suggest.h"
#include "latency_bench.h"
#include "main_window.h"
#include "native/native_model.h"
#include "plot_export.h"

#ifndef KFW_VERSION
#error "KFW_VERSION comes from CMake's project(VERSION)"
#endif

namespace {

// Without XDG_RUNTIME_DIR (containers, CI, su) Qt warns on stderr before kfw says anything. Give it
// the private directory it would fall back to, /tmp/runtime-UID (mode 0700, owned by the user), so
// kfw's own message is the first line. A directory that is not private is left to Qt to report.
void ensure_runtime_dir() {
  if (!qEnvironmentVariableIsEmpty("XDG_RUNTIME_DIR")) return;
  const std::string dir = "/tmp/runtime-" + std::to_string(::getuid());
  ::mkdir(dir.c_str(), 0700);
  struct stat st {};
  if (::lstat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode) || st.st_uid != ::getuid() ||
      (st.st_mode & 0777) != 0700) {
    return;
  }
  ::setenv("XDG_RUNTIME_DIR", dir.c_str(), 1);
}

// Export, screenshot and list modes promise an empty stderr on success: Qt's platform notices
// (no XDG_RUNTIME_DIR, "This plugin does not support propagateSizeHints()", qt.qpa.*) are
// dropped there. Everything else, and every kfw message, still reaches stderr.
QtMessageHandler g_previous = nullptr;
void quiet_platform_notices(QtMsgType type, const QMessageLogContext& ctx, const QString& msg) {
  const bool notice = type == QtDebugMsg || type == QtInfoMsg || type == QtWarningMsg;
  const QString category = ctx.category ? QString::fromLatin1(ctx.category) : QString();
  if (notice && (category.startsWith("qt.qpa") || msg.contains("propagateSizeHints") ||
                 msg.contains("XDG_RUNTIME_DIR") || msg.startsWith("QStandardPaths:"))) {
    return;
  }
  if (g_previous) {
    g_previous(type, ctx, msg);
  } else {
    std::fprintf(stderr, "%s\n", qPrintable(msg));
  }
}

// The interactive window needs a display; Qt aborts without one (SIGABRT, a core dump). Say so in
// one line first, with the headless ways to run.
bool display_missing() {
  const QByteArray platform = qgetenv("QT_QPA_PLATFORM");
  const bool x11 = qEnvironmentVariableIsEmpty("DISPLAY");
  const bool wayland = qEnvironmentVariableIsEmpty("WAYLAND_DISPLAY");
  if (platform.isEmpty()) return x11 && wayland;
  if (platform.startsWith("xcb")) return x11;
  if (platform.startsWith("wayland")) return wayland;
  return false;  // offscreen, minimal, eglfs, vnc: no display server needed
}

int fail(const kfw::Error& e) {
  std::fprintf(stderr, "kfw: %s\n", kfw::one_line(e.message).c_str());
  return e.exit_code;
}

// The export settings from the options, checked before any work (exit 2).
kfw::Expected<kfw::ExportSpec> export_spec(const kfw::AppOptions& o) {
  if (!o.export_dir) {
    if (!o.plots.isEmpty()) return kfw::Error{"--plot applies to --export (see --list-plots)"};
    if ((o.size && !o.screenshot) || o.dpi || o.font_scale != 1.0) {
      return kfw::Error{
          "--size, --dpi and --font-scale apply to --export (--size also to "
          "--screenshot)"};
    }
    if (o.screenshot) {  // --size is the window's, in px (checked by screenshotSize)
      kfw::ExportSpec spec;
      auto theme = kfw::parseTheme(o.theme);
      if (!theme) return theme.err();
      spec.theme = *theme;
      return spec;
    }
  }
  kfw::ExportSpec spec;
  auto theme = kfw::parseTheme(o.theme);
  if (!theme) return theme.err();
  spec.theme = *theme;
  spec.font_scale = o.font_scale;
  const bool physical = o.size && !o.size->trimmed().toLower().endsWith("px") &&
                        o.size->contains(QRegularExpression("in|mm|column|page"));
  spec.dpi = o.dpi ? *o.dpi : (physical ? 300.0 : kfw::kLayoutDpi);
  if (o.size) {
    if (auto st = kfw::parseSize(*o.size, spec.dpi, spec); !st) return st.err();
  } else {
    spec.width_in = kfw::kExportWidth / spec.dpi;
    spec.height_in = kfw::kExportHeight / spec.dpi;
  }
  return spec;
}

}  // namespace

int main(int argc, char** argv) {
  kfw::retain_freed_memory();
  if (const std::string notice = kfw::native::enable_from_environment(); !notice.empty())
    std::fprintf(stderr, "kfw: notice: %s\n", notice.c_str());
  QStringList raw;
  for (int i = 1; i < argc; ++i)
    raw << QString::fromLocal8Bit(argv[i]);
  auto opt = kfw::parseAppOptions(raw);
  if (!opt) {
    std::fprintf(stderr, "kfw: %s\n", kfw::one_line(opt.error()).c_str());
    return opt.exit_code();
  }
  if (opt->help) {
    std::printf("%s", kfw::appHelp().c_str());
    return 0;
  }
  if (opt->version) {
    std::printf("kfw %s\n", KFW_VERSION);
    return 0;
  }
  auto spec = export_spec(*opt);
  if (!spec) return fail(spec.err());
  const auto shot_size = kfw::screenshotSize(*opt);
  if (opt->screenshot && !shot_size) return fail(shot_size.err());
  std::optional<QStringList> formats;
  if (opt->export_dir) {
    auto f = kfw::parseFormats(opt->formats);
    if (!f) return fail(f.err());
    formats = *f;
  }
  // Export, screenshot and list modes need no display and must not depend on one: offscreen,
  // whatever QT_QPA_PLATFORM was inherited (an inherited xcb without a display aborts).
  const bool offscreen = opt->export_dir || opt->screenshot || opt->list_plots;
  const bool headless = offscreen || opt->bench_latency;
  if (offscreen || (headless && qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM"))) {
    qputenv("QT_QPA_PLATFORM", "offscreen");
  }
  if (!headless && display_missing()) {
    return fail(kfw::Error{
        "no display to open the window on (DISPLAY is not set); run headless with --export DIR "
        "or --screenshot FILE, or set QT_QPA_PLATFORM=offscreen"});
  }
  ensure_runtime_dir();
  if (offscreen) {
    g_previous = qInstallMessageHandler(quiet_platform_notices);
    // Qt's PDF writer emits its fonts in QHash order, which follows a per-process random seed:
    // two processes wrote the same PDF with its objects in another order.
    QHashSeed::setDeterministicGlobalSeed();
  }
  QApplication app(argc, argv);
  QApplication::setApplicationName("kfw");
  QApplication::setApplicationVersion(KFW_VERSION);  // Help → About reads it
  QApplication::setFont(QFont("DejaVu Sans", 9));
  if (opt->screenshot) {  // checked before any work, as every output path is
    if (auto st = kfw::checkScreenshotPath(*opt->screenshot); !st) return fail(st.err());
  }

  kfw::MainWindow w;
  auto loaded = w.loadPreset(opt->preset, opt->data, opt->sets, opt->import);
  if (!loaded && opt->data && !headless && !opt->import.any() &&
      w.loadPreset(opt->preset, std::nullopt, opt->sets)) {
    // --data that the preset's mapping does not read (and no import option says how): the
    // import dialog on the file.
    w.setInteractive(true);
    loaded = w.openDataset(*opt->data);
  }
  if (const auto& st = loaded; !st) {
    std::fprintf(stderr, "kfw: %s\n", kfw::one_line(st.error()).c_str());
    return st.exit_code();
  }
  // A session applies to the headless modes as to the window (its values, data and view).
  if (opt->session && headless) {
    if (auto st = w.loadSession(*opt->session); !st) return fail(st.err());
  }
  // A run that broke down or was refused: the headless modes exit as kfw-cli does for the same
  // input (2 refused, 1 broke down), with its message.
  const auto run_failed = [&w]() -> std::optional<kfw::Error> {
    if (!w.waitForRun()) return kfw::failure("the run did not finish");
    if (const int code = w.lastRunExitCode(); code != 0 || !w.result()) {
      const std::string why =
          w.lastError().isEmpty() ? "the run failed" : w.lastError().toStdString();
      return kfw::Error{why, code != 0 ? code : kfw::kExitFailed};
    }
    return std::nullopt;
  };
  if (opt->list_plots) {
    if (auto e = run_failed()) return fail(*e);
    for (const QString& n : w.plotNames())
      std::printf("%s\n", qPrintable(n));
    return 0;
  }
  if (opt->export_dir) {
    if (auto e = run_failed()) return fail(*e);
    auto files = w.exportAll(*opt->export_dir, *formats, *spec, opt->plots);
    if (!files) return fail(files.err());
    for (const auto& f : *files)
      std::printf("%s\n", qPrintable(f));
    return 0;
  }
  if (spec->theme != kfw::Theme::kLight) w.setTheme(spec->theme);
  if (opt->screenshot) {
    w.setScreenshotMode(true);  // no live timings: two screenshots are identical
    // --size WxH px, else 1600 × 1000; presentation mode at a projector's 1366 × 768 (offscreen
    // it is not full screen).
    w.resize(*shot_size);
    if (opt->present) w.setPresentation(true);
    w.show();
    if (auto e = run_failed()) return fail(*e);
    QApplication::processEvents();
    if (auto st = kfw::saveScreenshot(w.grab().toImage(), *opt->screenshot); !st)
      return fail(st.err());
    std::printf("%s\n", qPrintable(*opt->screenshot));
    return 0;
  }
  if (opt->bench_latency) {
    w.show();
    const auto s = kfw::measureLatency(w, opt->bench_changes);
    std::printf("latency p50 %.1f ms p95 %.1f ms (max %.1f ms, %d changes, %zu steps)\n", s.p50_ms,
                s.p95_ms, s.max_ms, opt->bench_changes, w.result() ? w.result()->steps() : 0);
    std::printf("cpu (all threads) p50 %.1f ms p95 %.1f ms\n", s.cpu_p50_ms, s.cpu_p95_ms);
    std::printf("readout per mouse move p50 %.1f ms p95 %.1f ms\n", s.readout_p50_ms,
                s.readout_p95_ms);
    return 0;
  }
  w.setInteractive(true);  // a CSV with other column names opens the mapping dialog
  if (opt->session) {
    if (auto st = w.loadSession(*opt->session); !st) {
      std::fprintf(stderr, "kfw: %s\n", st.error().c_str());
      return 2;
    }
  }
  w.show();
  if (opt->present) w.setPresentation(true);
  return app.exec();
}
