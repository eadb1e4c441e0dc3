// kfw: the workbench window, headless export (--export) and GUI latency measurement.
#include <QApplication>
#include <QFont>
#include <QFontDatabase>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <sys/stat.h>
#include <unistd.h>

#include "app_options.h"
#include "core/memory.h"
#include "core/suggest.h"
#include "latency_bench.h"
#include "main_window.h"
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

}  // namespace

int main(int argc, char** argv) {
  kfw::retain_freed_memory();
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
  const bool headless = opt->export_dir || opt->bench_latency || opt->screenshot;
  if (headless && qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM")) {
    qputenv("QT_QPA_PLATFORM", "offscreen");
  }
  ensure_runtime_dir();
  QApplication app(argc, argv);
  QApplication::setApplicationName("kfw");
  QApplication::setFont(QFont("DejaVu Sans", 9));

  kfw::MainWindow w;
  auto loaded = w.loadPreset(opt->preset, opt->data, opt->sets);
  if (!loaded && opt->data && !headless && w.loadPreset(opt->preset, std::nullopt, opt->sets)) {
    // --data that the preset's mapping does not read: the import dialog on the file.
    w.setInteractive(true);
    loaded = w.openDataset(*opt->data);
  }
  if (const auto& st = loaded; !st) {
    std::fprintf(stderr, "kfw: %s\n", kfw::one_line(st.error()).c_str());
    return st.exit_code();
  }
  if (opt->export_dir) {
    auto formats = kfw::parseFormats(opt->formats);
    if (!formats) {
      std::fprintf(stderr, "kfw: %s\n", formats.error().c_str());
      return 2;
    }
    auto files = w.exportAll(*opt->export_dir, *formats);
    if (!files) {
      std::fprintf(stderr, "kfw: %s\n", files.error().c_str());
      return 1;
    }
    for (const auto& f : *files)
      std::printf("%s\n", qPrintable(f));
    return 0;
  }
  if (opt->screenshot) {
    w.resize(1600, 1000);
    w.show();
    if (!w.waitForRun()) {
      std::fprintf(stderr, "kfw: the run did not finish\n");
      return 1;
    }
    QApplication::processEvents();
    if (!w.grab().save(*opt->screenshot)) {
      std::fprintf(stderr, "kfw: %s: cannot write the screenshot\n", qPrintable(*opt->screenshot));
      return 1;
    }
    std::printf("%s\n", qPrintable(*opt->screenshot));
    return 0;
  }
  if (opt->bench_latency) {
    w.show();
    const auto s = kfw::measureLatency(w, opt->bench_changes);
    std::printf("latency p50 %.1f ms p95 %.1f ms (max %.1f ms, %d changes, %zu steps)\n", s.p50_ms,
                s.p95_ms, s.max_ms, opt->bench_changes, w.result() ? w.result()->steps() : 0);
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
  return app.exec();
}
