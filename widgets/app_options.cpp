#include "app_options.h"

#include <CLI/CLI.hpp>
#include <QRegularExpression>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <vector>

#include "core/suggest.h"
#include "document/import_args_cli.h"

namespace kfw {

namespace {

// What CLI11 parses into, before it becomes AppOptions.
struct Parsed {
  std::string preset = "helicopter";
  std::optional<std::string> data, export_dir, screenshot, session, size;
  std::vector<std::string> sets, plots;
  ImportArgs import;
  std::optional<double> dpi;
  double font_scale = 1.0;
  std::string theme = "light";
  bool list_plots = false;
  bool present = false;
  std::string formats = "png";
  bool bench_latency = false;
  int bench_changes = 200;
  bool version = false;
};

struct Declaration {
  CLI::App app{"kfw: the Kalman filter tuning workbench.", "kfw"};
  Parsed p;
};

// NaN and infinities are refused by name: CLI::Range lets NaN through (it compares false).
CLI::Validator finite_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (end == text.c_str() || !std::isfinite(v))
          return "'" + text + "' is not a finite number";
        return {};
      },
      "");
}

void add_path(CLI::App& app, const std::string& name, std::optional<std::string>& dst,
              const std::string& type, const std::string& help) {
  app.add_option_function<std::string>(
         name, [&dst](const std::string& v) { dst = v; }, help)
      ->type_name(type);
}

std::unique_ptr<Declaration> declare() {
  auto d = std::make_unique<Declaration>();
  CLI::App& app = d->app;
  Parsed& p = d->p;
  app.get_formatter()->column_width(30);
  app.set_help_flag("-h,--help", "print this help and exit");
  app.allow_extras();  // unknown options are answered with "did you mean"
  app.add_option("PRESET", p.preset, "a preset file or a name in presets/ (default: helicopter)");
  add_path(app, "--data", p.data, "FILE.csv", "the dataset (CSV); default: the preset's");
  add_import_options(&app, p.import);
  app.add_option("--set", p.sets, "set a parameter (repeatable)")
      ->type_name("KEY=VALUE")
      ->allow_extra_args(false)
      ->take_all();
  add_path(app, "--session", p.session, "FILE.json", "restore a saved session after the preset");
  add_path(app, "--export", p.export_dir, "DIR", "write every plot to DIR and exit");
  app.add_option("--format", p.formats, "the export formats, comma-separated: png,pdf,svg")
      ->type_name("LIST")
      ->capture_default_str();
  add_path(app, "--size", p.size, "WxH",
           "export size: 3.5inx2.5in, 90x60mm, 1200x700 (px), column (3.5x2.5 in) or page "
           "(7x4 in); default 1200x700 px. With --screenshot: the window in px (default "
           "1600x1000; 1366x768 with --present)");
  app.add_option_function<double>(
         "--dpi", [&p](double v) { p.dpi = v; },
         "PNG pixels per inch (default: 300 for a size in in, mm or a named size, else 96)")
      ->type_name("N")
      ->check(finite_number())
      ->check(CLI::Range(24.0, 1200.0).description(""));
  app.add_option("--font-scale", p.font_scale, "every text of an exported plot x this")
      ->type_name("X")
      ->check(finite_number())
      ->check(CLI::Range(0.25, 4.0).description(""))
      ->capture_default_str();
  app.add_option("--plot", p.plots, "export only this plot (repeatable; see --list-plots)")
      ->type_name("NAME")
      ->allow_extra_args(false)
      ->take_all();
  app.add_option("--theme", p.theme, "light or dark: the window and the exports")
      ->type_name("NAME")
      ->capture_default_str();
  app.add_flag("--list-plots", p.list_plots, "print the plot names of PRESET and exit");
  app.add_flag("--present", p.present, "open in presentation mode (full screen, large text)");
  add_path(app, "--screenshot", p.screenshot, "FILE.png", "grab the whole window and exit");
  app.add_flag("--bench-latency", p.bench_latency,
               "measure slider-to-redraw latency and print p50/p95");
  app.add_option("--changes", p.bench_changes, "parameter changes for --bench-latency")
      ->type_name("N")
      ->check(CLI::Range(2, 1000000).description(""))
      ->capture_default_str();
  app.add_flag("--version", p.version, "print the version and exit");
  app.footer(
      "\n--export, --screenshot and --list-plots need no display (they run offscreen whatever\n"
      "QT_QPA_PLATFORM says; --bench-latency defaults to offscreen). Exit codes: 0 done; 2 an\n"
      "argument, preset, data file, plot name or output path is invalid (nothing written);\n"
      "1 the work failed (a failed export writes no file).\n");
  return d;
}

std::vector<std::string> option_names(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::Option* o : app.get_options()) {
    for (const auto& l : o->get_lnames())
      names.push_back("--" + l);
  }
  return names;
}

// An unknown option (with the nearest valid one) or a second preset.
std::optional<Error> check_extras(const CLI::App& app, const std::string& preset) {
  const auto rest = app.remaining(false);
  if (rest.empty()) return std::nullopt;
  const std::string& t = rest.front();
  if (t.size() > 1 && t.front() == '-') {
    return Error{unknown_message("option", t.substr(0, t.find('=')), option_names(app)) +
                 " (try kfw --help)"};
  }
  return Error{"more than one preset given (" + quote_token(preset) + ", " + quote_token(t) + ")"};
}

}  // namespace

std::string appHelp() {
  return declare()->app.help();
}

Expected<AppOptions> parseAppOptions(const QStringList& args) {
  auto d = declare();
  std::vector<std::string> reversed;  // CLI11 takes the arguments last first
  for (auto it = args.rbegin(); it != args.rend(); ++it)
    reversed.push_back(it->toStdString());
  AppOptions o;
  try {
    d->app.parse(reversed);
  } catch (const CLI::CallForHelp&) {
    o.help = true;
    return o;
  } catch (const CLI::ParseError& e) {
    if (auto extra = check_extras(d->app, d->p.preset)) return *extra;
    return Error{one_line(e.what())};
  }
  if (auto extra = check_extras(d->app, d->p.preset)) return *extra;
  const Parsed& p = d->p;
  auto q = [](const std::optional<std::string>& s) -> std::optional<QString> {
    if (!s) return std::nullopt;
    return QString::fromStdString(*s);
  };
  o.preset = QString::fromStdString(p.preset);
  o.data = q(p.data);
  for (const auto& s : p.sets)
    o.sets << QString::fromStdString(s);
  o.import = p.import;
  o.export_dir = q(p.export_dir);
  o.formats = QString::fromStdString(p.formats);
  o.screenshot = q(p.screenshot);
  o.session = q(p.session);
  o.bench_latency = p.bench_latency;
  o.bench_changes = p.bench_changes;
  o.version = p.version;
  o.size = q(p.size);
  o.dpi = p.dpi;
  o.font_scale = p.font_scale;
  for (const auto& s : p.plots)
    o.plots << QString::fromStdString(s);
  o.theme = QString::fromStdString(p.theme);
  o.list_plots = p.list_plots;
  o.present = p.present;
  return o;
}

Expected<QSize> screenshotSize(const AppOptions& o) {
  if (!o.size) return o.present ? QSize(1366, 768) : QSize(1600, 1000);
  static const QRegularExpression re(R"(^([0-9]+)\s*(px)?\s*x\s*([0-9]+)\s*(px)?$)");
  const auto m = re.match(o.size->trimmed().toLower());
  const std::string token = truncate_token(o.size->toStdString());
  if (!m.hasMatch()) {
    return Error{"--size: '" + token + "' is not WxH in pixels (e.g. 1366x768) for --screenshot"};
  }
  const int w = m.captured(1).toInt(), h = m.captured(3).toInt();
  // A window a screen can show: 320 x 240 to 7680 x 4320 (8K).
  if (w < 320 || h < 240 || w > 7680 || h > 4320) {
    return Error{"--size: '" + token + "' is outside 320x240 to 7680x4320 px for --screenshot"};
  }
  return QSize(w, h);
}

}  // namespace kfw
