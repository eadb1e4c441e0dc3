#include "app_options.h"

namespace kfw {

Expected<AppOptions> parseAppOptions(const QStringList& args) {
  AppOptions o;
  for (int i = 0; i < args.size(); ++i) {
    const QString& a = args[i];
    auto next = [&](QString& dst) -> bool {
      if (i + 1 >= args.size()) return false;
      dst = args[++i];
      return true;
    };
    QString v;
    if (a == "--help" || a == "-h") {
      o.help = true;
    } else if (a == "--data") {
      if (!next(v)) return Error{"--data needs a file"};
      o.data = v;
    } else if (a == "--set") {
      if (!next(v)) return Error{"--set needs key=value"};
      o.sets << v;
    } else if (a.startsWith("--set=")) {
      o.sets << a.mid(6);
    } else if (a == "--export") {
      if (!next(v)) return Error{"--export needs a directory"};
      o.export_dir = v;
    } else if (a == "--format") {
      if (!next(v)) return Error{"--format needs a list such as png,pdf,svg"};
      o.formats = v;
    } else if (a == "--session") {
      if (!next(v)) return Error{"--session needs a file"};
      o.session = v;
    } else if (a == "--screenshot") {
      if (!next(v)) return Error{"--screenshot needs a file name"};
      o.screenshot = v;
    } else if (a == "--bench-latency") {
      o.bench_latency = true;
    } else if (a == "--changes") {
      if (!next(v)) return Error{"--changes needs a number"};
      bool ok = false;
      o.bench_changes = v.toInt(&ok);
      if (!ok || o.bench_changes < 2)
        return Error{"--changes: '" + v.toStdString() + "' is not a count >= 2"};
    } else if (a.startsWith("-")) {
      return Error{"unknown option " + a.toStdString()};
    } else if (o.preset.isEmpty()) {
      o.preset = a;
    } else {
      return Error{"more than one preset given ('" + o.preset.toStdString() + "', '" +
                   a.toStdString() + "')"};
    }
  }
  if (o.preset.isEmpty()) o.preset = "helicopter";
  return o;
}

}  // namespace kfw
