// Command line of the GUI executable, shared by app/gui_main.cpp and the tests.
#pragma once

#include <QString>
#include <QStringList>
#include <optional>

#include "core/expected.h"

namespace kfw {

struct AppOptions {
  QString preset;  // path or name; default "helicopter"
  std::optional<QString> data;
  QStringList sets;
  std::optional<QString> export_dir;
  QString formats = "png";
  std::optional<QString> screenshot;
  std::optional<QString> session;  // restore a saved session after the preset  // grab the whole window to this PNG and exit
  bool bench_latency = false;
  int bench_changes = 200;
  bool help = false;
};

inline constexpr const char* kAppUsage =
    "usage: kfw [PRESET] [--data FILE] [--set key=value]... [--session FILE.json]\n"
    "       kfw --export DIR [PRESET] [--data FILE] [--set key=value]... [--format png,pdf,svg]\n"
    "       kfw --screenshot FILE.png [PRESET] [--data FILE] [--set key=value]...\n"
    "       kfw --bench-latency [PRESET] [--data FILE] [--changes N]\n"
    "PRESET is a preset file or a name in presets/ (default: helicopter).\n"
    "--export, --screenshot and --bench-latency need no display (they default QT_QPA_PLATFORM to "
    "offscreen).\n";

Expected<AppOptions> parseAppOptions(const QStringList& args);

}  // namespace kfw
