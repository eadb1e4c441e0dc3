// Command line of the GUI executable, shared by app/gui_main.cpp and the tests. One CLI11
// declaration yields the parsing, the help (appHelp) and the errors ("did you mean").
#pragma once

#include <QSize>
#include <QString>
#include <QStringList>
#include <optional>
#include <string>

#include "core/expected.h"
#include "document/import_args.h"

namespace kfw {

struct AppOptions {
  QString preset;  // path or name; default "helicopter"
  std::optional<QString> data;
  QStringList sets;
  ImportArgs import;  // --map, --time, --unit, --sep, --mapping, … as kfw-cli's
  std::optional<QString> export_dir;
  QString formats = "png";
  std::optional<QString> screenshot;  // grab the whole window to this PNG and exit
  std::optional<QString> session;     // restore a saved session after the preset
  // Exports: --size (see parseSize in plot_export.h), --dpi, --font-scale, --plot (repeatable),
  // --theme; --list-plots prints the plot names of the preset.
  std::optional<QString> size;
  std::optional<double> dpi;
  double font_scale = 1.0;
  QStringList plots;
  QString theme = "light";
  bool list_plots = false;
  bool present = false;  // open in presentation mode
  bool bench_latency = false;
  int bench_changes = 200;
  bool help = false;
  bool version = false;
};

// The help text, generated from the declaration.
std::string appHelp();

// The window size of --screenshot: --size WxH in pixels ("1366x768", "1366x768px"), else
// 1366 x 768 with --present, else 1600 x 1000. A physical or named size is an Error (exit 2).
Expected<QSize> screenshotSize(const AppOptions& o);

// Parses the arguments (without the program name). Bad arguments are an Error (exit 2) of one
// line; --help and --version set their flags.
Expected<AppOptions> parseAppOptions(const QStringList& args);

}  // namespace kfw
